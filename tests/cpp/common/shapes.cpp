// Analytic test solids. Every generator builds its vertices through integer keys (so shared
// vertices are created exactly once, no tolerance welding) and orients its triangles
// counter-clockwise seen from outside.
#include "common/shapes.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include <unistd.h>

namespace curvedslicer::testing {

namespace {

using Key = std::array<int, 4>;

/// Collects vertices by integer key; a key's position is computed once, on first use.
class MeshBuilder {
 public:
  template <typename PositionFn>
  int vertex(const Key& key, PositionFn&& position) {
    auto [it, inserted] = index_.try_emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(position());
    return it->second;
  }
  int addVertex(const Vec3& p) {
    mesh_.vertices.push_back(p);
    return static_cast<int>(mesh_.vertices.size()) - 1;
  }
  void triangle(int a, int b, int c, int faceId = 0) {
    mesh_.triangles.emplace_back(a, b, c);
    mesh_.faceIds.push_back(faceId);
  }
  /// Quad a-b-c-d (counter-clockwise from outside) as two triangles.
  void quad(int a, int b, int c, int d, int faceId = 0) {
    triangle(a, b, c, faceId);
    triangle(a, c, d, faceId);
  }
  TriMesh take() { return std::move(mesh_); }

 private:
  TriMesh mesh_;
  std::map<Key, int> index_;
};

void requireThat(bool condition, const char* message) {
  if (!condition) throw std::invalid_argument(message);
}

/// Regular `segments`-gon corner k (k taken modulo segments) on the circle of `radius` at z.
Vec3 polygonCorner(const Vec3& c, double radius, int segments, int k, double z) {
  const int kk = ((k % segments) + segments) % segments;
  const double a = 2.0 * std::numbers::pi * kk / segments;
  return {c.x() + radius * std::cos(a), c.y() + radius * std::sin(a), z};
}

/// Extrudes a counter-clockwise polygon (xy) over z ∈ [0, height]. `capTriangles` triangulate
/// the polygon (counter-clockwise, indices into `polygon`); `edgeIds[i]` is the face id of the
/// side face over edge i → i+1. Cap triangles get id 0.
TriMesh extrudePolygon(const std::vector<Eigen::Vector2d>& polygon,
                       const std::vector<Vec3i>& capTriangles, const std::vector<int>& edgeIds,
                       double height) {
  MeshBuilder b;
  const int n = static_cast<int>(polygon.size());
  std::vector<int> bottom(n), top(n);
  for (int i = 0; i < n; ++i) bottom[i] = b.addVertex({polygon[i].x(), polygon[i].y(), 0.0});
  for (int i = 0; i < n; ++i) top[i] = b.addVertex({polygon[i].x(), polygon[i].y(), height});
  for (const Vec3i& t : capTriangles) {
    b.triangle(top[t[0]], top[t[1]], top[t[2]]);
    b.triangle(bottom[t[0]], bottom[t[2]], bottom[t[1]]);
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    b.quad(bottom[i], bottom[j], top[j], top[i], edgeIds[i]);
  }
  return b.take();
}

/// A refined regular prism: caps are `segments` sectors each split into m² triangles, each side
/// quad into m columns × rows. With m = 1 the caps are fans around a centre vertex.
TriMesh makeRefinedPrism(const Vec3& c, double radius, double height, int segments, int m,
                         int rows) {
  MeshBuilder b;
  const int n = segments;
  // Cap point of level L (0 bottom, 1 top) in sector k at barycentric (i, j) / m from the
  // centre towards corners k and k+1.
  auto capPoint = [&](int level, int k, int i, int j) {
    k = ((k % n) + n) % n;
    if (i == 0 && j == 0) {
      return b.vertex({0, level, 0, 0}, [&] { return Vec3(c.x(), c.y(), c.z() + level * height); });
    }
    if (i == 0) {  // on the spoke towards corner k+1
      k = (k + 1) % n;
      i = j;
      j = 0;
    }
    const double z = c.z() + level * height;
    if (j == 0) {  // on the spoke towards corner k
      return b.vertex({1, level, k, i}, [&] {
        const Vec3 a = polygonCorner(c, radius, n, k, z);
        const Vec3 o(c.x(), c.y(), z);
        return Vec3(o + (double(i) / m) * (a - o));
      });
    }
    return b.vertex({2, level * n + k, i, j}, [&] {
      const Vec3 o(c.x(), c.y(), z);
      const Vec3 a = polygonCorner(c, radius, n, k, z);
      const Vec3 bb = polygonCorner(c, radius, n, k + 1, z);
      return Vec3(o + (double(i) / m) * (a - o) + (double(j) / m) * (bb - o));
    });
  };
  // Side point at row r (0..rows) on edge k, column j (0..m) from corner k towards k+1.
  auto sidePoint = [&](int r, int k, int j) {
    k = ((k % n) + n) % n;
    if (r == 0 || r == rows) return capPoint(r == 0 ? 0 : 1, k, m - j, j);
    if (j == m) {
      k = (k + 1) % n;
      j = 0;
    }
    return b.vertex({3, r, k, j}, [&] {
      const double z = c.z() + height * r / rows;
      const Vec3 a = polygonCorner(c, radius, n, k, z);
      const Vec3 bb = polygonCorner(c, radius, n, k + 1, z);
      return Vec3(a + (double(j) / m) * (bb - a));
    });
  };
  for (int k = 0; k < n; ++k) {
    // Caps: triangles of the barycentric grid; top counter-clockwise from +z, bottom reversed.
    for (int i = 0; i < m; ++i) {
      for (int j = 0; i + j < m; ++j) {
        for (int level = 0; level < 2; ++level) {
          const int p0 = capPoint(level, k, i, j), p1 = capPoint(level, k, i + 1, j),
                    p2 = capPoint(level, k, i, j + 1);
          if (level == 1)
            b.triangle(p0, p1, p2);
          else
            b.triangle(p0, p2, p1);
          if (i + j + 2 <= m) {
            const int p3 = capPoint(level, k, i + 1, j + 1);
            if (level == 1)
              b.triangle(p1, p3, p2);
            else
              b.triangle(p1, p2, p3);
          }
        }
      }
    }
    for (int r = 0; r < rows; ++r) {
      for (int j = 0; j < m; ++j) {
        b.quad(sidePoint(r, k, j), sidePoint(r, k, j + 1), sidePoint(r + 1, k, j + 1),
               sidePoint(r + 1, k, j));
      }
    }
  }
  return b.take();
}

/// A binary STL writer independent of mesh_io (so reader tests do not only check the library
/// against itself). Little-endian host assumed (x86-64, aarch64).
void writeBinaryStl(const std::filesystem::path& path, const TriMesh& mesh) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("writeTempStl: cannot create " + path.string());
  char header[80] = {};
  std::memcpy(header, "binary STL written by curvedslicer tests", 41);
  out.write(header, sizeof header);
  const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    float record[12];
    Vec3 nrm = mesh.areaNormal(t);
    if (nrm.norm() > 0) nrm.normalize();
    for (int a = 0; a < 3; ++a) record[a] = static_cast<float>(nrm[a]);
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) record[3 + 3 * k + a] = static_cast<float>(mesh.corner(t, k)[a]);
    }
    const std::uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(record), sizeof record);
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
  out.close();
  if (!out) throw std::runtime_error("writeTempStl: writing " + path.string() + " failed");
}

}  // namespace

