#include "solid_boundary.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace curvedslicer::detail {

namespace {

/// Builds CSR lists from (brick, item) pairs by counting (pairs of one item are unique and items
/// arrive in increasing order, so each brick's list comes out sorted).
void buildCsr(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs, std::size_t bricks,
              std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& list) {
  start.assign(bricks + 1, 0);
  for (const auto& p : pairs) ++start[p.first + 1];
  for (std::size_t b = 0; b < bricks; ++b) start[b + 1] += start[b];
  list.resize(pairs.size());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (const auto& p : pairs) list[fill[p.first]++] = p.second;
}

/// Whether a triangle overlaps axis-aligned cubes of half-size `h` (inflated by a tiny relative
/// margin by the caller): separating-axis test over the box axes, the triangle's normal and the
/// nine edge × axis directions (Akenine-Möller 2001, "Fast 3D triangle-box overlap testing").
/// Exact up to rounding, unlike a bounding-box test, which lists a long thin diagonal triangle in
/// every brick of its box. The triangle's projections on the 13 axes are computed once; a cube
/// then costs one dot product per axis (its centre's projection). These absolute projections
/// round to ~1e-16 of the coordinates: below the 1e-9 margin for grids up to 10^6 cells a side.
class TriangleBoxTester {
 public:
  TriangleBoxTester(const Triangle& t, double h) {
    const Vec3 e[3] = {t[1] - t[0], t[2] - t[1], t[0] - t[2]};
    int k = 0;
    auto add = [&](const Vec3& axis, double radius) {
      const double p0 = axis.dot(t[0]), p1 = axis.dot(t[1]), p2 = axis.dot(t[2]);
      axes_[k] = axis;
      lo_[k] = std::min({p0, p1, p2}) - radius;
      hi_[k] = std::max({p0, p1, p2}) + radius;
      ++k;
    };
    for (int a = 0; a < 3; ++a) add(Vec3::Unit(a), h);
    const Vec3 n = e[0].cross(e[1]);
    add(n, h * n.cwiseAbs().sum());
    for (int i = 0; i < 3; ++i) {
      for (int a = 0; a < 3; ++a) {
        const Vec3 axis = e[i].cross(Vec3::Unit(a));
        add(axis, h * axis.cwiseAbs().sum());
      }
    }
  }

  /// True unless an axis separates the triangle from the cube of centre `c`.
  bool overlaps(const Vec3& c) const {
    for (int k = 0; k < kAxes; ++k) {
      const double pc = axes_[k].dot(c);
      if (pc < lo_[k] || pc > hi_[k]) return false;
    }
    return true;
  }

 private:
  static constexpr int kAxes = 13;
  Vec3 axes_[kAxes];
  double lo_[kAxes], hi_[kAxes];  // the triangle's projection widened by the cube's radius
};

}  // namespace

