// Layer surface simplification: half-edge collapse bounded by quadrics of the original planes, in
// threshold passes over a flat triangle array; border and non-manifold vertices fixed. See the
// header for the method and the bound.
#include "curvedslicer/layers/layer_simplification.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "layers/layer_internal.hpp"

namespace curvedslicer {
namespace {

using layers_detail::formatNumber;

/// New triangles must have |a × b| above kMinSine times their longest edge squared (angles not
/// within about 1e-6 rad of 0 or π).
constexpr double kMinSine = 1e-6;

/// A new triangle's normal must stay within acos(kMinNormalCosine) = 60° of the normal of the
/// triangle it replaces.
constexpr double kMinNormalCosine = 0.5;

/// Thresholds of the passes as shares of ε²: small errors first (a coarse stand-in for a priority
/// queue), then passes at ε² until one removes fewer than kLastPassShare of the vertices left.
constexpr std::array<double, 4> kThresholdShares = {1.0 / 256, 1.0 / 32, 1.0 / 4, 1.0};
constexpr double kLastPassShare = 0.01;
constexpr int kMaxPasses = 8;

/// Symmetric 4 × 4 quadric Q of a sum of squared plane distances: e(p) = [p 1] Q [p 1]ᵀ
/// (Garland & Heckbert 1997), stored as its upper triangle.
struct Quadric {
  std::array<double, 10> q{};  // xx xy xz xw yy yz yw zz zw ww

  void addPlane(const Vec3& n, double d) {  // n·p + d = 0, |n| = 1
    q[0] += n.x() * n.x(), q[1] += n.x() * n.y(), q[2] += n.x() * n.z(), q[3] += n.x() * d;
    q[4] += n.y() * n.y(), q[5] += n.y() * n.z(), q[6] += n.y() * d;
    q[7] += n.z() * n.z(), q[8] += n.z() * d, q[9] += d * d;
  }
  void add(const Quadric& o) {
    for (std::size_t k = 0; k < q.size(); ++k) q[k] += o.q[k];
  }
  double error(const Vec3& p) const {
    const double x = p.x(), y = p.y(), z = p.z();
    return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y +
           2 * q[5] * y * z + 2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
  }
};

/// One corner of a triangle: the triangle and the corner's position in it (0–2).
struct Corner {
  int triangle;
  int k;
};

class Decimator {
 public:
  Decimator(const TriMesh& surface, double epsilon, double maxEdgeLength)
      : p_(surface.vertices),
        tris_(surface.triangles),
        centre_(surface.bounds().center()),
        epsilonSq_(epsilon * epsilon),
        maxEdgeSq_(maxEdgeLength > 0.0 ? maxEdgeLength * maxEdgeLength
                                       : std::numeric_limits<double>::infinity()),
        alive_(tris_.size(), 1),
        quadrics_(p_.size()),
        fixed_(p_.size(), 0),
        touched_(p_.size(), 0),
        stamp_(p_.size(), 0) {}

  /// False if an edge has more than two triangles or two triangles using it in one direction.
  bool classifyVertices();
  void addPlanes();
  /// Runs the passes; returns the number of vertices held fixed.
  std::size_t run();
  TriMesh collect() const;

 private:
  void buildCorners();
  std::size_t runPass(double threshold);
  bool tryCollapse(int u, int v, double threshold, double& cost);
  bool linkConditionHolds(int u, int v);
  bool keepsTrianglesSound(int u, int v) const;
  void collapse(int u, int v);
  bool hasVertex(int t, int v) const {
    const Vec3i& f = tris_[static_cast<std::size_t>(t)];
    return f[0] == v || f[1] == v || f[2] == v;
  }

