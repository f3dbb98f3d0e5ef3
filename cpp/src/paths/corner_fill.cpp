#include "curvedslicer/paths/corner_fill.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "paths_internal.hpp"

namespace curvedslicer {

namespace {

using paths_detail::formatNumber;

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxShrinks = 12;
constexpr double kShrink = 0.75;

void checkOptions(const CornerFillOptions& o) {
  if (!(o.beadSpacing > 0.0) || !std::isfinite(o.beadSpacing)) {
    throw InvalidInput("corner fill bead spacing must be a positive number of mm: " +
                       formatNumber(o.beadSpacing) + "; pass e.g. 3.7");
  }
  if (!std::isfinite(o.maxOverdeposit)) {
    throw InvalidInput("corner fill overdeposit bound must be a finite number of mm: " +
                       formatNumber(o.maxOverdeposit) + "; pass e.g. " +
                       formatNumber(0.25 * o.beadSpacing) + ", or a negative value for s/4");
  }
  if (!(o.maxCornerAngle > 0.0 && o.maxCornerAngle < 180.0)) {
    throw InvalidInput("corner fill angle must lie in (0, 180) degrees: " +
                       formatNumber(o.maxCornerAngle) + "; pass e.g. 85");
  }
  if (!std::isfinite(o.cornerArm)) {
    throw InvalidInput(
        "corner fill arm must be a finite number of mm: " + formatNumber(o.cornerArm) +
        "; pass e.g. " + formatNumber(0.25 * o.beadSpacing) + ", or a negative value for s/4");
  }
}

void checkBead(const CornerFillBead& b, std::size_t k) {
  if (b.line == nullptr || b.normals == nullptr || b.normals->size() != b.line->points.size() ||
      (b.widths != nullptr && !b.widths->empty() && b.widths->size() != b.line->points.size())) {
    throw InvalidInput("corner fill bead " + std::to_string(k) +
                       " lacks one normal (and width, when widths are given) per point; pass "
                       "per-point normals and widths");
  }
}

/// The ring's arc length at each point (closed: the closing segment ends at length()).
std::vector<double> arcLengths(const Polyline& line) {
  std::vector<double> s(line.points.size(), 0.0);
  for (std::size_t i = 1; i < s.size(); ++i) {
    s[i] = s[i - 1] + (line.points[i] - line.points[i - 1]).norm();
  }
  return s;
}

/// Arc distance between points i and j (closed: the shorter way round).
double arcDistance(const std::vector<double>& s, double total, bool closed, std::size_t i,
                   std::size_t j) {
  const double d = std::abs(s[i] - s[j]);
  return closed ? std::min(d, total - d) : d;
}

/// The point `arm` of arc length before (step −1) or after (step +1) point i; -1 when an open
/// line ends first or the walk comes round.
long armPoint(const Polyline& line, std::size_t i, int step, double arm) {
  const long n = static_cast<long>(line.points.size());
  long j = static_cast<long>(i);
  double walked = 0.0;
  for (long k = 0; k < n - 1; ++k) {
    const long next = j + step;
    if (!line.closed && (next < 0 || next >= n)) return k == 0 ? -1 : j;
    const long wrapped = (next + n) % n;
    walked += (line.points[wrapped] - line.points[j]).norm();
    j = wrapped;
    if (walked >= arm) return j;
  }
  return -1;
}

Vec3 tangential(const Vec3& v, const Vec3& normal) {
  return v - v.dot(normal) * normal;
}

/// A corner of a ring: its point, turn (radians) and the outside of the turn.
struct Corner {
  std::size_t index = 0;
  double turn = 0.0;
  Vec3 outside = Vec3::Zero();
};

std::vector<Corner> findCorners(const Polyline& line, const std::vector<Vec3>& normals, double arm,
                                double minTurn) {
  std::vector<Corner> candidates;
  for (std::size_t i = 0; i < line.points.size(); ++i) {
    const long a = armPoint(line, i, -1, arm);
    const long b = armPoint(line, i, +1, arm);
    if (a < 0 || b < 0 || a == b) continue;
    const Vec3& c = line.points[i];
    const Vec3 u1 = tangential(c - line.points[a], normals[i]);
    const Vec3 u2 = tangential(line.points[b] - c, normals[i]);
    if (!(u1.norm() > 1e-9 && u2.norm() > 1e-9)) continue;
    const Vec3 d1 = u1.normalized(), d2 = u2.normalized();
    const double turn = std::acos(std::clamp(d1.dot(d2), -1.0, 1.0));
    const Vec3 out = d1 - d2;
    if (turn < minTurn || !(out.norm() > 1e-9)) continue;
    candidates.push_back({i, turn, out.normalized()});
  }
  // The sharpest first (ties by index); a corner within `arm` of a sharper one is the same.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Corner& x, const Corner& y) { return x.turn > y.turn; });
  const std::vector<double> s = arcLengths(line);
  const double total = line.length();
  std::vector<Corner> corners;
  for (const Corner& c : candidates) {
    const bool near = std::any_of(corners.begin(), corners.end(), [&](const Corner& k) {
      return arcDistance(s, total, line.closed, c.index, k.index) < arm;
    });
    if (!near) corners.push_back(c);
  }
  std::sort(corners.begin(), corners.end(),
            [](const Corner& x, const Corner& y) { return x.index < y.index; });
  return corners;
}

/// How a corner point moves: the dip point Q and its sample, and the dip depth.
struct Dip {
  EdgeSample q;
  double depth = 0.0;
  double overdeposit = 0.0;
};

/// Step 2–3 of the file comment for one corner; no value when the point stays.
std::optional<Dip> planDip(const Polyline& line, const Corner& corner, double halfWidth,
                           double bound, const EdgeSampler& sample) {
  const Vec3& c = line.points[corner.index];
  const double e0 = sample(c).edgeDistance;
  if (!std::isfinite(e0) || std::abs(e0 - halfWidth) > 0.25 * halfWidth) return std::nullopt;
  const double sinHalf = std::cos(0.5 * corner.turn);  // sin(θ/2), θ = π − turn
  if (!(sinHalf > 1e-3)) return std::nullopt;
  double depth = std::min(halfWidth * (1.0 / sinHalf - 1.0), bound / sinHalf);
  for (int k = 0; k <= kMaxShrinks && depth > 1e-6; ++k, depth *= kShrink) {
    Dip dip;
    dip.q = sample(c + depth * corner.outside);
    dip.depth = depth;
    const double e = dip.q.edgeDistance;
    if (!std::isfinite(e) || e > e0 - 0.5 * depth * sinHalf) return std::nullopt;  // not convex
    dip.overdeposit = halfWidth - e;
    if (dip.overdeposit <= bound + 1e-9 * halfWidth) return dip;  // rounding at the bound
  }
  return std::nullopt;
}

/// A point on the chord from the corner towards `to`, `t` mm away, put on the surface.
EdgeSample chordPoint(const Vec3& corner, const Vec3& to, double t, const EdgeSampler& sample) {
  return sample(corner + t * (to - corner).normalized());
}

CornerFillResult dipBead(const CornerFillBead& bead, const EdgeSampler& sample, double s,
                         double bound, double arm, double minTurn) {
  CornerFillResult result;
  Polyline& line = *bead.line;
  std::vector<Vec3>& normals = *bead.normals;
  const bool hasWidths = bead.widths != nullptr && !bead.widths->empty();
  const std::size_t n = line.points.size();
  if (n < 3) return result;
  const std::vector<Corner> corners = findCorners(line, normals, arm, minTurn);
  if (corners.empty()) return result;
  Polyline out;
  out.closed = line.closed;
  std::vector<Vec3> outNormals;
  std::vector<double> outWidths;
  auto push = [&](const Vec3& p, const Vec3& nrm, double w) {
    out.points.push_back(p);
    outNormals.push_back(nrm);
    if (hasWidths) outWidths.push_back(w);
  };
  std::size_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = hasWidths ? (*bead.widths)[i] : s;
    const bool isCorner = next < corners.size() && corners[next].index == i;
    std::optional<Dip> dip;
    if (isCorner) dip = planDip(line, corners[next++], 0.5 * w, bound, sample);
    if (!dip) {
      push(line.points[i], normals[i], w);
      continue;
    }
    const Vec3& c = line.points[i];
    const Vec3& before = line.points[(i + n - 1) % n];
    const Vec3& after = line.points[(i + 1) % n];
    const double t = std::min({dip->depth, 0.5 * (c - before).norm(), 0.5 * (after - c).norm()});
    const EdgeSample a = chordPoint(c, before, t, sample);
    const EdgeSample b = chordPoint(c, after, t, sample);
    push(a.point, a.normal, w);
    push(dip->q.point, dip->q.normal, w);
    push(b.point, b.normal, w);
    ++result.corners;
    result.largestOverdeposit = std::max(result.largestOverdeposit, dip->overdeposit);
    result.largestDip = std::max(result.largestDip, dip->depth);
  }
  if (result.corners == 0) return result;
  line = std::move(out);
  normals = std::move(outNormals);
  if (hasWidths) *bead.widths = std::move(outWidths);
  return result;
}

}  // namespace

CornerFillResult fillRingCorners(const std::vector<CornerFillBead>& beads,
                                 const EdgeSampler& sample, const CornerFillOptions& options) {
  checkOptions(options);
  for (std::size_t k = 0; k < beads.size(); ++k) checkBead(beads[k], k);
  const double s = options.beadSpacing;
  const double bound = options.maxOverdeposit < 0.0 ? 0.25 * s : options.maxOverdeposit;
  const double arm = options.cornerArm < 0.0 ? 0.25 * s : options.cornerArm;
  const double minTurn = (180.0 - options.maxCornerAngle) * kPi / 180.0;
  CornerFillResult total;
  for (const CornerFillBead& bead : beads) {
    const CornerFillResult r = dipBead(bead, sample, s, bound, arm, minTurn);
    total.corners += r.corners;
    total.largestOverdeposit = std::max(total.largestOverdeposit, r.largestOverdeposit);
    total.largestDip = std::max(total.largestDip, r.largestDip);
  }
  return total;
}

}  // namespace curvedslicer
