// Smoothing cubic B-spline fit and resampling of raw paths (see curvedslicer/paths/path_fit.hpp).
#include "curvedslicer/paths/path_fit.hpp"

#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

#include "curvedslicer/core/error.hpp"
#include "segment_grid.hpp"

namespace curvedslicer {

namespace {

constexpr int kP = BSplineCurve::kDegree;
/// Raw vertices closer than this fraction of the tolerance to the previous kept one are merged.
constexpr double kMergeFraction = 1.0 / 50.0;
/// Corners are turns measured over this multiple of the tolerance of arc length on each side.
constexpr double kCornerReachFactor = 4.0;

/// Uniform cubic B-spline weights and their derivatives at local t in [0, 1].
void uniformWeights(double t, double w[4], double dw[4]) {
  const double s = 1.0 - t;
  w[0] = s * s * s / 6.0;
  w[1] = (3 * t * t * t - 6 * t * t + 4) / 6.0;
  w[2] = (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6.0;
  w[3] = t * t * t / 6.0;
  dw[0] = -s * s / 2.0;
  dw[1] = (9 * t * t - 12 * t) / 6.0;
  dw[2] = (-9 * t * t + 6 * t + 3) / 6.0;
  dw[3] = t * t / 2.0;
}

/// Knot span index of u in a clamped knot vector (NURBS Book A2.1).
int findSpan(const std::vector<double>& U, int controlCount, double u) {
  const int n = controlCount - 1;
  if (u >= U[n + 1]) return n;
  if (u <= U[kP]) return kP;
  int lo = kP, hi = n + 1;
  int mid = (lo + hi) / 2;
  while (u < U[mid] || u >= U[mid + 1]) {
    if (u < U[mid]) {
      hi = mid;
    } else {
      lo = mid;
    }
    mid = (lo + hi) / 2;
  }
  return mid;
}

/// Non-zero basis functions of degree p at u (NURBS Book A2.2).
void basisFunctions(const std::vector<double>& U, int span, double u, int p, double* N) {
  double left[kP + 1], right[kP + 1];
  N[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = u - U[span + 1 - j];
    right[j] = U[span + j] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double denom = right[r + 1] + left[j - r];
      const double temp = denom != 0.0 ? N[r] / denom : 0.0;
      N[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    N[j] = saved;
  }
}

/// Basis rows: for parameter u, the 4 control indices and weights.
struct BasisRow {
  int index[4];
  double weight[4];
};

BasisRow basisRow(const BSplineCurve& c, double u) {
  BasisRow row{};
  const int k = static_cast<int>(c.controlPoints.size());
  if (c.closed) {
    double x = u - std::floor(u);
    x *= k;
    int j = static_cast<int>(std::floor(x));
    if (j >= k) j = k - 1;
    double dw[4];
    uniformWeights(x - j, row.weight, dw);
    for (int i = 0; i < 4; ++i) row.index[i] = (j + i) % k;
  } else {
    u = std::clamp(u, 0.0, 1.0);
    const int span = findSpan(c.knots, k, u);
    basisFunctions(c.knots, span, u, kP, row.weight);
    for (int i = 0; i < 4; ++i) row.index[i] = span - kP + i;
  }
  return row;
}

BSplineCurve makeShape(bool closed, int k) {
  BSplineCurve c;
  c.closed = closed;
  c.controlPoints.assign(k, Vec3::Zero());
  if (closed) {
    for (int i = 0; i <= k; ++i) c.knots.push_back(static_cast<double>(i) / k);
  } else {
    const int interior = k - kP - 1;
    for (int i = 0; i <= kP; ++i) c.knots.push_back(0.0);
    for (int i = 1; i <= interior; ++i) c.knots.push_back(static_cast<double>(i) / (interior + 1));
    for (int i = 0; i <= kP; ++i) c.knots.push_back(1.0);
  }
  return c;
}

std::string num(double x) {
  return std::to_string(x);
}

/// Penalised least-squares fit with k control points (see the header).
BSplineCurve fitControlPoints(const std::vector<Vec3>& pts, const std::vector<double>& u,
                              bool closed, int k, double lambda) {
  BSplineCurve c = makeShape(closed, k);
  const int n = static_cast<int>(pts.size());
  // Unknowns: all control points (closed) or the interior ones (open; ends fixed to the data).
  const int first = closed ? 0 : 1;
  const int m = closed ? k : k - 2;
  if (!closed) {
    c.controlPoints.front() = pts.front();
    c.controlPoints.back() = pts.back();
  }
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(16 * static_cast<std::size_t>(n) + 10 * static_cast<std::size_t>(m));
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 3);
  auto unknown = [&](int index) { return index - first; };
  auto isUnknown = [&](int index) { return closed || (index >= 1 && index <= k - 2); };
  for (int i = 0; i < n; ++i) {
    const BasisRow row = basisRow(c, u[i]);
    Vec3 target = pts[i];
    for (int a = 0; a < 4; ++a) {
      if (!isUnknown(row.index[a])) target -= row.weight[a] * c.controlPoints[row.index[a]];
    }
    for (int a = 0; a < 4; ++a) {
      if (!isUnknown(row.index[a])) continue;
      const int ia = unknown(row.index[a]);
      rhs.row(ia) += row.weight[a] * target.transpose();
      for (int b = 0; b < 4; ++b) {
        if (!isUnknown(row.index[b])) continue;
        triplets.emplace_back(ia, unknown(row.index[b]), row.weight[a] * row.weight[b]);
      }
    }
  }
  // Second-difference penalty λ Σ |P_{j-1} − 2 P_j + P_{j+1}|².
  if (lambda > 0.0) {
    const int count = closed ? k : k - 2;
    for (int j = 0; j < count; ++j) {
      const int idx[3] = {closed ? (j + k - 1) % k : j, closed ? j : j + 1,
                          closed ? (j + 1) % k : j + 2};
      const double coef[3] = {1.0, -2.0, 1.0};
      Vec3 fixed = Vec3::Zero();
      for (int a = 0; a < 3; ++a) {
        if (!isUnknown(idx[a])) fixed += coef[a] * c.controlPoints[idx[a]];
      }
      for (int a = 0; a < 3; ++a) {
        if (!isUnknown(idx[a])) continue;
        const int ia = unknown(idx[a]);
        rhs.row(ia) -= lambda * coef[a] * fixed.transpose();
        for (int b = 0; b < 3; ++b) {
          if (!isUnknown(idx[b])) continue;
          triplets.emplace_back(ia, unknown(idx[b]), lambda * coef[a] * coef[b]);
        }
      }
    }
  }
  // A tiny ridge keeps control points without data (sparse raw points) determined.
  for (int j = 0; j < m; ++j) triplets.emplace_back(j, j, 1e-12);
  Eigen::SparseMatrix<double> A(m, m);
  A.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) {
    throw NumericalFailure("path spline fit failed: singular system with " + std::to_string(k) +
                           " control points; check the raw path for repeated points");
  }
  const Eigen::MatrixXd x = solver.solve(rhs);
  for (int j = 0; j < m; ++j) c.controlPoints[j + first] = x.row(j).transpose();
  return c;
}

/// Dense samples of the spline at uniform parameter (closed: without the wrap-around point).
std::vector<Vec3> sampleSpline(const BSplineCurve& c, int count) {
  std::vector<Vec3> out;
  out.reserve(count + 1);
  const int last = c.closed ? count - 1 : count;
  for (int i = 0; i <= last; ++i) out.push_back(c.evaluate(static_cast<double>(i) / count));
  return out;
}

double pointSegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

/// Exact distances from points to a polyline: a cheap upper bound from the segments around a hint
/// index, and the exact distance by brute force for the first few queries, then through a uniform
/// hash grid of the segments built on demand (long segments go in as pieces no longer than a cell,
/// so no segment covers a large box).
class PolylineDistance {
 public:
  /// `minCell` (mm, > 0) bounds the grid's cell size from below; the cell is the mean segment
  /// length. Keeps a reference to `pts`.
  PolylineDistance(const std::vector<Vec3>& pts, bool closed, double minCell)
      : pts_(pts), closed_(closed), minCell_(minCell) {}