SolidBoundary::SolidBoundary(const GridGeometry& g, const TriMesh& model) {
  std::vector<Vec3> v(model.vertices.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    v[i] = (g.frame.toFrame(model.vertices[i]) - g.corner) / g.voxelSize;

  // Brick size from the mean triangle area (cells²): a few triangles per brick. Large triangles
  // (boxes, prisms) make most bricks hold only one or two triangles whatever their size, and
  // bigger bricks mean fewer steps per segment.
  double area = 0.0;
  for (const Vec3i& f : model.triangles)
    area += 0.5 * (v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]).norm();
  const double meanArea = model.triangles.empty() ? 0.0 : area / model.triangles.size();
  brick_ = meanArea < 16.0 ? 2 : meanArea < 64.0 ? 4 : 8;
  inverseBrick_ = 1.0 / brick_;
  bdims_ = (g.dims.array() + brick_ - 1) / brick_;
  const std::size_t bricks = static_cast<std::size_t>(bdims_.x()) * bdims_.y() * bdims_.z();

  // Triangles -> bricks (bounding-box range, then an exact triangle-box test).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  // Half-size of a brick, inflated so that rounding never drops a triangle touching its faces.
  const double brickHalf = 0.5 * brick_ * (1.0 + 1e-9) + 1e-9;
  std::vector<std::uint32_t> triOfModel(model.triangles.size(), UINT32_MAX);
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    const Vec3i& f = model.triangles[t];
    Triangle tri{v[f[0]], v[f[1]], v[f[2]]};
    const Vec3 n = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
    const double nn = n.norm();
    if (!(nn > 0)) continue;
    const std::uint32_t id = static_cast<std::uint32_t>(tris_.size());
    triOfModel[t] = id;
    tris_.push_back(tri);
    normals_.push_back(n);
    crossing_.push_back(
        {1e-9 * nn,
         -1e-9 * n.squaredNorm(),
         {n.cross(tri[1] - tri[0]), n.cross(tri[2] - tri[1]), n.cross(tri[0] - tri[2])}});
    const Vec3 lo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]);
    const Vec3 hi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]);
    const Vec3i b0 = brickOf(lo), b1 = brickOf(hi);
    if (b0 == b1) {  // within one brick: no test needed
      pairs.emplace_back(static_cast<std::uint32_t>(brickIndex(b0)), id);
      continue;
    }
    const TriangleBoxTester tester(tri, brickHalf);
    for (int i = b0.x(); i <= b1.x(); ++i)
      for (int j = b0.y(); j <= b1.y(); ++j)
        for (int k = b0.z(); k <= b1.z(); ++k) {
          const Vec3 centre = (Vec3(i, j, k).array() + 0.5) * brick_;
          if (!tester.overlaps(centre)) continue;
          pairs.emplace_back(static_cast<std::uint32_t>(brickIndex(Vec3i(i, j, k))), id);
        }
  }
  buildCsr(pairs, bricks, triStart_, triList_);

  // Reflex edges: manifold, consistently oriented edges whose neighbouring triangle's far vertex
  // lies outside (in front of) the first triangle's plane.
  // Edge uses sorted by (lower vertex, higher vertex), each edge's uses in triangle order.
  struct Use {
    std::uint64_t key;  // lower vertex << 32 | higher vertex
    std::uint32_t tri;
    bool forward;  // the triangle traverses the edge from lower to higher vertex index
    int opposite;  // vertex not on the edge
  };
  std::vector<Use> uses;
  uses.reserve(3 * model.triangles.size());
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    if (triOfModel[t] == UINT32_MAX) continue;
    const Vec3i& f = model.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
      const auto key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) |
                       static_cast<std::uint32_t>(std::max(a, b));
      uses.push_back({key, triOfModel[t], a < b, c});
    }
  }
  std::stable_sort(uses.begin(), uses.end(),
                   [](const Use& l, const Use& r) { return l.key < r.key; });
  pairs.clear();
  closed_ = !model.triangles.empty() &&
            std::find(triOfModel.begin(), triOfModel.end(), UINT32_MAX) == triOfModel.end();
  for (std::size_t u0 = 0, u1 = 0; u0 < uses.size(); u0 = u1) {
    u1 = u0 + 1;
    while (u1 < uses.size() && uses[u1].key == uses[u0].key) ++u1;
    if (u1 - u0 != 2 || uses[u0].forward == uses[u0 + 1].forward) {
      closed_ = false;
      continue;
    }
    const Use& first = uses[u0];
    const Use& second = uses[u0 + 1];
    const Vec3& a = v[static_cast<std::size_t>(first.key >> 32)];
    const Vec3& b = v[static_cast<std::size_t>(first.key & 0xffffffffu)];
    const Vec3 n1 = normals_[first.tri].normalized();
    const double edgeLen = (b - a).norm();
    const double bulge = n1.dot(v[second.opposite] - a);
    // Reflex when the second face turns outward by more than ~1e-6 rad relative to its size.
    const double size = (v[second.opposite] - a).norm();
    if (!(bulge > 1e-6 * size) || !(edgeLen > 0)) continue;
    const std::uint32_t id = static_cast<std::uint32_t>(reflex_.size());
    reflex_.push_back({a, b});
    reflexNormals_.push_back({n1, normals_[second.tri].normalized()});
    const Vec3i b0 = brickOf(a.cwiseMin(b).array() - 3.0);
    const Vec3i b1 = brickOf(a.cwiseMax(b).array() + 3.0);
    for (int i = b0.x(); i <= b1.x(); ++i)
      for (int j = b0.y(); j <= b1.y(); ++j)
        for (int k = b0.z(); k <= b1.z(); ++k)
          pairs.emplace_back(static_cast<std::uint32_t>(brickIndex(Vec3i(i, j, k))), id);
  }
  buildCsr(pairs, bricks, edgeStart_, edgeList_);
}