  const std::vector<Vec3>& p_;
  std::vector<Vec3i> tris_;
  Vec3 centre_;  // quadrics are taken about this point (fewer digits lost)
  double epsilonSq_;
  double maxEdgeSq_;  // longest edge a collapse may create, squared
  std::vector<char> alive_;
  std::vector<Quadric> quadrics_;
  std::vector<char> fixed_;    // border, non-manifold, or on a degenerate fan: never removed
  std::vector<char> touched_;  // changed in this pass: not collapsed again before the next
  std::vector<int> stamp_;     // scratch marks for the link condition
  int stampValue_ = 0;
  std::vector<Corner> corners_;  // per vertex [first_[v], first_[v] + count_[v]); dead ones stay
  std::vector<std::size_t> first_;
  std::vector<int> count_;
  std::size_t verticesLeft_ = 0;
};

void Decimator::buildCorners() {
  const std::size_t nv = p_.size();
  first_.assign(nv + 1, 0);
  count_.assign(nv, 0);
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    if (alive_[t] == 0) continue;
    for (int k = 0; k < 3; ++k) ++first_[static_cast<std::size_t>(tris_[t][k]) + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) first_[v + 1] += first_[v];
  corners_.assign(first_[nv], Corner{});
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    if (alive_[t] == 0) continue;
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(tris_[t][k]);
      corners_[first_[v] + static_cast<std::size_t>(count_[v]++)] = {static_cast<int>(t), k};
    }
  }
}

bool Decimator::classifyVertices() {
  buildCorners();
  // Walk each vertex's fan: triangle (v, a, b) maps a → b. An interior manifold vertex has every
  // neighbour once as a and once as b, and the map is one cycle through all its triangles.
  std::vector<std::pair<int, int>> next;
  for (std::size_t v = 0; v < p_.size(); ++v) {
    const int n = count_[v];
    if (n == 0) continue;
    ++verticesLeft_;
    next.clear();
    for (int c = 0; c < n; ++c) {
      const Corner& corner = corners_[first_[v] + static_cast<std::size_t>(c)];
      const Vec3i& f = tris_[static_cast<std::size_t>(corner.triangle)];
      next.emplace_back(f[(corner.k + 1) % 3], f[(corner.k + 2) % 3]);
    }
    std::sort(next.begin(), next.end());
    for (int c = 0; c + 1 < n; ++c) {
      if (next[c].first == next[c + 1].first) return false;  // an edge used twice v → a
    }
    bool closed = true;
    for (int c = 0; c < n && closed; ++c) {
      const auto it =
          std::lower_bound(next.begin(), next.end(), std::make_pair(next[c].second, -1));
      closed = it != next.end() && it->first == next[c].second;
    }
    if (!closed) {
      fixed_[v] = 1;  // on the border
      continue;
    }
    int steps = 0;
    for (int a = next[0].first;;) {
      a = std::lower_bound(next.begin(), next.end(), std::make_pair(a, -1))->second;
      ++steps;
      if (a == next[0].first || steps > n) break;
    }
    if (steps != n) fixed_[v] = 1;  // two or more fans meet here
  }
  return true;
}

void Decimator::addPlanes() {
  for (const Vec3i& f : tris_) {
    const Vec3 n = (p_[f[1]] - p_[f[0]]).cross(p_[f[2]] - p_[f[0]]);
    const double length = n.norm();
    if (!(length > 0.0)) {
      for (int k = 0; k < 3; ++k) fixed_[static_cast<std::size_t>(f[k])] = 1;  // no plane
      continue;
    }
    const Vec3 unit = n / length;
    const double d = -unit.dot(p_[f[0]] - centre_);
    for (int k = 0; k < 3; ++k) quadrics_[static_cast<std::size_t>(f[k])].addPlane(unit, d);
  }
}

bool Decimator::linkConditionHolds(int u, int v) {
  const auto iterate = [&](int vertex, auto&& body) {
    const auto begin = first_[static_cast<std::size_t>(vertex)];
    const auto end = begin + static_cast<std::size_t>(count_[static_cast<std::size_t>(vertex)]);
    for (std::size_t c = begin; c < end; ++c) {
      if (alive_[static_cast<std::size_t>(corners_[c].triangle)] != 0) body(corners_[c]);
    }
  };
  const int neighbourOfU = ++stampValue_;
  int trianglesU = 0;
  iterate(u, [&](const Corner& c) {
    for (int j : {1, 2}) {
      stamp_[static_cast<std::size_t>(tris_[static_cast<std::size_t>(c.triangle)][(c.k + j) % 3])] =
          neighbourOfU;
    }
    ++trianglesU;
  });
  const int counted = ++stampValue_;
  int shared = 0, trianglesV = 0;
  iterate(v, [&](const Corner& c) {
    for (int j : {1, 2}) {
      int& s = stamp_[static_cast<std::size_t>(
          tris_[static_cast<std::size_t>(c.triangle)][(c.k + j) % 3])];
      if (s == neighbourOfU) {
        s = counted;
        ++shared;
      }
    }
    ++trianglesV;
  });
  // u is interior, so the edge has two triangles, whose third vertices must be the only shared
  // neighbours; v keeps at least three triangles (no fold of a closed tetrahedron).
  return shared == 2 && trianglesU + trianglesV - 4 >= 3;
}