  int segmentCount() const {
    const int n = static_cast<int>(pts_.size());
    return closed_ ? n : n - 1;
  }

  /// Upper bound of the distance from p: the nearest of the segments hint − 1 … hint + 1.
  double localBound(const Vec3& p, int hint) const {
    const int segments = segmentCount();
    const int n = static_cast<int>(pts_.size());
    double bound = kInf;
    for (int o = -1; o <= 1; ++o) {
      int s = hint + o;
      if (closed_) {
        s = ((s % segments) + segments) % segments;
      } else if (s < 0 || s >= segments) {
        continue;
      }
      bound = std::min(bound, pointSegmentDistance(p, pts_[s], pts_[(s + 1) % n]));
    }
    return bound;
  }

  /// Exact distance from p to the polyline, given an upper bound of it.
  double distance(const Vec3& p, double bound) {
    const int segments = segmentCount();
    const int n = static_cast<int>(pts_.size());
    if (exactQueries_ < kBruteForceQueries) {
      ++exactQueries_;
      double best = bound;
      for (int s = 0; s < segments; ++s)
        best = std::min(best, pointSegmentDistance(p, pts_[s], pts_[(s + 1) % n]));
      return best;
    }
    // A grid query visits about (2·bound/cell + 1)³ cells: when that is more than the segments,
    // testing every segment is cheaper (a far local bound on a finely sampled line).
    const double span = 2.0 * bound / gridCell() + 1.0;
    if (!(span * span * span < static_cast<double>(segments))) {
      double best = bound;
      for (int s = 0; s < segments; ++s)
        best = std::min(best, pointSegmentDistance(p, pts_[s], pts_[(s + 1) % n]));
      return best;
    }
    if (!grid_) buildGrid();
    Vec3 point;
    double d = bound;
    if (grid_->nearest(p, bound, point, d)) return std::min(d, bound);
    return bound;
  }

 private:
  static constexpr int kBruteForceQueries = 8;

