#include "curvedslicer/pipeline/hole_capping.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"

namespace curvedslicer {

namespace {

std::uint64_t edgeKey(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b));
  const auto hi = static_cast<std::uint32_t>(std::max(a, b));
  return (std::uint64_t{lo} << 32) | hi;
}

/// Boundary loops as vertex cycles v0, v1, … such that the mesh has the half-edges v_i → v_{i+1}.
struct BoundaryLoops {
  std::vector<std::vector<int>> loops;
  std::size_t boundaryEdges = 0;
};

BoundaryLoops findBoundaryLoops(const TriMesh& mesh) {
  std::unordered_map<std::uint64_t, int> uses;
  uses.reserve(mesh.triangleCount() * 2);
  for (const Vec3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++uses[edgeKey(t[k], t[(k + 1) % 3])];
  }
  // Outgoing boundary half-edges per vertex, in triangle order (deterministic).
  std::vector<std::pair<int, int>> halfEdges;
  std::unordered_map<int, std::vector<int>> outgoing;
  for (const Vec3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (uses[edgeKey(a, b)] == 1) {
        halfEdges.emplace_back(a, b);
        outgoing[a].push_back(b);
      }
    }
  }
  BoundaryLoops result;
  result.boundaryEdges = halfEdges.size();
  std::unordered_map<int, bool> visited;
  for (const auto& [start, first] : halfEdges) {
    if (visited[start] || outgoing[start].size() != 1) continue;
    std::vector<int> loop{start};
    visited[start] = true;
    int current = first;
    bool closed = false;
    while (true) {
      if (current == start) {
        closed = true;
        break;
      }
      const auto it = outgoing.find(current);
      if (it == outgoing.end() || it->second.size() != 1 || visited[current]) break;
      visited[current] = true;
      loop.push_back(current);
      current = it->second.front();
    }
    if (closed && loop.size() >= 3) result.loops.push_back(std::move(loop));
  }
  return result;
}

/// Projects `p` onto the start surface along ±normal (nearest hit), else to the closest point.
Vec3 projectOntoSurface(const TriangleBvh& bvh, const Vec3& p, const Vec3& normal) {
  const std::optional<RayHit> up = bvh.firstRayHit(p, normal);
  const std::optional<RayHit> down = bvh.firstRayHit(p, -normal);
  if (up && (!down || up->t <= down->t)) return up->point;
  if (down) return down->point;
  return bvh.closestPoint(p).point;
}

}  // namespace

HoleCappingResult capHoles(const TriMesh& mesh, const TriMesh& startSurface,
                           const HoleCappingOptions& options) {
  if (!std::isfinite(options.ringSpacing) || options.ringSpacing <= 0.0) {
    throw InvalidInput("cap ring spacing must be a positive length: " +
                       std::to_string(options.ringSpacing) + " mm; pass e.g. the voxel size");
  }
  if (!std::isfinite(options.onSurfaceTolerance) || options.onSurfaceTolerance < 0.0) {
    throw InvalidInput("on-surface tolerance must be a non-negative length: " +
                       std::to_string(options.onSurfaceTolerance) + " mm; pass e.g. L/4");
  }
  HoleCappingResult result;
  result.mesh = mesh;
  TriMesh& out = result.mesh;
  const bool withIds = mesh.faceIds.size() == mesh.triangles.size() && !mesh.faceIds.empty();

  const BoundaryLoops boundary = findBoundaryLoops(mesh);
  result.loops = boundary.loops.size();
  std::size_t cappedEdges = 0;
  const TriangleBvh bvh = startSurface.empty() ? TriangleBvh() : TriangleBvh(startSurface);

  for (const std::vector<int>& loop : boundary.loops) {
    const std::size_t n = loop.size();
    Vec3 centroid = Vec3::Zero();
    for (int v : loop) centroid += mesh.vertices[v];
    centroid /= static_cast<double>(n);
    // Newell normal of the loop polygon.
    Vec3 normal = Vec3::Zero();
    double radius = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 a = mesh.vertices[loop[i]] - centroid;
      const Vec3 b = mesh.vertices[loop[(i + 1) % n]] - centroid;
      normal += a.cross(b);
      radius = std::max(radius, a.norm());
    }
    normal = normal.norm() > 0.0 ? Vec3(normal.normalized()) : Vec3(Vec3::UnitZ());

    bool onSurface = !bvh.empty();
    for (std::size_t i = 0; onSurface && i < n; ++i) {
      onSurface = bvh.distance(mesh.vertices[loop[i]]) <= options.onSurfaceTolerance;
    }
    const int rings = onSurface
                          ? std::clamp(static_cast<int>(std::ceil(radius / options.ringSpacing)), 1,
                                       std::max(1, options.maxRings))
                          : 1;

    // ring[rings] is the loop itself; ring[k] for 0 < k < rings scaled towards the centroid.
    std::vector<std::vector<int>> ring(rings + 1);
    ring[rings] = loop;
    for (int k = rings - 1; k >= 1; --k) {
      const double s = static_cast<double>(k) / rings;
      ring[k].resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        Vec3 p = centroid + s * (mesh.vertices[loop[i]] - centroid);
        if (onSurface) p = projectOntoSurface(bvh, p, normal);
        ring[k][i] = static_cast<int>(out.vertices.size());
        out.vertices.push_back(p);
      }
    }
    const int centre = static_cast<int>(out.vertices.size());
    out.vertices.push_back(onSurface ? projectOntoSurface(bvh, centroid, normal) : centroid);

    const std::size_t before = out.triangles.size();
    // The model has half-edges o_i → o_{i+1} along the outer ring; the cap runs them backwards.
    for (int k = rings; k >= 2; --k) {
      const std::vector<int>& outer = ring[k];
      const std::vector<int>& inner = ring[k - 1];
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        out.triangles.emplace_back(outer[j], outer[i], inner[i]);
        out.triangles.emplace_back(outer[j], inner[i], inner[j]);
      }
    }
    const std::vector<int>& innermost = ring[1];
    for (std::size_t i = 0; i < n; ++i) {
      out.triangles.emplace_back(innermost[(i + 1) % n], innermost[i], centre);
    }
    const std::size_t added = out.triangles.size() - before;
    if (withIds) out.faceIds.insert(out.faceIds.end(), added, -1);
    result.capTriangles += added;
    ++result.cappedLoops;
    if (onSurface) ++result.loopsOnStartSurface;
    cappedEdges += n;
  }
  result.openBoundaryEdges = boundary.boundaryEdges - cappedEdges;
  return result;
}

}  // namespace curvedslicer