bool Decimator::keepsTrianglesSound(int u, int v) const {
  const Vec3& to = p_[static_cast<std::size_t>(v)];
  const auto begin = first_[static_cast<std::size_t>(u)];
  const auto end = begin + static_cast<std::size_t>(count_[static_cast<std::size_t>(u)]);
  for (std::size_t c = begin; c < end; ++c) {
    const Corner& corner = corners_[c];
    if (alive_[static_cast<std::size_t>(corner.triangle)] == 0 || hasVertex(corner.triangle, v)) {
      continue;  // gone, or removed by the collapse
    }
    const Vec3i& f = tris_[static_cast<std::size_t>(corner.triangle)];
    const Vec3& b = p_[static_cast<std::size_t>(f[(corner.k + 1) % 3])];
    const Vec3& c2 = p_[static_cast<std::size_t>(f[(corner.k + 2) % 3])];
    const Vec3 normal = (b - to).cross(c2 - to);
    if ((b - to).squaredNorm() > maxEdgeSq_ || (c2 - to).squaredNorm() > maxEdgeSq_) return false;
    const double longest =
        std::max({(b - to).squaredNorm(), (c2 - b).squaredNorm(), (to - c2).squaredNorm()});
    if (!(normal.squaredNorm() > kMinSine * kMinSine * longest * longest)) return false;
    const Vec3& from = p_[static_cast<std::size_t>(u)];
    const Vec3 before = (b - from).cross(c2 - from);
    if (!(normal.dot(before) > kMinNormalCosine * normal.norm() * before.norm())) return false;
  }
  return true;
}

bool Decimator::tryCollapse(int u, int v, double threshold, double& cost) {
  const auto ui = static_cast<std::size_t>(u), vi = static_cast<std::size_t>(v);
  if (fixed_[ui] != 0 || touched_[ui] != 0 || touched_[vi] != 0) return false;
  Quadric q = quadrics_[ui];
  q.add(quadrics_[vi]);
  cost = q.error(p_[vi] - centre_);
  return cost <= threshold;
}

void Decimator::collapse(int u, int v) {
  const auto ui = static_cast<std::size_t>(u), vi = static_cast<std::size_t>(v);
  quadrics_[vi].add(quadrics_[ui]);
  // v's corners: u's live ones that survive (now corners of v), then v's live ones.
  const std::size_t start = corners_.size();
  for (const int vertex : {u, v}) {
    const auto begin = first_[static_cast<std::size_t>(vertex)];
    const auto end = begin + static_cast<std::size_t>(count_[static_cast<std::size_t>(vertex)]);
    for (std::size_t c = begin; c < end; ++c) {
      const Corner corner = corners_[c];
      auto& f = tris_[static_cast<std::size_t>(corner.triangle)];
      if (alive_[static_cast<std::size_t>(corner.triangle)] == 0) continue;
      if (vertex == u && hasVertex(corner.triangle, v)) {
        alive_[static_cast<std::size_t>(corner.triangle)] = 0;
        continue;
      }
      if (vertex == u) f[corner.k] = v;
      corners_.push_back(corner);
    }
  }
  first_[vi] = start;
  count_[vi] = static_cast<int>(corners_.size() - start);
  count_[ui] = 0;
  touched_[ui] = touched_[vi] = 1;
  --verticesLeft_;
}