  /// The grid's cell size: the mean segment length, at least minCell_.
  double gridCell() {
    if (cell_ > 0.0) return cell_;
    const int segments = segmentCount();
    const int n = static_cast<int>(pts_.size());
    double total = 0.0;
    for (int s = 0; s < segments; ++s) total += (pts_[(s + 1) % n] - pts_[s]).norm();
    cell_ = std::max(total / std::max(segments, 1), minCell_);
    return cell_;
  }

  void buildGrid() {
    const int segments = segmentCount();
    const int n = static_cast<int>(pts_.size());
    const double cell = gridCell();
    grid_.emplace(cell);
    for (int s = 0; s < segments; ++s) {
      const Vec3& a = pts_[s];
      const Vec3& b = pts_[(s + 1) % n];
      const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / cell)));
      for (int q = 0; q < pieces; ++q) {
        grid_->add(a + (b - a) * (static_cast<double>(q) / pieces),
                   q + 1 == pieces ? b : a + (b - a) * (static_cast<double>(q + 1) / pieces));
      }
    }
  }

  const std::vector<Vec3>& pts_;
  bool closed_;
  double minCell_;
  int exactQueries_ = 0;
  double cell_ = 0.0;
  std::optional<detail::SegmentGrid> grid_;
};

/// Largest distance of `points` from the polyline of `distance`, with hints[i] a segment index
/// near points[i]. The point with the largest local upper bound is measured exactly first; after
/// it, a point whose bound is at most the running maximum cannot raise it and is skipped, so only
/// a few points need an exact distance when the fit is close.
double measureLargestDistance(const std::vector<Vec3>& points, const std::vector<int>& hints,
                              PolylineDistance& distance) {
  const std::size_t count = points.size();
  std::vector<double> bounds(count);
  std::size_t first = 0;
  for (std::size_t i = 0; i < count; ++i) {
    bounds[i] = distance.localBound(points[i], hints[i]);
    if (bounds[i] > bounds[first]) first = i;
  }
  if (count == 0) return 0.0;
  double worst = distance.distance(points[first], bounds[first]);
  for (std::size_t i = 0; i < count; ++i) {
    if (i != first && bounds[i] > worst)
      worst = std::max(worst, distance.distance(points[i], bounds[i]));
  }
  return worst;
}

/// Two-sided deviation between the spline and the raw polyline `rawLine` (vertex parameters
/// `rawU`): the largest distance of a fitted point (`pts`, parameters `u`; the raw vertices, or
/// points on the raw segments after densification) from a dense sampling of the spline, and of a
/// spline sample from the raw polyline. Exact for those samples. Cost: O((n + s) log(n + s)) for
/// n fitted points and s = max(16k, 4n) samples when the fit is close (the local bounds decide).
double measureDeviation(const BSplineCurve& c, const std::vector<Vec3>& pts,
                        const std::vector<double>& u, const std::vector<Vec3>& rawLine,
                        const std::vector<double>& rawU, bool closed, double minCell) {
  const int k = static_cast<int>(c.controlPoints.size());
  const int n = static_cast<int>(pts.size());
  const int samples = std::max({16 * k, 4 * n, 64});
  const std::vector<Vec3> dense = sampleSpline(c, samples);
  const int denseCount = static_cast<int>(dense.size());
  // Spline sample → raw polyline (hint: the raw segment holding the sample's parameter).
  std::vector<int> hints(denseCount);
  int center = 0;
  for (int j = 0; j < denseCount; ++j) {
    const double uj = static_cast<double>(j) / samples;
    while (center + 1 < static_cast<int>(rawU.size()) && rawU[center + 1] <= uj) ++center;
    hints[j] = center;
  }
  PolylineDistance rawDistance(rawLine, closed, minCell);
  double worst = measureLargestDistance(dense, hints, rawDistance);
  // Fitted point → spline (hint: the dense segment holding the point's parameter).
  PolylineDistance splineDistance(dense, closed, minCell);
  const int denseSegments = splineDistance.segmentCount();
  hints.resize(n);
  for (int i = 0; i < n; ++i)
    hints[i] = std::min(static_cast<int>(u[i] * samples), denseSegments - 1);
  worst = std::max(worst, measureLargestDistance(pts, hints, splineDistance));
  return worst;
}

}  // namespace

Vec3 BSplineCurve::evaluate(double u) const {
  if (controlPoints.empty()) return Vec3::Zero();
  const BasisRow row = basisRow(*this, u);
  Vec3 p = Vec3::Zero();
  for (int a = 0; a < 4; ++a) p += row.weight[a] * controlPoints[row.index[a]];
  return p;
}

Vec3 BSplineCurve::derivative(double u) const {
  const int k = static_cast<int>(controlPoints.size());
  if (k == 0) return Vec3::Zero();
  if (closed) {
    double x = (u - std::floor(u)) * k;
    int j = static_cast<int>(std::floor(x));
    if (j >= k) j = k - 1;
    double w[4], dw[4];
    uniformWeights(x - j, w, dw);
    Vec3 d = Vec3::Zero();
    for (int i = 0; i < 4; ++i) d += dw[i] * controlPoints[(j + i) % k];
    return d * k;
  }
  // Derivative curve: degree 2 with Q_i = 3 (P_{i+1} − P_i) / (U_{i+4} − U_{i+1}).
  u = std::clamp(u, 0.0, 1.0);
  const int span = findSpan(knots, k, u);
  double N[kP + 1];
  const std::vector<double> U2(knots.begin() + 1, knots.end() - 1);
  // Span in U2 is span − 1; basis functions of degree 2 over control indices span−3 … span−1.
  basisFunctions(U2, span - 1, u, kP - 1, N);
  Vec3 d = Vec3::Zero();
  for (int a = 0; a < kP; ++a) {
    const int i = span - kP + a;
    const double denom = knots[i + kP + 1] - knots[i + 1];
    if (denom > 0.0) d += N[a] * kP * (controlPoints[i + 1] - controlPoints[i]) / denom;
  }
  return d;
}