Vec3i SolidBoundary::brickOf(const Vec3& p) const {
  Vec3i b;
  for (int a = 0; a < 3; ++a) {
    const int i = static_cast<int>(std::floor(p[a] * inverseBrick_));
    b[a] = std::clamp(i, 0, bdims_[a] - 1);
  }
  return b;
}

bool SolidBoundary::crossesTriangle(const Vec3& a, const Vec3& b, std::uint32_t t,
                                    double startTolerance) const {
  const Triangle& tri = tris_[t];
  const Vec3& n = normals_[t];
  const double da = n.dot(a - tri[0]);
  const double db = n.dot(b - tri[0]);
  // Both ends on one side (the common case, decided without the square root below).
  if ((da > 0) == (db > 0)) return false;
  const CrossingData& c = crossing_[t];
  const double eps = c.planeEps;
  if (std::abs(da) <= eps || std::abs(db) <= eps) return false;  // touches the plane at an end
  const double s = da / (da - db);
  // A start point within startTolerance cells outside the surface (a cell centre in the sliver
  // between a curved solid and its tessellation) is not blocked by that surface.
  if (startTolerance > 0 && s * (b - a).norm() < startTolerance) return false;
  const Vec3 p = a + s * (b - a);
  // Inclusive point-in-triangle test (a crossing through an edge or vertex counts).
  for (int k = 0; k < 3; ++k) {
    if (c.sideNormals[k].dot(p - tri[k]) < c.sideTol) return false;
  }
  return true;
}

bool SolidBoundary::segmentClear(const Vec3& a, const Vec3& b, Mailbox& mailbox, Vec3* hit,
                                 double startTolerance) const {
  // The point where the segment crosses triangle t (which it does).
  auto crossing = [&](std::uint32_t t) {
    const Triangle& tri = tris_[t];
    const Vec3& n = normals_[t];
    const double da = n.dot(a - tri[0]), db = n.dot(b - tri[0]);
    return Vec3(a + (da / (da - db)) * (b - a));
  };
  Vec3i cell = brickOf(a);
  const Vec3i last = brickOf(b);
  if (cell == last) {
    // Within one brick (most short segments): its list holds each triangle once, so no marks.
    const std::size_t bi = brickIndex(cell);
    for (std::uint32_t i = triStart_[bi]; i < triStart_[bi + 1]; ++i) {
      if (!crossesTriangle(a, b, triList_[i], startTolerance)) continue;
      if (hit) *hit = crossing(triList_[i]);
      return false;
    }
    return true;
  }
  // 3D DDA over bricks from a to b.
  const Vec3 d = b - a;
  const Vec3 pa = a * inverseBrick_;
  Vec3i step;
  Vec3 tMax, tDelta;
  for (int k = 0; k < 3; ++k) {
    const double dk = d[k] * inverseBrick_;
    if (dk > 0) {
      step[k] = 1;
      tMax[k] = (std::floor(pa[k]) + 1 - pa[k]) / dk;
      tDelta[k] = 1 / dk;
    } else if (dk < 0) {
      step[k] = -1;
      tMax[k] = (pa[k] - std::floor(pa[k])) / -dk;
      tDelta[k] = -1 / dk;
    } else {
      step[k] = 0;
      tMax[k] = kInf;
      tDelta[k] = kInf;
    }
  }
  std::vector<std::uint32_t>& stamp = mailbox.stamp;
  if (++mailbox.epoch == 0) {  // wrapped: clear the marks
    std::fill(stamp.begin(), stamp.end(), 0);
    mailbox.epoch = 1;
  }
  const std::uint32_t epoch = mailbox.epoch;
  // Guard against rounding: at most the Manhattan brick distance + a few steps.
  int budget = (last - cell).cwiseAbs().sum() + 4;
  while (true) {
    const std::size_t bi = brickIndex(cell);
    for (std::uint32_t i = triStart_[bi]; i < triStart_[bi + 1]; ++i) {
      const std::uint32_t t = triList_[i];
      if (stamp[t] == epoch) continue;
      stamp[t] = epoch;
      if (!crossesTriangle(a, b, t, startTolerance)) continue;
      if (hit) *hit = crossing(t);
      return false;
    }
    if (cell == last || budget-- <= 0) break;
    int axis = 0;
    if (tMax[1] < tMax[axis]) axis = 1;
    if (tMax[2] < tMax[axis]) axis = 2;
    if (tMax[axis] > 1.0) break;
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= bdims_[axis]) break;
    tMax[axis] += tDelta[axis];
  }
  return true;
}

