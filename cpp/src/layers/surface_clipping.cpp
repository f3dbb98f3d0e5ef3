// Clipping layer surfaces to the solid, clean-up and connected components (see
// layer_internal.hpp).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <utility>

#include "layers/layer_internal.hpp"

namespace curvedslicer::layers_detail {
namespace {

std::uint64_t edgeKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

}  // namespace

std::vector<std::uint8_t> markSurfaceCells(const TriMesh& model, const GridGeometry& g) {
  std::vector<std::uint8_t> marks(g.cellCount(), 0);
  const double reach = 0.5 * std::sqrt(3.0) * (1.0 + 1e-9);  // cells: centre to cube corner
  const auto triangles = static_cast<std::ptrdiff_t>(model.triangles.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t t = 0; t < triangles; ++t) {
    const auto tri = static_cast<std::size_t>(t);
    const Vec3 a = g.toCellCoordinates(model.corner(tri, 0));
    const Vec3 b = g.toCellCoordinates(model.corner(tri, 1));
    const Vec3 c = g.toCellCoordinates(model.corner(tri, 2));
    const Vec3 normal = (b - a).cross(c - a);
    const double length = normal.norm();
    if (!(length > 0.0) || !std::isfinite(length)) continue;  // takes no part in queries either
    const Vec3 n = normal / length;
    Vec3i lo, hi;
    bool outside = false;
    for (int k = 0; k < 3; ++k) {
      const double mn = std::min({a[k], b[k], c[k]}), mx = std::max({a[k], b[k], c[k]});
      outside = outside || mx < 0.0 || mn > g.dims[k];
      // A hair of margin: points on a cell face may be assigned to either neighbour.
      lo[k] = static_cast<int>(std::clamp(std::floor(mn - 1e-9), 0.0, g.dims[k] - 1.0));
      hi[k] = static_cast<int>(std::clamp(std::floor(mx + 1e-9), 0.0, g.dims[k] - 1.0));
    }
    if (outside) continue;
    for (int i = lo.x(); i <= hi.x(); ++i) {
      for (int j = lo.y(); j <= hi.y(); ++j) {
        for (int k = lo.z(); k <= hi.z(); ++k) {
          const Vec3 centre(i + 0.5, j + 0.5, k + 0.5);
          if (std::abs(n.dot(centre - a)) > reach) continue;
          std::atomic_ref<std::uint8_t>(marks[g.index(i, j, k)])
              .store(1, std::memory_order_relaxed);
        }
      }
    }
  }
  return marks;
}

TriMesh clipSurfaceToSolid(const TriMesh& surface, const TriangleBvh& model, const VoxelGrid& grid,
                           const std::vector<std::uint8_t>& surfaceCells, ClipStats& stats) {
  const GridGeometry& g = grid.geometry;
  const std::size_t nv = surface.vertices.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> sd(nv, nan);
  std::vector<std::uint8_t> in(nv, 0);
  TriMesh out;
  out.vertices = surface.vertices;

  // Exact signed distance. Vertices within `snap` of the surface count as on it (inside) and move
  // onto it, so that no sliver triangles appear between them and the rim.
  const double snap = kSnapDistance * g.voxelSize;
  // Queries follow the vertex order, which is spatially coherent: the previous answer is a good
  // starting bound when it is near; otherwise the model's own search tree picks the start.
  ClosestPoint hint;
  const double hintReach2 = 4.0 * g.voxelSize * g.voxelSize;
  auto hintFor = [&](const Vec3& p) {
    return (p - hint.point).squaredNorm() <= hintReach2 ? hint : ClosestPoint{};
  };
  auto computeExact = [&](std::size_t v) {
    ClosestPoint closest;
    sd[v] = model.signedDistance(surface.vertices[v], hintFor(surface.vertices[v]), &closest);
    hint = closest;
    ++stats.exactQueries;
    if (std::abs(sd[v]) <= snap) {
      sd[v] = 0.0;
      out.vertices[v] = closest.point;
    }
  };

  // Side of every vertex. If no model triangle meets the cube of the cell containing the vertex,
  // the segment from the vertex to the cell centre does not cross the surface: read the side from
  // the voxel mask. Otherwise compute the signed distance.
  for (std::size_t v = 0; v < nv; ++v) {
    const Vec3i c = g.cellOf(surface.vertices[v]);
    if (g.contains(c) && surfaceCells[g.index(c)] == 0) {
      in[v] = grid.inside[g.index(c)] != 0 ? 1 : 0;
    } else {
      computeExact(v);
      in[v] = sd[v] <= 0.0 ? 1 : 0;
    }
  }
  // Crossing triangles need exact distances at all their corners.
  for (const Vec3i& t : surface.triangles) {
    const int inside = in[t[0]] + in[t[1]] + in[t[2]];
    if (inside == 0 || inside == 3) continue;
    for (int k = 0; k < 3; ++k) {
      if (std::isnan(sd[t[k]])) computeExact(static_cast<std::size_t>(t[k]));
    }
  }

  out.triangles.reserve(surface.triangles.size());
  std::unordered_map<std::uint64_t, int> rim;
  // Vertex where the edge from inside vertex a to outside vertex b crosses the model surface.
  auto crossing = [&](int a, int b) -> int {
    if (sd[a] == 0.0) return a;
    const auto [it, inserted] = rim.try_emplace(edgeKey(a, b), 0);
    if (!inserted) return it->second;
    const double denom = sd[b] - sd[a];
    const double s = denom > 0.0 ? std::clamp(-sd[a] / denom, 0.0, 1.0) : 0.5;
    const Vec3& pa = surface.vertices[a];
    const Vec3 x = pa + s * (surface.vertices[b] - pa);
    it->second = static_cast<int>(out.vertices.size());
    hint = model.closestPoint(x, hintFor(x));
    out.vertices.push_back(hint.point);
    ++stats.rimVertices;
    return it->second;
  };
  for (const Vec3i& t : surface.triangles) {
    const int inside = in[t[0]] + in[t[1]] + in[t[2]];
    if (inside == 3) {
      out.triangles.push_back(t);
    } else if (inside == 1) {
      int k = 0;
      while (!in[t[k]]) ++k;
      const int a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
      out.triangles.emplace_back(a, crossing(a, b), crossing(a, c));
    } else if (inside == 2) {
      int k = 0;
      while (in[t[k]]) ++k;
      const int c = t[k], a = t[(k + 1) % 3], b = t[(k + 2) % 3];
      const int xbc = crossing(b, c), xac = crossing(a, c);
      out.triangles.emplace_back(a, b, xbc);
      out.triangles.emplace_back(a, xbc, xac);
    }
  }
  removeDegenerateAndUnused(out);
  return out;
}

void removeDegenerateAndUnused(TriMesh& mesh) {
  std::vector<Vec3i> kept;
  kept.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3i& tri = mesh.triangles[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) continue;
    if (!(mesh.areaNormal(t).squaredNorm() > 0.0)) continue;
    kept.push_back(tri);
  }
  std::vector<int> newIndex(mesh.vertices.size(), -1);
  for (const Vec3i& t : kept)
    for (int k = 0; k < 3; ++k) newIndex[t[k]] = 0;
  std::vector<Vec3> vertices;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (newIndex[v] < 0) continue;
    newIndex[v] = static_cast<int>(vertices.size());
    vertices.push_back(mesh.vertices[v]);
  }
  for (Vec3i& t : kept) t = Vec3i(newIndex[t[0]], newIndex[t[1]], newIndex[t[2]]);
  mesh.vertices = std::move(vertices);
  mesh.triangles = std::move(kept);
  mesh.faceIds.clear();
}

std::size_t countEdgeComponents(const TriMesh& mesh) {
  const std::size_t nt = mesh.triangles.size(), nv = mesh.vertices.size();
  // Vertex -> incident triangles (compressed rows).
  std::vector<std::size_t> start(nv + 1, 0), incident(3 * nt);
  for (const Vec3i& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++start[static_cast<std::size_t>(t[k]) + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) incident[fill[mesh.triangles[t][k]]++] = t;

  std::vector<std::size_t> parent(nt);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  for (std::size_t t = 0; t < nt; ++t) {
    const Vec3i& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      // Other triangles around vertex a that also use vertex b share the edge ab.
      for (std::size_t q = start[a]; q < start[a + 1]; ++q) {
        const std::size_t u = incident[q];
        if (u == t) continue;
        const Vec3i& other = mesh.triangles[u];
        if (other[0] != b && other[1] != b && other[2] != b) continue;
        const std::size_t ra = find(t), rb = find(u);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
      }
    }
  }
  std::size_t components = 0;
  for (std::size_t t = 0; t < nt; ++t) components += find(t) == t ? 1 : 0;
  return components;
}

}  // namespace curvedslicer::layers_detail