Polyline resamplePolyline(const Polyline& polyline, double spacing) {
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InvalidInput("point spacing must be positive: " + num(spacing) +
                       " mm; pass a value such as 2");
  }
  Polyline out;
  out.closed = polyline.closed;
  const double length = polyline.length();
  if (polyline.points.size() < 2 || !(length > 0.0)) return polyline;
  const int segments =
      std::max(static_cast<int>(std::ceil(length / spacing - 1e-9)), out.closed ? 3 : 1);
  const int last = out.closed ? segments - 1 : segments;
  for (int i = 0; i <= last; ++i)
    out.points.push_back(evaluatePolylineAt(polyline, length * i / segments));
  if (!out.closed) out.points.back() = polyline.points.back();
  return out;
}

namespace {

/// A fitted piece of a path: its curve, the two-sided deviation measured against its raw part, the
/// rounds it took, and, for a piece kept as a polyline, its vertices.
struct PieceFit {
  BSplineCurve spline;
  double deviation = 0.0;
  int rounds = 0;
  std::vector<Vec3> polyline;  ///< non-empty: the piece is this polyline (exact, C0 at vertices)
};

/// Exact cubic B-spline of an open polyline: each segment a cubic Bézier with control points at
/// thirds, knots of multiplicity 3 at the vertices (C0 there), parameter proportional to arc
/// length.
BSplineCurve makePolylineSpline(const std::vector<Vec3>& vertices) {
  BSplineCurve c;
  c.closed = false;
  const std::size_t m = vertices.size() - 1;
  std::vector<double> cum{0.0};
  for (std::size_t i = 0; i < m; ++i)
    cum.push_back(cum.back() + (vertices[i + 1] - vertices[i]).norm());
  for (int r = 0; r <= kP; ++r) c.knots.push_back(0.0);
  for (std::size_t i = 1; i < m; ++i) {
    for (int r = 0; r < kP; ++r) c.knots.push_back(cum[i] / cum.back());
  }
  for (int r = 0; r <= kP; ++r) c.knots.push_back(1.0);
  c.controlPoints.push_back(vertices.front());
  for (std::size_t i = 0; i < m; ++i) {
    const Vec3& a = vertices[i];
    const Vec3& b = vertices[i + 1];
    c.controlPoints.push_back(a + (b - a) / 3.0);
    c.controlPoints.push_back(a + (b - a) * (2.0 / 3.0));
    c.controlPoints.push_back(b);
  }
  return c;
}

/// The rounds of the uniform-knot fit (see the header) of the points `pts` (parameters `u`) of one
/// piece, measured against its raw polyline `rawLine` (vertex parameters `rawU`, arc length
/// `length`). Returns the best round; its deviation may exceed the tolerance.
PieceFit fitUniformRounds(std::vector<Vec3> pts, std::vector<double> u,
                          const std::vector<Vec3>& rawLine, const std::vector<double>& rawU,
                          bool closed, double length, const PathFitOptions& options) {
  PieceFit best;
  const double minCell = 0.5 * options.tolerance;
  const int minK = 4;
  int n = static_cast<int>(pts.size());
  int maxK = std::max(n, minK);
  int densifications = 0;
  int k = std::clamp(static_cast<int>(std::ceil(length / (8.0 * options.pointSpacing))) + minK,
                     minK, maxK);
  for (;;) {
    const double lambda = k >= maxK ? 0.0 : options.smoothing * static_cast<double>(n) / k;
    BSplineCurve spline = fitControlPoints(pts, u, closed, k, lambda);
    ++best.rounds;
    // Measured against the raw polyline: every raw vertex (merged ones too) to the spline and the
    // spline's samples to the raw polyline.
    const double deviation =
        measureDeviation(spline, rawLine, rawU, rawLine, rawU, closed, minCell);
    if (!std::isfinite(deviation)) {
      throw NumericalFailure("path spline fit is not finite: " + num(deviation) +
                             " mm deviation; check the raw path");
    }
    if (best.spline.empty() || deviation < best.deviation) {
      best.spline = std::move(spline);
      best.deviation = deviation;
    }
    if (deviation <= options.tolerance) break;
    if (k >= maxK) {
      // Even interpolating every data point overshoots between them (sharp corners): sample the
      // raw segments 4× more densely, which allows 4× finer knots, at most twice.
      if (densifications == 2) break;
      ++densifications;
      std::vector<Vec3> dense;
      std::vector<double> du;
      const std::size_t segments = closed ? pts.size() : pts.size() - 1;
      for (std::size_t i = 0; i < segments; ++i) {
        const Vec3& a = pts[i];
        const Vec3& b = pts[(i + 1) % pts.size()];
        const double ub = i + 1 < pts.size() ? u[i + 1] : 1.0;
        for (int j = 0; j < 4; ++j) {
          dense.push_back(a + (b - a) * (j / 4.0));
          du.push_back(u[i] + (ub - u[i]) * (j / 4.0));
        }
      }
      if (!closed) {
        dense.push_back(pts.back());
        du.push_back(1.0);
      }
      pts = std::move(dense);
      u = std::move(du);
      n = static_cast<int>(pts.size());
      maxK = n;
    }
    // Next control-point count: the deviation of a kink the knots cannot follow shrinks about in
    // proportion to the knot spacing, so grow by the deviation / tolerance ratio, at least by half
    // and at most 4× (a smooth stretch converges faster than that). A jump to interpolation stops
    // at 2/3 of it first (interpolating unevenly spaced points can overshoot where less does not).
    const double growth = std::clamp(deviation / options.tolerance, 1.5, 4.0);
    int next = std::max(k + 1, static_cast<int>(std::ceil(k * growth)));
    const int beforeInterpolation = 2 * maxK / 3;
    if (next >= maxK && k < beforeInterpolation) next = beforeInterpolation;
    k = std::min(maxK, next);
  }
  return best;
}

/// Marks the vertices kept for fitting: a vertex closer than `mergeDistance` to the last kept one
/// is dropped (open: the end point is always kept, replacing a kept vertex within the distance
/// before it; closed: a last vertex within the distance of the first is dropped). Falls back to
/// keeping every vertex if fewer than 2 (open) or 3 (closed) would remain.
std::vector<char> markKeptVertices(const std::vector<Vec3>& pts, bool closed,
                                   double mergeDistance) {
  const std::size_t n = pts.size();
  std::vector<char> keep(n, 0);
  const double d2 = mergeDistance * mergeDistance;
  std::size_t last = 0;
  keep[0] = 1;
  std::size_t count = 1;
  for (std::size_t i = 1; i < n; ++i) {
    if ((pts[i] - pts[last]).squaredNorm() > d2) {
      keep[i] = 1;
      last = i;
      ++count;
    }
  }
  if (!closed && !keep[n - 1]) {
    if (last != 0) {
      keep[last] = 0;
      --count;
    }
    keep[n - 1] = 1;
    ++count;
  }
  if (closed && last != 0 && (pts[last] - pts[0]).squaredNorm() <= d2) {
    keep[last] = 0;
    --count;
  }
  if (count < (closed ? 3u : 2u)) keep.assign(n, 1);
  return keep;
}

/// Corners of a raw line (see the header): kept vertices where the chords from the points an arc
/// length `reach` before and after turn by more than `angle` (radians), and that turn the most
/// within `reach` of arc length on either side (ties: the first). Open lines: interior vertices,
/// the chords clamped at the ends. Returns vertex indices in order. O(n) plus, per candidate, the
/// candidates within `reach`.
std::vector<std::size_t> findCorners(const std::vector<Vec3>& pts, const std::vector<double>& cum,
                                     const std::vector<char>& keep, bool closed, double reach,
                                     double angle) {
  const std::size_t n = pts.size();
  const double length = cum.back();
  std::vector<std::size_t> corners;
  if (!(angle < std::numbers::pi) || (closed && length <= 4.0 * reach)) return corners;
  // The point at arc length s for increasing s (one cursor per stream, so O(n) in all): s may
  // leave [0, length) by up to one length on a closed line (it wraps), and is clamped on an open.
  const std::ptrdiff_t segments = static_cast<std::ptrdiff_t>(cum.size()) - 1;
  struct Cursor {
    std::ptrdiff_t g;  ///< segment index counted over laps (closed: may be negative)
  };
  auto start = [&](std::ptrdiff_t lap) -> double {  // arc length where lap `lap` begins
    return static_cast<double>(lap) * length;
  };
  auto pointAt = [&](Cursor& cursor, double s) -> Vec3 {
    if (!closed) s = std::clamp(s, 0.0, length);
    auto lapOf = [&](std::ptrdiff_t g) {
      return g >= 0 ? g / segments : -((-g + segments - 1) / segments);
    };
    auto segmentEnd = [&](std::ptrdiff_t g) {
      const std::ptrdiff_t lap = lapOf(g);
      return start(lap) + cum[static_cast<std::size_t>(g - lap * segments) + 1];
    };
    const std::ptrdiff_t last = closed ? std::numeric_limits<std::ptrdiff_t>::max() : segments - 1;
    while (cursor.g < last && segmentEnd(cursor.g) <= s) ++cursor.g;
    const std::ptrdiff_t lap = lapOf(cursor.g);
    const std::size_t i = static_cast<std::size_t>(cursor.g - lap * segments);
    const double s0 = start(lap) + cum[i];
    const double len = cum[i + 1] - cum[i];
    const double t = len > 0.0 ? std::clamp((s - s0) / len, 0.0, 1.0) : 0.0;
    return pts[i] + (pts[(i + 1) % n] - pts[i]) * t;
  };
  const double cosAngle = std::cos(angle);
  std::vector<std::pair<std::size_t, double>> candidates;  // vertex, turn (radians)
  Cursor behind{closed ? -segments : 0}, ahead{0};
  for (std::size_t i = closed ? 0 : 1; i < (closed ? n : n - 1); ++i) {
    const Vec3 toVertex = pts[i] - pointAt(behind, cum[i] - reach);
    const Vec3 fromVertex = pointAt(ahead, cum[i] + reach) - pts[i];
    if (!keep[i]) continue;
    const double dot = toVertex.dot(fromVertex);
    if (dot >= cosAngle * toVertex.norm() * fromVertex.norm()) continue;  // turn ≤ angle
    const double turn = std::atan2(toVertex.cross(fromVertex).norm(), dot);
    if (turn > angle) candidates.emplace_back(i, turn);
  }
  const std::size_t c = candidates.size();
  auto arcBetween = [&](std::size_t a, std::size_t b) {
    const double d = std::abs(cum[b] - cum[a]);
    return closed ? std::min(d, length - d) : d;
  };
  for (std::size_t j = 0; j < c; ++j) {
    const auto [i, turn] = candidates[j];
    bool best = true;
    // Neighbouring candidates within `reach`, ahead and behind (wrapping for closed lines).
    for (int dir = -1; dir <= 1 && best; dir += 2) {
      for (std::size_t step = 1; step < c; ++step) {
        std::size_t o;
        if (closed) {
          o = (j + c + dir * static_cast<std::ptrdiff_t>(step % c)) % c;
        } else {
          const std::ptrdiff_t q =
              static_cast<std::ptrdiff_t>(j) + dir * static_cast<std::ptrdiff_t>(step);
          if (q < 0 || q >= static_cast<std::ptrdiff_t>(c)) break;
          o = static_cast<std::size_t>(q);
        }
        if (arcBetween(i, candidates[o].first) > reach) break;
        const double other = candidates[o].second;
        if (other > turn || (other == turn && o < j)) {
          best = false;
          break;
        }
      }
    }
    if (best) corners.push_back(i);
  }
  return corners;
}

/// Resamples a fitted spline piece at equal arc length with at most `spacing` between points and
/// halves every interval whose chord leaves the spline by more than `chordTolerance`. Appends the
/// points (open: both ends; closed: without repeating the first); raises `chordError`.
void resampleSpline(const BSplineCurve& c, double spacing, double chordTolerance,
                    std::vector<Vec3>& out, double& chordError) {
  const bool closed = c.closed;
  const int tableCount = std::max(64 * static_cast<int>(c.controlPoints.size()), 1024);
  std::vector<double> tu(tableCount + 1), ts(tableCount + 1);
  Vec3 prev = c.evaluate(0.0);
  ts[0] = 0.0;
  for (int i = 0; i <= tableCount; ++i) {
    tu[i] = static_cast<double>(i) / tableCount;
    if (i == 0) continue;
    const Vec3 p = c.evaluate(closed && i == tableCount ? 0.0 : tu[i]);
    ts[i] = ts[i - 1] + (p - prev).norm();
    prev = p;
  }
  const double splineLength = ts.back();
  auto paramAt = [&](double s) {
    const auto it = std::upper_bound(ts.begin(), ts.end(), s);
    const int i = std::clamp(static_cast<int>(it - ts.begin()) - 1, 0, tableCount - 1);
    const double len = ts[i + 1] - ts[i];
    const double t = len > 0.0 ? (s - ts[i]) / len : 0.0;
    return tu[i] + t * (tu[i + 1] - tu[i]);
  };
  const int segments =
      std::max(static_cast<int>(std::ceil(splineLength / spacing - 1e-9)), closed ? 3 : 1);
  std::vector<double> params;
  for (int i = 0; i <= segments; ++i)
    params.push_back(i == segments ? 1.0 : paramAt(splineLength * i / segments));
  // Chord error of an interval: largest distance of interior spline samples from the chord.
  auto intervalChordError = [&](double ua, double ub) {
    const Vec3 a = c.evaluate(ua), b = c.evaluate(ub);
    double worst = 0.0;
    for (int j = 1; j < 8; ++j) {
      const double uj = ua + (ub - ua) * j / 8.0;
      worst = std::max(worst, pointSegmentDistance(c.evaluate(uj), a, b));
    }
    return worst;
  };
  std::vector<double> refined{params.front()};
  for (std::size_t i = 0; i + 1 < params.size(); ++i) {
    // Halve the interval until its chord is within the tolerance (depth-limited).
    std::vector<std::pair<double, int>> stack{{params[i + 1], 0}};
    double ua = params[i];
    while (!stack.empty()) {
      const auto [ub, depth] = stack.back();
      const double e = intervalChordError(ua, ub);
      if (e > chordTolerance && depth < 30) {
        stack.push_back({0.5 * (ua + ub), depth + 1});
        continue;
      }
      chordError = std::max(chordError, e);
      refined.push_back(ub);
      ua = ub;
      stack.pop_back();
    }
  }
  const std::size_t count = closed ? refined.size() - 1 : refined.size();
  for (std::size_t i = 0; i < count; ++i) out.push_back(c.evaluate(refined[i]));
}

/// Appends an open polyline with every segment longer than `spacing` split evenly (both ends).
void resampleVertices(const std::vector<Vec3>& vertices, double spacing, std::vector<Vec3>& out) {
  out.push_back(vertices.front());
  for (std::size_t i = 0; i + 1 < vertices.size(); ++i) {
    const Vec3& a = vertices[i];
    const Vec3& b = vertices[i + 1];
    const int parts = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing - 1e-9)));
    for (int q = 1; q < parts; ++q) out.push_back(a + (b - a) * (static_cast<double>(q) / parts));
    out.push_back(b);
  }
}