TriMesh makeBox(const Vec3& min, const Vec3& max) {
  return makeSubdividedBox(min, max, 1);
}

TriMesh makeSubdividedBox(const Vec3& min, const Vec3& max, int n) {
  requireThat(n >= 1, "makeSubdividedBox: n must be >= 1");
  MeshBuilder b;
  // Vertices keyed by their lattice coordinates (i, j, k) ∈ [0, n]³.
  auto lattice = [&](const std::array<int, 3>& ijk) {
    return b.vertex({ijk[0], ijk[1], ijk[2], 0}, [&] {
      Vec3 p;
      for (int a = 0; a < 3; ++a) {
        p[a] = ijk[a] == n ? max[a] : min[a] + (max[a] - min[a]) * double(ijk[a]) / n;
      }
      return p;
    });
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // e_u × e_v = e_axis
    for (int side = 0; side < 2; ++side) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          auto at = [&](int di, int dj) {
            std::array<int, 3> ijk{};
            ijk[axis] = side * n;
            ijk[u] = i + di;
            ijk[v] = j + dj;
            return lattice(ijk);
          };
          if (side == 1) {
            b.quad(at(0, 0), at(1, 0), at(1, 1), at(0, 1));
          } else {
            b.quad(at(0, 0), at(0, 1), at(1, 1), at(1, 0));
          }
        }
      }
    }
  }
  return b.take();
}

