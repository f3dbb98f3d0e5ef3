// Boundary loops and sections (see curvedslicer/paths/surface_curves.hpp).
#include "curvedslicer/paths/surface_curves.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "paths/paths_internal.hpp"

namespace curvedslicer {

using paths_detail::edgeKey;

std::vector<Polyline> extractBoundaryLoops(const TriMesh& mesh) {
  return findBoundary(mesh).loops;
}

namespace {

/// The undirected edges (edgeKey) used by exactly one triangle, sorted.
std::vector<std::uint64_t> findSingleUseEdges(const TriMesh& mesh) {
  std::vector<std::uint64_t> keys;
  keys.reserve(mesh.triangleCount() * 3);
  for (const Vec3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) keys.push_back(edgeKey(t[k], t[(k + 1) % 3]));
  }
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint64_t> once;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    if (j - i == 1) once.push_back(keys[i]);
    i = j;
  }
  return once;
}

}  // namespace

SurfaceBoundary findBoundary(const TriMesh& mesh) {
  SurfaceBoundary boundary;
  // Boundary edges are used by one triangle, directed as in it.
  const std::vector<std::uint64_t> once = findSingleUseEdges(mesh);
  // Directed boundary edges from -> to, kept in a deterministic order.
  std::multimap<std::int32_t, std::int32_t> next;
  for (const Vec3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = t[k], b = t[(k + 1) % 3];
      if (!std::binary_search(once.begin(), once.end(), edgeKey(a, b))) continue;
      boundary.vertices.push_back(a);
      boundary.vertices.push_back(b);
      if (a != b) next.emplace(a, b);
    }
  }
  std::sort(boundary.vertices.begin(), boundary.vertices.end());
  boundary.vertices.erase(std::unique(boundary.vertices.begin(), boundary.vertices.end()),
                          boundary.vertices.end());
  std::map<std::int32_t, int> inDegree;
  for (const auto& [a, b] : next) ++inDegree[b];

  struct Loop {
    Polyline line;
    std::int32_t smallest;
  };
  std::vector<Loop> loops;
  auto walk = [&](std::int32_t startVertex) {
    Loop loop;
    loop.smallest = startVertex;
    std::int32_t v = startVertex;
    std::vector<std::int32_t> chain{v};
    for (;;) {
      auto it = next.find(v);
      if (it == next.end()) break;
      const std::int32_t w = it->second;
      next.erase(it);
      if (w == startVertex) {
        loop.line.closed = true;
        break;
      }
      chain.push_back(w);
      v = w;
    }
    for (const std::int32_t c : chain) {
      loop.smallest = std::min(loop.smallest, c);
      loop.line.points.push_back(mesh.vertices[c]);
    }
    if (loop.line.closed && loop.line.points.size() < 3) loop.line.closed = false;
    if (loop.line.points.size() >= 2) loops.push_back(std::move(loop));
  };
  // Open chains first start where no boundary edge comes in; then the closed loops.
  std::vector<std::int32_t> starts;
  for (const auto& [a, b] : next) {
    if (inDegree[a] == 0) starts.push_back(a);
  }
  for (const std::int32_t s : starts) {
    while (next.count(s) != 0) walk(s);
  }
  while (!next.empty()) walk(next.begin()->first);

  std::stable_sort(loops.begin(), loops.end(), [](const Loop& x, const Loop& y) {
    const double lx = x.line.length(), ly = y.line.length();
    if (lx != ly) return lx > ly;
    return x.smallest < y.smallest;
  });
  boundary.loops.reserve(loops.size());
  for (Loop& l : loops) boundary.loops.push_back(std::move(l.line));
  return boundary;
}

std::vector<Polyline> computePlaneSection(const TriMesh& mesh, const Vec3& point,
                                          const Vec3& normal) {
  const double n = normal.norm();
  if (!(n > 0.0) || !std::isfinite(n) || !point.allFinite()) {
    throw InvalidInput("section plane normal is zero or not finite: |n| = " + std::to_string(n) +
                       "; pass a non-zero normal and a finite point");
  }
  const Vec3 unit = normal / n;
  std::vector<double> f(mesh.vertexCount());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) f[v] = unit.dot(mesh.vertices[v] - point);
  // Place the crossing on the exact plane (the linear interpolation already is, up to rounding).
  return paths_detail::traceLevelSet(mesh, f, 0.0,
                                     [&](std::int32_t a, std::int32_t b, double t) -> Vec3 {
                                       const Vec3& pa = mesh.vertices[a];
                                       const Vec3& pb = mesh.vertices[b];
                                       const Vec3 p = pa + t * (pb - pa);
                                       return p - unit.dot(p - point) * unit;
                                     });
}

std::vector<Polyline> computeSurfaceSection(const TriMesh& mesh, const TriMesh& userSurface) {
  if (userSurface.empty()) {
    throw InvalidInput(
        "user surface for the initial curve is empty: 0 triangles; pass a surface "
        "that crosses the layer");
  }
  const TriangleBvh bvh(userSurface);
  // Signed distance with the sign of the nearest feature's pseudo-normal (locally meaningful for
  // an open surface, which is all a section needs).
  auto signedDistance = [&](const Vec3& p) { return bvh.signedDistance(p); };
  std::vector<double> f(mesh.vertexCount());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) f[v] = signedDistance(mesh.vertices[v]);
  return paths_detail::traceLevelSet(mesh, f, 0.0,
                                     [&](std::int32_t a, std::int32_t b, double t) -> Vec3 {
                                       // Bisection on the exact signed distance along the edge,
                                       // started from the bracket.
                                       const Vec3& pa = mesh.vertices[a];
                                       const Vec3& pb = mesh.vertices[b];
                                       double lo = 0.0, hi = 1.0;
                                       const bool aboveAtLo = f[a] >= 0.0;
                                       double mid = t;
                                       for (int i = 0; i < 40; ++i) {
                                         const double value = signedDistance(pa + mid * (pb - pa));
                                         if ((value >= 0.0) == aboveAtLo) {
                                           lo = mid;
                                         } else {
                                           hi = mid;
                                         }
                                         if (hi - lo < 1e-9) break;
                                         mid = 0.5 * (lo + hi);
                                       }
                                       return Vec3(pa + 0.5 * (lo + hi) * (pb - pa));
                                     });
}

}  // namespace curvedslicer