/// One clamped spline of open pieces joined end to start (knots of multiplicity 3 at the joins,
/// C0 there), each piece's parameter range proportional to its raw arc length `lengths`.
BSplineCurve joinPieces(const std::vector<BSplineCurve>& pieces,
                        const std::vector<double>& lengths) {
  if (pieces.size() == 1) return pieces.front();
  double total = 0.0;
  for (const double l : lengths) total += l;
  BSplineCurve c;
  c.closed = false;
  for (int r = 0; r <= kP; ++r) c.knots.push_back(0.0);
  double start = 0.0;
  for (std::size_t j = 0; j < pieces.size(); ++j) {
    const BSplineCurve& p = pieces[j];
    const double end = j + 1 == pieces.size() ? 1.0 : start + lengths[j] / total;
    for (std::size_t q = kP + 1; q + kP + 1 < p.knots.size(); ++q)
      c.knots.push_back(start + (end - start) * p.knots[q]);
    const int repeat = j + 1 == pieces.size() ? kP + 1 : kP;
    for (int r = 0; r < repeat; ++r) c.knots.push_back(end);
    c.controlPoints.insert(c.controlPoints.end(), p.controlPoints.begin() + (j == 0 ? 0 : 1),
                           p.controlPoints.end());
    start = end;
  }
  return c;
}