TriMesh rotated(const TriMesh& mesh, const Mat3& rotation, const Vec3& center) {
  TriMesh out = mesh;
  for (Vec3& p : out.vertices) p = center + rotation * (p - center);
  return out;
}

TriMesh makeSphere(const Vec3& center, double radius, int subdivisions) {
  requireThat(subdivisions >= 0 && radius > 0, "makeSphere: bad radius or subdivisions");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                            {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                            {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : unit) p.normalize();
  std::vector<Vec3i> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                              {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                              {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                              {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  // Orient each base face outward (the icosahedron is convex and centred at the origin).
  for (Vec3i& f : faces) {
    const Vec3 nrm = (unit[f[1]] - unit[f[0]]).cross(unit[f[2]] - unit[f[0]]);
    if (nrm.dot(unit[f[0]] + unit[f[1]] + unit[f[2]]) < 0) std::swap(f[1], f[2]);
  }
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b2) {
      const std::pair<int, int> key = std::minmax(a, b2);
      auto [it, inserted] = midpoint.try_emplace(key, static_cast<int>(unit.size()));
      if (inserted) unit.push_back((unit[a] + unit[b2]).normalized());
      return it->second;
    };
    std::vector<Vec3i> next;
    next.reserve(faces.size() * 4);
    for (const Vec3i& f : faces) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      next.emplace_back(f[0], ab, ca);
      next.emplace_back(f[1], bc, ab);
      next.emplace_back(f[2], ca, bc);
      next.emplace_back(ab, bc, ca);
    }
    faces = std::move(next);
  }
  TriMesh mesh;
  mesh.vertices.reserve(unit.size());
  for (const Vec3& p : unit) mesh.vertices.push_back(center + radius * p);
  mesh.triangles = std::move(faces);
  mesh.faceIds.assign(mesh.triangles.size(), 0);
  return mesh;
}

TriMesh makeSphericalShell(const Vec3& center, double r1, double r2, int subdivisions) {
  requireThat(r1 > 0 && r1 < r2, "makeSphericalShell: need 0 < r1 < r2");
  TriMesh mesh = makeSphere(center, r2, subdivisions);
  TriMesh inner = makeSphere(center, r1, subdivisions);
  for (Vec3i& t : inner.triangles) std::swap(t[1], t[2]);
  appendMesh(mesh, inner);
  return mesh;
}

TriMesh makeTorus(const Vec3& center, double majorRadius, double minorRadius, int majorSegments,
                  int minorSegments) {
  requireThat(
      majorSegments >= 3 && minorSegments >= 3 && minorRadius > 0 && majorRadius > minorRadius,
      "makeTorus: need R > r > 0 and at least 3 segments each way");
  MeshBuilder b;
  auto at = [&](int i, int j) {
    i %= majorSegments;
    j %= minorSegments;
    return b.vertex({i, j, 0, 0}, [&] {
      const double theta = 2.0 * std::numbers::pi * i / majorSegments;
      const double phi = 2.0 * std::numbers::pi * j / minorSegments;
      const double rho = majorRadius + minorRadius * std::cos(phi);
      return Vec3(center +
                  Vec3(rho * std::cos(theta), rho * std::sin(theta), minorRadius * std::sin(phi)));
    });
  };
  for (int i = 0; i < majorSegments; ++i) {
    for (int j = 0; j < minorSegments; ++j) {
      b.quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  return b.take();
}

TriMesh makeCylinder(const Vec3& baseCenter, double radius, double height, int segments,
                     int rings) {
  requireThat(segments >= 3 && rings >= 1 && radius > 0 && height > 0,
              "makeCylinder: need radius, height > 0, segments >= 3, rings >= 1");
  return makeRefinedPrism(baseCenter, radius, height, segments, 1, rings);
}

TriMesh makeSliverCylinder(const Vec3& baseCenter, double radius, double height, int segments) {
  requireThat(segments >= 3 && radius > 0 && height > 0,
              "makeSliverCylinder: need radius, height > 0, segments >= 3");
  // Side quads not touching rim corner 0 are split into `columns` thin strips whose diagonals
  // run corner to corner (steep). The caps are fans from rim corner 0 over every rim point,
  // including the strip points, which makes long, thin triangles.
  constexpr int columns = 4;
  const int n = segments;
  MeshBuilder b;
  auto columnsOf = [&](int k) { return (k == 0 || k == n - 1) ? 1 : columns; };
  auto rimPoint = [&](int level, int k, int j) {  // edge k, column j of columnsOf(k)
    const int m = columnsOf(k);
    if (j == m) {
      k = (k + 1) % n;
      j = 0;
    }
    return b.vertex({level, k, j, 0}, [&] {
      const double z = baseCenter.z() + level * height;
      const Vec3 a = polygonCorner(baseCenter, radius, n, k, z);
      if (j == 0) return a;
      const Vec3 bb = polygonCorner(baseCenter, radius, n, k + 1, z);
      return Vec3(a + (double(j) / columnsOf(k)) * (bb - a));
    });
  };
  // Rim points in counter-clockwise order, starting at corner 0.
  for (int level = 0; level < 2; ++level) {
    std::vector<int> rim;
    for (int k = 0; k < n; ++k) {
      for (int j = 0; j < columnsOf(k); ++j) rim.push_back(rimPoint(level, k, j));
    }
    for (std::size_t q = 1; q + 1 < rim.size(); ++q) {
      if (level == 1) {
        b.triangle(rim[0], rim[q], rim[q + 1]);
      } else {
        b.triangle(rim[0], rim[q + 1], rim[q]);
      }
    }
  }
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < columnsOf(k); ++j) {
      b.quad(rimPoint(0, k, j), rimPoint(0, k, j + 1), rimPoint(1, k, j + 1), rimPoint(1, k, j));
    }
  }
  return b.take();
}

TriMesh makeFineCylinder(const Vec3& baseCenter, double radius, double height, int segments,
                         int targetTriangles) {
  requireThat(segments >= 3 && radius > 0 && height > 0 && targetTriangles > 0,
              "makeFineCylinder: need radius, height, targetTriangles > 0, segments >= 3");
  // Triangles: caps 2·n·m², sides 2·n·m·rows. About half go to the caps.
  const double n = segments;
  const int m = std::max(1, static_cast<int>(std::lround(std::sqrt(targetTriangles / (4.0 * n)))));
  const double capTriangles = 2.0 * n * m * m;
  const int rows =
      std::max(1, static_cast<int>(std::lround((targetTriangles - capTriangles) / (2.0 * n * m))));
  return makeRefinedPrism(baseCenter, radius, height, segments, m, rows);
}

TriMesh makeCone(const Vec3& baseCenter, double r0, double r1, double height, int segments) {
  requireThat(segments >= 3 && r0 >= 0 && r1 >= 0 && r0 + r1 > 0 && height > 0,
              "makeCone: need r0, r1 >= 0 (not both 0), height > 0, segments >= 3");
  MeshBuilder b;
  const int n = segments;
  const double radius[2] = {r0, r1};
  auto rim = [&](int level, int k) {
    k %= n;
    if (radius[level] == 0) k = 0;  // apex
    return b.vertex({1, level, k, 0}, [&] {
      return polygonCorner(baseCenter, radius[level], n, k, baseCenter.z() + level * height);
    });
  };
  auto centre = [&](int level) {
    return b.vertex({0, level, 0, 0},
                    [&] { return Vec3(baseCenter + Vec3(0, 0, level * height)); });
  };
  for (int k = 0; k < n; ++k) {
    if (r1 > 0) b.triangle(centre(1), rim(1, k), rim(1, k + 1));
    if (r0 > 0) b.triangle(centre(0), rim(0, k + 1), rim(0, k));
    if (r1 == 0) {
      b.triangle(rim(0, k), rim(0, k + 1), rim(1, 0));
    } else if (r0 == 0) {
      b.triangle(rim(0, 0), rim(1, k + 1), rim(1, k));
    } else {
      b.quad(rim(0, k), rim(0, k + 1), rim(1, k + 1), rim(1, k));
    }
  }
  return b.take();
}

TriMesh makeLPrism(double a, double b, double w, double height) {
  requireThat(w > 0 && a > w && b > w && height > 0, "makeLPrism: need a, b > w > 0, height > 0");
  // Counter-clockwise outline; (0, w) splits the x = 0 side so both caps' rectangles share it.
  const std::vector<Eigen::Vector2d> polygon = {{0, 0}, {a, 0}, {a, w}, {w, w},
                                                {w, b}, {0, b}, {0, w}};
  const std::vector<Vec3i> cap = {{0, 1, 2}, {0, 2, 3}, {0, 3, 6}, {6, 3, 4}, {6, 4, 5}};
  // Edges: 0 (y=0), 1 (x=a, id 1), 2, 3, 4 (y=b, id 2), 5, 6.
  const std::vector<int> edgeIds = {0, 1, 0, 0, 2, 0, 0};
  return extrudePolygon(polygon, cap, edgeIds, height);
}

TriMesh makeUChannel(double a, double b, double w, double height) {
  requireThat(w > 0 && a > w && b > 3 * w && height > 0,
              "makeUChannel: need a > w > 0, b > 3w, height > 0");
  // Counter-clockwise outline; (0, w) and (0, b − w) split the x = 0 side for the caps.
  const std::vector<Eigen::Vector2d> polygon = {{0, 0},     {a, 0}, {a, w}, {w, w},     {w, b - w},
                                                {a, b - w}, {a, b}, {0, b}, {0, b - w}, {0, w}};
  const std::vector<Vec3i> cap = {{0, 1, 2}, {0, 2, 3}, {0, 3, 9}, {9, 3, 4},
                                  {9, 4, 8}, {8, 4, 7}, {4, 6, 7}, {4, 5, 6}};
  const std::vector<int> edgeIds = {0, 1, 0, 0, 0, 0, 0, 0, 0, 0};
  return extrudePolygon(polygon, cap, edgeIds, height);
}

TriMesh makeHalfAnnulus(double ri, double ro, double height, int segments) {
  requireThat(ri > 0 && ro > ri && height > 0 && segments >= 1,
              "makeHalfAnnulus: need 0 < ri < ro, height > 0, segments >= 1");
  const int s = segments;
  auto dir = [&](int k) -> Eigen::Vector2d {
    if (k == 0) return {1.0, 0.0};
    if (k == s) return {-1.0, 0.0};
    const double theta = std::numbers::pi * k / s;
    return {std::cos(theta), std::sin(theta)};
  };
  // Outline: outer arc θ = 0 → π (indices 0..s), inner arc θ = π → 0 (indices s+1..2s+1).
  std::vector<Eigen::Vector2d> polygon;
  for (int k = 0; k <= s; ++k) polygon.push_back(ro * dir(k));
  for (int k = s; k >= 0; --k) polygon.push_back(ri * dir(k));
  auto outer = [&](int k) { return k; };
  auto inner = [&](int k) { return 2 * s + 1 - k; };
  std::vector<Vec3i> cap;
  for (int k = 0; k < s; ++k) {
    cap.emplace_back(inner(k), outer(k), outer(k + 1));
    cap.emplace_back(inner(k), outer(k + 1), inner(k + 1));
  }
  std::vector<int> edgeIds(polygon.size(), 0);
  edgeIds[s] = 2;          // (-ro, 0) → (-ri, 0): end face at θ = π
  edgeIds[2 * s + 1] = 1;  // (ri, 0) → (ro, 0): end face at θ = 0
  return extrudePolygon(polygon, cap, edgeIds, height);
}

TriMesh makeFlatGrid(double x0, double x1, double y0, double y1, double z, int n, int m) {
  TriMesh mesh;
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= n; ++i) {
      mesh.vertices.emplace_back(x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / m, z);
    }
  }
  const auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      mesh.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return mesh;
}