void SolidBoundary::reflexEdgesNear(const Vec3& x, double radius,
                                    std::vector<std::uint32_t>& out) const {
  out.clear();
  const std::size_t bi = brickIndex(brickOf(x));
  for (std::uint32_t i = edgeStart_[bi]; i < edgeStart_[bi + 1]; ++i) {
    const std::uint32_t e = edgeList_[i];
    const Vec3& a = reflex_[e][0];
    const Vec3 ab = reflex_[e][1] - a;
    const double s = std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    if ((a + s * ab - x).norm() <= radius) out.push_back(e);
  }
}

bool SolidBoundary::polygonMeetsReflexEdge(const Vec3* poly, int count, std::int64_t skip,
                                           double tolerance) const {
  // Plane normal from the diagonals (quadrilateral) or two sides (triangle).
  const Vec3 m = count == 4 ? (poly[2] - poly[0]).cross(poly[3] - poly[1])
                            : (poly[1] - poly[0]).cross(poly[2] - poly[0]);
  // Degenerate when |m| <= 1e-12; decided from |m|² away from the threshold (no square root),
  // exactly as |m| > 1e-12 otherwise.
  const double m2 = m.squaredNorm();
  if (!(m2 > 1.001e-24) && !(m.norm() > 1e-12)) return true;
  Vec3 lo = poly[0], hi = poly[0];
  for (int i = 1; i < count; ++i) {
    lo = lo.cwiseMin(poly[i]);
    hi = hi.cwiseMax(poly[i]);
  }
  lo.array() -= tolerance;
  hi.array() += tolerance;
  Vec3 n = Vec3::Zero();  // unit normal, computed for the first edge that passes the box test
  bool haveNormal = false;
  for (std::size_t e = 0; e < reflex_.size(); ++e) {
    if (static_cast<std::int64_t>(e) == skip) continue;
    const Vec3& a = reflex_[e][0];
    const Vec3& b = reflex_[e][1];
    if ((a.array() < lo.array() && b.array() < lo.array()).any() ||
        (a.array() > hi.array() && b.array() > hi.array()).any())
      continue;
    if (!haveNormal) {
      n = m / m.norm();
      haveNormal = true;
    }
    const double sa = n.dot(a - poly[0]), sb = n.dot(b - poly[0]);
    if ((sa > tolerance && sb > tolerance) || (sa < -tolerance && sb < -tolerance)) continue;
    // Nearly in the plane: the bounding boxes overlap, so count it (conservative).
    if (std::abs(sa - sb) <= tolerance) return true;
    const Vec3 q = a + (b - a) * std::clamp(sa / (sa - sb), 0.0, 1.0);
    bool inside = true;
    for (int i = 0; i < count && inside; ++i) {
      const Vec3 side = poly[(i + 1) % count] - poly[i];
      inside = n.dot(side.cross(q - poly[i])) >= -tolerance * side.norm();
    }
    if (inside) return true;
  }
  return false;
}

}  // namespace curvedslicer::detail