void checkFitOptions(const PathFitOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance)) {
    throw InvalidInput("fit tolerance must be positive: " + num(options.tolerance) +
                       " mm; pass a value such as 0.05");
  }
  if (!(options.pointSpacing > 0.0) || !std::isfinite(options.pointSpacing)) {
    throw InvalidInput("point spacing must be positive: " + num(options.pointSpacing) +
                       " mm; pass a value such as 2");
  }
  if (!(options.smoothing >= 0.0) || !std::isfinite(options.smoothing)) {
    throw InvalidInput("fit smoothing must be non-negative: " + num(options.smoothing) +
                       "; pass a value such as 1e-4 or 0");
  }
  if (!(options.cornerAngle > 0.0) || !std::isfinite(options.cornerAngle)) {
    throw InvalidInput("corner angle must be positive: " + num(options.cornerAngle) +
                       " degrees; pass a value such as 30, or 180 for no corners");
  }
}

/// The raw path's points without repeated consecutive ones (closed: nor the first repeated at
/// the end); throws when they are not finite or too few.
std::vector<Vec3> collectDistinctPoints(const Polyline& raw) {
  std::vector<Vec3> pts;
  for (const Vec3& p : raw.points) {
    if (!p.allFinite()) {
      throw InvalidInput("raw path has a non-finite point; pass finite coordinates");
    }
    if (pts.empty() || (p - pts.back()).squaredNorm() > 0.0) pts.push_back(p);
  }
  const bool closed = raw.closed;
  if (closed && pts.size() > 1 && (pts.back() - pts.front()).squaredNorm() == 0.0) pts.pop_back();
  const std::size_t minPoints = closed ? 3 : 2;
  if (pts.size() < minPoints) {
    throw InvalidInput(
        std::string("raw path has too few distinct points: ") + std::to_string(pts.size()) +
        (closed ? " (closed needs 3)" : " (open needs 2)") + "; drop the path or pass more points");
  }
  return pts;
}