TriMesh makeOpenBox(const Vec3& size, double wall) {
  requireThat(wall > 0 && size.x() > 2 * wall && size.y() > 2 * wall && size.z() > wall,
              "makeOpenBox: need 0 < wall, size.x and size.y > 2·wall, size.z > wall");
  MeshBuilder b;
  const double X = size.x(), Y = size.y(), Z = size.z(), w = wall;
  // Corners counter-clockwise seen from above: outer at z = 0 and z = Z, cavity at z = w and Z.
  const std::array<Eigen::Vector2d, 4> outer = {{{0, 0}, {X, 0}, {X, Y}, {0, Y}}};
  const std::array<Eigen::Vector2d, 4> inner = {{{w, w}, {X - w, w}, {X - w, Y - w}, {w, Y - w}}};
  std::array<int, 4> o0{}, oZ{}, iw{}, iZ{};
  for (int k = 0; k < 4; ++k) {
    o0[k] = b.addVertex({outer[k].x(), outer[k].y(), 0.0});
    oZ[k] = b.addVertex({outer[k].x(), outer[k].y(), Z});
    iw[k] = b.addVertex({inner[k].x(), inner[k].y(), w});
    iZ[k] = b.addVertex({inner[k].x(), inner[k].y(), Z});
  }
  b.quad(o0[0], o0[3], o0[2], o0[1]);  // outer bottom, facing −z
  b.quad(iw[0], iw[1], iw[2], iw[3]);  // cavity floor, facing +z (into the cavity)
  for (int k = 0; k < 4; ++k) {
    const int n = (k + 1) % 4;
    b.quad(o0[k], o0[n], oZ[n], oZ[k]);  // outer side, facing out
    b.quad(iw[n], iw[k], iZ[k], iZ[n]);  // cavity side, facing the cavity
    b.quad(oZ[k], oZ[n], iZ[n], iZ[k]);  // rim at z = Z, facing +z
  }
  return b.take();
}

TriMesh deleteTriangles(const TriMesh& mesh, double fraction) {
  TriMesh out;
  out.vertices = mesh.vertices;
  const bool ids = mesh.faceIds.size() == mesh.triangles.size();
  const double f = std::clamp(fraction, 0.0, 1.0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    // Triangle t is removed when the running count floor((t + 1)·f) steps up: evenly spread,
    // about f·n removed in total.
    const bool remove = std::floor((t + 1) * f) > std::floor(t * f);
    if (remove) continue;
    out.triangles.push_back(mesh.triangles[t]);
    if (ids) out.faceIds.push_back(mesh.faceIds[t]);
  }
  return out;
}

std::string writeTempStl(const TriMesh& mesh, const std::string& name) {
  namespace fs = std::filesystem;
  static std::atomic<unsigned> counter{0};
  // A folder per call keeps the file name as given while two processes never collide.
  const fs::path dir = fs::temp_directory_path() /
                       ("curvedslicer-shapes-" + std::to_string(::getuid())) /
                       (std::to_string(::getpid()) + "-" + std::to_string(counter++));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::path file = dir / name;
  if (!file.has_extension()) file += ".stl";
  writeBinaryStl(file, mesh);
  return file.string();
}

}  // namespace curvedslicer::testing