std::size_t Decimator::runPass(double threshold) {
  std::fill(touched_.begin(), touched_.end(), 0);
  std::size_t collapses = 0;
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    if (alive_[t] == 0) continue;
    for (int k = 0; k < 3 && alive_[t] != 0; ++k) {
      const int a = tris_[t][k], b = tris_[t][(k + 1) % 3];
      // A collapse removes an interior vertex, so the edge is interior and its other triangle
      // sees it as (b, a): each edge once.
      if (a > b ||
          (fixed_[static_cast<std::size_t>(a)] & fixed_[static_cast<std::size_t>(b)]) != 0) {
        continue;
      }
      double costAB = 0.0, costBA = 0.0;
      const bool ab = tryCollapse(a, b, threshold, costAB);
      const bool ba = tryCollapse(b, a, threshold, costBA);
      // The cheaper direction first, then the other if the first breaks a check.
      std::array<std::pair<int, int>, 2> order = {std::make_pair(a, b), std::make_pair(b, a)};
      if (ba && (!ab || costBA < costAB)) std::swap(order[0], order[1]);
      for (int o = 0; o < (ab ? 1 : 0) + (ba ? 1 : 0); ++o) {
        const auto [u, v] = order[static_cast<std::size_t>(o)];
        if (linkConditionHolds(u, v) && keepsTrianglesSound(u, v)) {
          collapse(u, v);
          ++collapses;
          break;
        }
      }
    }
  }
  return collapses;
}

std::size_t Decimator::run() {
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    const double share = kThresholdShares[std::min<std::size_t>(static_cast<std::size_t>(pass),
                                                                kThresholdShares.size() - 1)];
    if (pass > 0) buildCorners();  // drops the dead corners and the stale lists
    const std::size_t before = verticesLeft_;
    const std::size_t collapses = runPass(share * epsilonSq_);
    if (static_cast<std::size_t>(pass) + 1 >= kThresholdShares.size() &&
        static_cast<double>(collapses) < kLastPassShare * static_cast<double>(before)) {
      break;
    }
  }
  return static_cast<std::size_t>(std::count(fixed_.begin(), fixed_.end(), 1));
}

TriMesh Decimator::collect() const {
  TriMesh out;
  std::vector<int> newIndex(p_.size(), -1);
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    if (alive_[t] == 0) continue;
    for (int k = 0; k < 3; ++k) newIndex[static_cast<std::size_t>(tris_[t][k])] = 0;
  }
  for (std::size_t v = 0; v < p_.size(); ++v) {
    if (newIndex[v] < 0) continue;
    newIndex[v] = static_cast<int>(out.vertices.size());
    out.vertices.push_back(p_[v]);
  }
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    if (alive_[t] == 0) continue;
    const Vec3i& f = tris_[t];
    out.triangles.emplace_back(newIndex[static_cast<std::size_t>(f[0])],
                               newIndex[static_cast<std::size_t>(f[1])],
                               newIndex[static_cast<std::size_t>(f[2])]);
  }
  return out;
}

}  // namespace

double resolveLayerTolerance(const LayerSimplificationOptions& options, double voxelSize) {
  if (!(options.tolerance >= 0.0) || !std::isfinite(options.tolerance)) {
    throw InvalidInput("layer tolerance must be positive: " + formatNumber(options.tolerance) +
                       " mm; pass a finite value such as 0.05 times the voxel size, or 0 for "
                       "that default");
  }
  return options.tolerance > 0.0 ? options.tolerance : kDefaultLayerToleranceVoxels * voxelSize;
}

SimplifiedSurface simplifyLayerSurface(const TriMesh& surface, double tolerance,
                                       double maxEdgeLength) {
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) {
    throw InvalidInput("layer tolerance must be positive: " + formatNumber(tolerance) +
                       " mm; pass a finite value such as 0.025");
  }
  SimplifiedSurface result;
  result.trianglesBefore = surface.triangleCount();
  result.verticesBefore = surface.vertexCount();
  Decimator decimator(surface, tolerance, maxEdgeLength);
  if (surface.empty() || !decimator.classifyVertices()) {
    result.mesh = surface;
    result.keptFull = !surface.empty();
    result.trianglesAfter = result.trianglesBefore;
    result.verticesAfter = result.verticesBefore;
    return result;
  }
  decimator.addPlanes();
  result.fixedVertices = decimator.run();
  result.mesh = decimator.collect();
  result.trianglesAfter = result.mesh.triangleCount();
  result.verticesAfter = result.mesh.vertexCount();
  return result;
}

}  // namespace curvedslicer