/// A ring without corners as one periodic spline over the whole ring; false (result.fitRounds
/// set) when even the densified interpolation does not follow it within the tolerance.
bool fitRing(const std::vector<Vec3>& pts, const std::vector<double>& cum,
             const std::vector<char>& keep, const PathFitOptions& options, double chordTolerance,
             PathFitResult& result) {
  const std::size_t n = pts.size();
  const double length = cum.back();
  std::vector<double> rawU(n);
  for (std::size_t i = 0; i < n; ++i) rawU[i] = cum[i] / length;
  std::vector<Vec3> fitPts;
  std::vector<double> fitU;
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    fitPts.push_back(pts[i]);
    fitU.push_back(rawU[i]);
  }
  PieceFit fit =
      fitUniformRounds(std::move(fitPts), std::move(fitU), pts, rawU, true, length, options);
  result.fitRounds = fit.rounds;
  if (!(fit.deviation <= options.tolerance)) return false;
  result.fitDeviation = fit.deviation;
  result.spline = std::move(fit.spline);
  resampleSpline(result.spline, options.pointSpacing, chordTolerance, result.points.points,
                 result.chordError);
  result.points.closed = true;
  return true;
}

/// Piece ends: the corners (open lines: also the end points; closed: around to the first
/// corner again, index + n).
std::vector<std::size_t> findPieceBreaks(const std::vector<std::size_t>& corners, bool closed,
                                         std::size_t n) {
  std::vector<std::size_t> breaks;
  if (!closed) breaks.push_back(0);
  breaks.insert(breaks.end(), corners.begin(), corners.end());
  if (!closed) {
    breaks.push_back(n - 1);
  } else {
    breaks.push_back(corners.front() + n);
  }
  return breaks;
}

