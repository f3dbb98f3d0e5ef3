// cleanMesh: weld (spatial hash, first representative wins), then drop degenerate and duplicated
// triangles, then compact the vertex list.
#include "curvedslicer/mesh/mesh_repair.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <unordered_map>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "mesh/mesh_checks.hpp"

namespace curvedslicer {

namespace {

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey&) const = default;
};

struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

}  // namespace

std::vector<int> findExactDuplicateVertices(const std::vector<Vec3>& vertices) {
  std::vector<int> order(vertices.size());
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    const Vec3& p = vertices[a];
    const Vec3& q = vertices[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<int> rep(vertices.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const bool sameAsPrevious = k > 0 && vertices[order[k]] == vertices[order[k - 1]];
    rep[order[k]] = sameAsPrevious ? rep[order[k - 1]] : order[k];
  }
  return rep;
}

namespace {

/// Representative of each vertex with tolerance `tol` > 0. Vertices are visited in index order;
/// each joins the lowest-index representative within `tol` or becomes a representative itself,
/// so every vertex ends within `tol` of its representative (no chains).
std::vector<int> weldWithTolerance(const std::vector<Vec3>& vertices, const Vec3& origin,
                                   double tol, double cellSize) {
  // With cells at least 2·tol wide, the ball of radius tol touches at most 2 cells per axis.
  std::unordered_map<CellKey, int, CellKeyHash> head;  // cell -> first representative in list
  head.reserve(vertices.size());
  std::vector<int> next(vertices.size(), -1);  // linked list of representatives per cell
  std::vector<int> rep(vertices.size());
  const double tol2 = tol * tol;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Vec3 local = (vertices[i] - origin) / cellSize;
    std::array<std::int64_t, 3> cell{};
    std::array<std::array<std::int64_t, 2>, 3> range{};
    for (int a = 0; a < 3; ++a) {
      const double f = std::floor(local[a]);
      cell[a] = static_cast<std::int64_t>(f);
      const double offset = (local[a] - f) * cellSize;  // mm from the cell's lower face
      range[a][0] = offset < tol ? cell[a] - 1 : cell[a];
      range[a][1] = offset > cellSize - tol ? cell[a] + 1 : cell[a];
    }
    int best = -1;
    for (std::int64_t x = range[0][0]; x <= range[0][1]; ++x) {
      for (std::int64_t y = range[1][0]; y <= range[1][1]; ++y) {
        for (std::int64_t z = range[2][0]; z <= range[2][1]; ++z) {
          auto it = head.find({x, y, z});
          if (it == head.end()) continue;
          for (int j = it->second; j >= 0; j = next[j]) {
            if ((best < 0 || j < best) && (vertices[j] - vertices[i]).squaredNorm() <= tol2) {
              best = j;
            }
          }
        }
      }
    }
    if (best >= 0) {
      rep[i] = best;
      continue;
    }
    rep[i] = static_cast<int>(i);
    auto [it, inserted] = head.try_emplace({cell[0], cell[1], cell[2]}, static_cast<int>(i));
    if (!inserted) {
      next[i] = it->second;
      it->second = static_cast<int>(i);
    }
  }
  return rep;
}

/// (smallest index, next, last) of the triangle's cyclic order plus its orientation bit: two
/// triangles over the same vertices have the same orientation iff their bits agree.
struct TriangleKey {
  std::array<int, 3> sorted;
  bool flipped;
};

TriangleKey keyOf(const Vec3i& t) {
  int r = 0;
  if (t[1] < t[r]) r = 1;
  if (t[2] < t[r]) r = 2;
  const int a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3];
  return {{a, std::min(b, c), std::max(b, c)}, b > c};
}

}  // namespace

