// Smoothing cubic B-spline fit and resampling of raw paths (see curvedslicer/paths/path_fit.hpp).
#include "curvedslicer/paths/path_fit.hpp"

#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "curvedslicer/core/error.hpp"
#include "segment_grid.hpp"

namespace curvedslicer {

namespace {

constexpr int kP = BSplineCurve::kDegree;

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

PathFitResult fitPath(const Polyline& raw, const PathFitOptions& options) {
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
  const double chordTolerance =
      options.chordTolerance > 0.0 ? options.chordTolerance : options.tolerance;
  // Drop repeated consecutive points.
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
  Polyline clean{pts, closed};
  const std::vector<double> cum = computeCumulativeLengths(clean);
  const double length = cum.back();
  std::vector<double> u(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) u[i] = cum[i] / length;

  // Distances to the raw polyline: its geometry stays the same when it is densified below.
  const std::vector<Vec3> rawLine = pts;
  const std::vector<double> rawU = u;
  const double minCell = 0.5 * options.tolerance;

  PathFitResult result;
  const int minK = 4;
  int n = static_cast<int>(pts.size());
  int maxK = std::max(n, minK);
  int densifications = 0;
  int k = std::clamp(static_cast<int>(std::ceil(length / (8.0 * options.pointSpacing))) + minK,
                     minK, maxK);
  for (;;) {
    const double lambda = k >= maxK ? 0.0 : options.smoothing * static_cast<double>(n) / k;
    BSplineCurve spline = fitControlPoints(pts, u, closed, k, lambda);
    ++result.fitRounds;
    // Measured against the raw polyline (its vertices and the spline's distance to it).
    const double deviation = measureDeviation(spline, pts, u, rawLine, rawU, closed, minCell);
    if (!std::isfinite(deviation)) {
      throw NumericalFailure("path spline fit is not finite: " + num(deviation) +
                             " mm deviation; check the raw path");
    }
    if (result.spline.empty() || deviation < result.fitDeviation) {
      result.spline = std::move(spline);
      result.fitDeviation = deviation;
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
    k = std::min(maxK, std::max(k + 1, k + k / 2));
  }

  // Resampling: arc-length table of the spline.
  const BSplineCurve& c = result.spline;
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
  const int segments = std::max(
      static_cast<int>(std::ceil(splineLength / options.pointSpacing - 1e-9)), closed ? 3 : 1);
  std::vector<double> params;
  for (int i = 0; i <= segments; ++i)
    params.push_back(i == segments ? 1.0 : paramAt(splineLength * i / segments));
  // Chord error of an interval: largest distance of interior spline samples from the chord.
  auto chordError = [&](double ua, double ub) {
    const Vec3 a = c.evaluate(ua), b = c.evaluate(ub);
    double worst = 0.0;
    for (int j = 1; j < 8; ++j) {
      const double uj = ua + (ub - ua) * j / 8.0;
      worst = std::max(worst, pointSegmentDistance(c.evaluate(uj), a, b));
    }
    return worst;
  };
  std::vector<double> refined{params.front()};
  result.chordError = 0.0;
  for (std::size_t i = 0; i + 1 < params.size(); ++i) {
    // Halve the interval until its chord is within the tolerance (depth-limited).
    std::vector<std::pair<double, int>> stack{{params[i + 1], 0}};
    double ua = params[i];
    while (!stack.empty()) {
      const auto [ub, depth] = stack.back();
      const double e = chordError(ua, ub);
      if (e > chordTolerance && depth < 30) {
        stack.push_back({0.5 * (ua + ub), depth + 1});
        continue;
      }
      result.chordError = std::max(result.chordError, e);
      refined.push_back(ub);
      ua = ub;
      stack.pop_back();
    }
  }
  result.points.closed = closed;
  const std::size_t count = closed ? refined.size() - 1 : refined.size();
  for (std::size_t i = 0; i < count; ++i) result.points.points.push_back(c.evaluate(refined[i]));
  if (!closed) {
    result.points.points.front() = pts.front();
    result.points.points.back() = pts.back();
  }
  return result;
}

}  // namespace curvedslicer