/// One piece between two breaks: its raw points (`rawLine`, arc parameters `rawU` in [0, 1],
/// raw length `pieceLength`) fitted by an open clamped spline through its two end vertices, or
/// kept as the (merged) raw vertices when no spline is within the tolerance.
PieceFit fitPiece(const std::vector<Vec3>& pts, const std::vector<char>& keep, std::size_t from,
                  std::size_t to, const PathFitOptions& options, std::vector<Vec3>& rawLine,
                  double& pieceLength) {
  const std::size_t n = pts.size();
  std::vector<double> rawU{0.0};
  std::vector<Vec3> fitPts;
  std::vector<double> fitU;
  for (std::size_t q = from; q <= to; ++q) {
    const Vec3& p = pts[q % n];
    if (!rawLine.empty()) rawU.push_back(rawU.back() + (p - rawLine.back()).norm());
    rawLine.push_back(p);
  }
  pieceLength = rawU.back();
  for (double& x : rawU) x /= pieceLength;
  for (std::size_t q = from; q <= to; ++q) {
    if (!keep[q % n]) continue;
    fitPts.push_back(pts[q % n]);
    fitU.push_back(rawU[q - from]);
  }
  PieceFit fit;
  if (fitPts.size() >= 4) {
    fit = fitUniformRounds(fitPts, fitU, rawLine, rawU, false, pieceLength, options);
  }
  if (fit.spline.empty() || fit.deviation > options.tolerance) {
    // Too few points for a cubic, or no spline within the tolerance: keep the (merged) raw
    // vertices; the deviation of that polyline is measured like a spline's.
    fit.spline = makePolylineSpline(fitPts);
    fit.deviation =
        measureDeviation(fit.spline, rawLine, rawU, rawLine, rawU, false, 0.5 * options.tolerance);
    fit.polyline = std::move(fitPts);
  }
  return fit;
}

/// Pieces between corners, each an open clamped spline, their points joined into the result.
void fitPieces(const std::vector<Vec3>& pts, const std::vector<char>& keep,
               const std::vector<std::size_t>& breaks, bool closed, const PathFitOptions& options,
               double chordTolerance, PathFitResult& result) {
  std::vector<BSplineCurve> splines;
  std::vector<double> pieceLengths;
  std::vector<Vec3>& out = result.points.points;
  for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
    std::vector<Vec3> rawLine;
    double pieceLength = 0.0;
    PieceFit fit = fitPiece(pts, keep, breaks[b], breaks[b + 1], options, rawLine, pieceLength);
    result.fitRounds += fit.rounds;
    result.fitDeviation = std::max(result.fitDeviation, fit.deviation);
    // Points of this piece, its first point shared with the previous piece's last.
    std::vector<Vec3> piecePoints;
    if (!fit.polyline.empty()) {
      resampleVertices(fit.polyline, options.pointSpacing, piecePoints);
    } else {
      resampleSpline(fit.spline, options.pointSpacing, chordTolerance, piecePoints,
                     result.chordError);
    }
    piecePoints.front() = rawLine.front();
    piecePoints.back() = rawLine.back();
    if (b > 0) {
      result.corners.push_back(out.size() - 1);  // the previous piece's last point
    } else if (closed) {
      result.corners.push_back(0);
    }
    out.insert(out.end(), piecePoints.begin() + (b == 0 ? 0 : 1), piecePoints.end());
    splines.push_back(std::move(fit.spline));
    pieceLengths.push_back(pieceLength);
  }
  if (closed) out.pop_back();  // the first corner again
  result.points.closed = closed;
  result.spline = joinPieces(splines, pieceLengths);
}

}  // namespace

PathFitResult fitPath(const Polyline& raw, const PathFitOptions& options) {
  checkFitOptions(options);
  const double chordTolerance =
      options.chordTolerance > 0.0 ? options.chordTolerance : options.tolerance;
  const std::vector<Vec3> pts = collectDistinctPoints(raw);
  const bool closed = raw.closed;
  const std::vector<double> cum = computeCumulativeLengths(Polyline{pts, closed});
  const std::vector<char> keep = markKeptVertices(pts, closed, kMergeFraction * options.tolerance);
  std::vector<std::size_t> corners =
      findCorners(pts, cum, keep, closed, kCornerReachFactor * options.tolerance,
                  options.cornerAngle * std::numbers::pi / 180.0);
  PathFitResult result;
  if (closed && corners.empty()) {
    if (fitRing(pts, cum, keep, options, chordTolerance, result)) return result;
    // Not even the densified interpolation follows it: one open piece from vertex 0 around, kept
    // as a polyline below if it fails again.
    corners.push_back(0);
  }
  fitPieces(pts, keep, findPieceBreaks(corners, closed, pts.size()), closed, options,
            chordTolerance, result);
  return result;
}

}  // namespace curvedslicer