CleanResult cleanMesh(const TriMesh& mesh, const CleanOptions& options) {
  if (!std::isfinite(options.relativeWeldTolerance) || options.relativeWeldTolerance < 0) {
    throw InvalidInput("relative weld tolerance must be finite and >= 0: " +
                       std::to_string(options.relativeWeldTolerance) + "; use e.g. 1e-6");
  }
  detail::requireValidMesh(mesh, "cleanMesh");
  CleanResult result;
  const std::size_t nv = mesh.vertices.size();
  const Aabb box = mesh.bounds();
  const double diag = box.diagonal();
  result.weldTolerance = options.relativeWeldTolerance * diag;

  // ---- weld ---------------------------------------------------------------------------------
  std::vector<int> rep;
  if (result.weldTolerance > 0) {
    // Cell size floor keeps cell coordinates well inside int64 for tiny tolerances.
    const double cellSize = std::max(2.0 * result.weldTolerance, 1e-12 * diag);
    rep = weldWithTolerance(mesh.vertices, box.min, result.weldTolerance, cellSize);
  } else {
    rep = findExactDuplicateVertices(mesh.vertices);
  }
  for (std::size_t i = 0; i < nv; ++i) result.mergedVertices += rep[i] != static_cast<int>(i);

  // ---- degenerate triangles -------------------------------------------------------------------
  const double minArea = detail::degenerateAreaThreshold(diag);
  std::vector<Vec3i> welded;
  std::vector<std::size_t> source;  // input triangle of each kept triangle
  welded.reserve(mesh.triangles.size());
  source.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3i& in = mesh.triangles[t];
    const Vec3i tri(rep[in[0]], rep[in[1]], rep[in[2]]);
    if (options.removeDegenerate) {
      const bool repeated = tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0];
      const Vec3& a = mesh.vertices[tri[0]];
      if (repeated ||
          0.5 * (mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a).norm() < minArea) {
        ++result.degenerateTriangles;
        continue;
      }
    }
    welded.push_back(tri);
    source.push_back(t);
  }

  // ---- duplicated triangles -------------------------------------------------------------------
  std::vector<bool> keep(welded.size(), true);
  if (options.removeDuplicates) {
    std::vector<std::pair<TriangleKey, int>> keys(welded.size());
    for (std::size_t k = 0; k < welded.size(); ++k) {
      keys[k] = {keyOf(welded[k]), static_cast<int>(k)};
    }
    std::sort(keys.begin(), keys.end(), [](const auto& p, const auto& q) {
      if (p.first.sorted != q.first.sorted) return p.first.sorted < q.first.sorted;
      return p.second < q.second;
    });
    for (std::size_t k = 1, first = 0; k < keys.size(); ++k) {
      if (keys[k].first.sorted != keys[first].first.sorted) {
        first = k;
        continue;
      }
      keep[keys[k].second] = false;
      if (keys[k].first.flipped == keys[first].first.flipped) {
        ++result.duplicateTriangles;
      } else {
        ++result.oppositeDuplicateTriangles;
      }
    }
  }

  // ---- compact ----------------------------------------------------------------------------------
  const bool ids = mesh.faceIds.size() == mesh.triangles.size() && !mesh.faceIds.empty();
  std::vector<int> newIndex(nv, -1);
  for (std::size_t k = 0; k < welded.size(); ++k) {
    if (!keep[k]) continue;
    for (int c = 0; c < 3; ++c) newIndex[welded[k][c]] = 0;  // mark used
  }
  TriMesh& out = result.mesh;
  for (std::size_t i = 0; i < nv; ++i) {
    if (newIndex[i] < 0) continue;
    newIndex[i] = static_cast<int>(out.vertices.size());
    out.vertices.push_back(mesh.vertices[i]);
  }
  for (std::size_t k = 0; k < welded.size(); ++k) {
    if (!keep[k]) continue;
    out.triangles.emplace_back(newIndex[welded[k][0]], newIndex[welded[k][1]],
                               newIndex[welded[k][2]]);
    if (ids) out.faceIds.push_back(mesh.faceIds[source[k]]);
  }
  return result;
}

}  // namespace curvedslicer
