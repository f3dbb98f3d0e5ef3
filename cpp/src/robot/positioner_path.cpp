// Positioner angles along one path (internal to planMotion). Phases: merge and sample, exact
// alignment per point (eq. 16, both branches), the a2 tube (where a tilt that compensates keeps
// V within the band angle of gravity), a rate-bounded a2 through the tube, points inserted where
// a2 still steps more than maxA2Step, the tilt for the chosen a2.
#include "positioner_path.hpp"

#include <algorithm>
#include <cmath>

namespace curvedslicer::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

double angleBetween(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// a + 2πk nearest `reference` within [limit.min, limit.max] (endless: no range); false if no
/// shift fits (then the nearest to the range).
bool fitRotation(double& a, const PositionerAxis& axis, double reference) {
  a = unwrapNear(a, reference);
  if (axis.endless) return true;
  double best = a;
  double bestCost = kInf;
  bool found = false;
  for (int k = -3; k <= 3; ++k) {
    const double c = a + k * kTwoPi;
    const bool inside = axis.limit.contains(c);
    const double cost =
        inside ? std::abs(c - reference) : 1e6 + std::max(axis.limit.min - c, c - axis.limit.max);
    if (cost < bestCost) {
      bestCost = cost;
      best = c;
      found = inside;
    }
  }
  a = best;
  return found;
}

double clampTilt(double a1, const PositionerAxis& tilt, bool& clamped) {
  const double c = std::clamp(a1, tilt.limit.min, tilt.limit.max);
  clamped = c != a1;
  return c;
}

/// The feasible pose of least residual when no exact alignment lies within the limits: tilt at
/// a limit (with the best rotation), rotation at a limit (with the best tilt), or a branch.
void chooseLeastResidual(const PositionerDescription& pos, const Vec3& gravity, AngleSample& s,
                         double refA1, double refA2) {
  double bestResidual = kInf;
  double bestA1 = s.a1, bestA2 = s.a2;
  std::uint32_t bestFlags = 0;
  auto consider = [&](double a1, double a2, std::uint32_t flags) {
    bool clamped = false;
    a1 = clampTilt(a1, pos.tilt, clamped);
    if (clamped) flags |= kMotionTiltLimited;
    if (!fitRotation(a2, pos.rotation, refA2)) {
      a2 = std::clamp(a2, pos.rotation.limit.min, pos.rotation.limit.max);
      flags |= kMotionRotationLimited;
    }
    const double r = computeGravityResidual(pos, s.v, gravity, a1, a2);
    const double cost = r + 1e-6 * (std::abs(a1 - refA1) + std::abs(a2 - refA2));
    if (cost < bestResidual) {
      bestResidual = cost;
      bestA1 = a1;
      bestA2 = a2;
      bestFlags = flags;
    }
  };
  for (double a1 : {pos.tilt.limit.min, pos.tilt.limit.max}) {
    consider(a1, optimalRotationForTilt(pos, s.v, gravity, a1), kMotionTiltLimited);
  }
  if (!pos.rotation.endless) {
    for (double a2 : {pos.rotation.limit.min, pos.rotation.limit.max}) {
      consider(optimalTiltForRotation(pos, s.v, gravity, a2), a2, kMotionRotationLimited);
    }
  }
  for (int b = 0; b < 2; ++b) consider(s.align.branches[b].a1, s.align.branches[b].a2, 0);
  s.a1 = bestA1;
  s.a2 = bestA2;
  s.flags |= bestFlags;
}

/// Chooses the branch and unwrapping nearest the reference within the positioner limits (or
/// the pose of least residual, then `fixed`). Sets a1, a2 and exactA2.
void chooseAngles(const PositionerDescription& pos, const Vec3& gravity, AngleSample& s,
                  double refA1, double refA2, bool haveRef, const MotionOptions& options) {
  double bestCost = kInf;
  bool bestFeasible = false;
  for (int b = 0; b < 2; ++b) {
    double a1 = s.align.branches[b].a1;
    double a2 = s.align.branches[b].a2;
    const bool rotOk = fitRotation(a2, pos.rotation, refA2);
    const bool feasible = rotOk && pos.tilt.limit.contains(a1) && s.align.feasible;
    double cost = haveRef ? std::abs(a1 - refA1) + std::abs(a2 - refA2)
                          : std::abs(a2 - refA2) +
                                ((options.preferPositiveTilt == (a1 >= 0.0)) ? 0.0 : 100.0);
    if (!feasible) cost += 1e6;
    if (cost < bestCost) {
      bestCost = cost;
      bestFeasible = feasible;
      s.a1 = a1;
      s.a2 = a2;
    }
  }
  if (!bestFeasible) {
    chooseLeastResidual(pos, gravity, s, refA1, refA2);
    s.fixed = true;
  }
  s.exactA2 = s.a2;
}

/// With an endless rotation either branch may continue the previous exact a2: the nearer one
/// (a2 then moves continuously while the tilt changes sign; a tilt that compensates makes the
/// choice free of cost).
void continueExactA2(const PositionerDescription& pos, AngleSample& s, double previousExact) {
  if (!pos.rotation.endless || s.fixed) return;
  double best = unwrapNear(s.exactA2, previousExact);
  for (int b = 0; b < 2; ++b) {
    if (!pos.tilt.limit.contains(s.align.branches[b].a1)) continue;
    const double c = unwrapNear(s.align.branches[b].a2, previousExact);
    if (std::abs(c - previousExact) < std::abs(best - previousExact) - 1e-12) best = c;
  }
  s.exactA2 = best;
}

/// Tilt for a prescribed rotation, clamped to its limits.
void tiltForRotation(const PositionerDescription& pos, const Vec3& gravity, AngleSample& s,
                     double refA1) {
  double a1 = unwrapNear(optimalTiltForRotation(pos, s.v, gravity, s.a2), refA1);
  if (!pos.tilt.limit.contains(a1)) {
    const double other = a1 + (a1 > 0 ? -kTwoPi : kTwoPi);
    if (pos.tilt.limit.contains(other)) a1 = other;
  }
  bool clamped = false;
  a1 = clampTilt(a1, pos.tilt, clamped);
  if (clamped) s.flags |= kMotionTiltLimited;
  s.a1 = a1;
}

/// Gaussian smoothing of V along the path (arc length), bounded deviation.
std::vector<Vec3> smoothDepositions(const std::vector<const PathPoint*>& pts, bool closed,
                                    const MotionOptions& options) {
  const std::size_t n = pts.size();
  std::vector<Vec3> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = pts[i]->deposition.normalized();
  if (options.smoothingLength <= 0.0 || n < 3) return out;
  std::vector<double> s(n, 0.0);
  for (std::size_t i = 1; i < n; ++i) {
    s[i] = s[i - 1] + (pts[i]->position - pts[i - 1]->position).norm();
  }
  const double total = closed ? s[n - 1] + (pts[0]->position - pts[n - 1]->position).norm() : 0.0;
  const double sigma = options.smoothingLength;
  const double reach = 3.0 * sigma;
  std::vector<Vec3> original = out;
  auto distance = [&](std::size_t a, std::size_t b) {
    const double d = std::abs(s[a] - s[b]);
    return closed ? std::min(d, total - d) : d;
  };
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 sum = original[i];
    for (int direction : {-1, 1}) {
      for (std::size_t step = 1; step < n; ++step) {
        const long long raw = static_cast<long long>(i) + direction * static_cast<long long>(step);
        if (!closed && (raw < 0 || raw >= static_cast<long long>(n))) break;
        const std::size_t j =
            static_cast<std::size_t>((raw % static_cast<long long>(n) + static_cast<long long>(n)) %
                                     static_cast<long long>(n));
        if (closed && 2 * step > n) break;  // the other direction covers the rest
        const double d = distance(i, j);
        if (d > reach) break;
        sum += std::exp(-0.5 * d * d / (sigma * sigma)) * original[j];
      }
    }
    if (sum.norm() < 1e-12) continue;
    Vec3 smoothed = sum.normalized();
    const double deviation = angleBetween(smoothed, original[i]);
    if (deviation > options.maxSmoothingDeviation) {
      const Vec3 axis = original[i].cross(smoothed).normalized();
      smoothed = Eigen::AngleAxisd(options.maxSmoothingDeviation, axis) * original[i];
    }
    out[i] = smoothed;
  }
  return out;
}

void alignSample(const PositionerDescription& pos, const Vec3& gravity, AngleSample& s,
                 const MotionOptions& options) {
  s.align = alignWithGravity(pos, s.v, gravity);
  s.band = s.align.axisAngle < options.nearSingularBand;
  if (s.band) s.flags |= kMotionNearSingular | kMotionSingular;
}

/// Exact alignment of every sample outside the band, continuous along the path.
void computeExactAngles(const PositionerDescription& pos, const Vec3& gravity,
                        std::vector<AngleSample>& samples, double refA1, double refA2, bool haveRef,
                        const MotionOptions& options) {
  bool haveExact = false;
  for (AngleSample& s : samples) {
    if (s.band) continue;
    chooseAngles(pos, gravity, s, refA1, refA2, haveRef, options);
    if (haveExact) continueExactA2(pos, s, refA2);
    refA1 = s.a1;
    refA2 = s.exactA2;
    haveRef = haveExact = true;
  }
}

/// Per sample the a2 interval that keeps V within the band angle of gravity once the tilt
/// compensates (perpendicular axes: residual = asin(sin θ · |sin δ|) for V at θ from the
/// rotation axis and a2 off by δ), and the a2 aimed at: the exact value, or in the band a
/// linear blend (in arc length) of the exact values on both sides.
struct A2Tube {
  std::vector<double> lo, hi, target;
};

A2Tube computeA2Tube(const PositionerDescription& pos, const std::vector<AngleSample>& samples,
                     double holdA2, const MotionOptions& options) {
  const std::size_t n = samples.size();
  A2Tube tube{std::vector<double>(n, -kInf), std::vector<double>(n, kInf),
              std::vector<double>(n, holdA2)};
  const double sinTolerance = std::sin(options.nearSingularBand) * (1.0 - 1e-9);
  std::vector<std::size_t> exact;  // indices outside the band
  for (std::size_t k = 0; k < n; ++k) {
    const AngleSample& s = samples[k];
    if (s.band) continue;
    exact.push_back(k);
    tube.target[k] = s.exactA2;
    if (s.fixed) {
      tube.lo[k] = tube.hi[k] = s.a2;
      continue;
    }
    const double ratio = sinTolerance / std::max(std::sin(s.align.axisAngle), 1e-300);
    const double width = ratio >= 1.0 ? 0.5 * kPi : std::asin(ratio);
    tube.lo[k] = s.exactA2 - width;
    tube.hi[k] = s.exactA2 + width;
  }
  // band targets: blend between the nearest exact neighbours
  std::size_t next = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!samples[k].band) continue;
    while (next < exact.size() && exact[next] < k) ++next;
    const bool hasRight = next < exact.size();
    const bool hasLeft = next > 0;
    if (hasLeft && hasRight) {
      const AngleSample& l = samples[exact[next - 1]];
      const AngleSample& r = samples[exact[next]];
      const double t = (samples[k].arc - l.arc) / std::max(r.arc - l.arc, 1e-300);
      tube.target[k] = l.exactA2 + (r.exactA2 - l.exactA2) * std::clamp(t, 0.0, 1.0);
    } else if (hasLeft) {
      tube.target[k] = samples[exact[next - 1]].exactA2;
    } else if (hasRight) {
      tube.target[k] = samples[exact[next]].exactA2;
    }
  }
  if (!pos.rotation.endless) {
    for (std::size_t k = 0; k < n; ++k) {
      if (samples[k].fixed) continue;
      tube.lo[k] = std::max(tube.lo[k], pos.rotation.limit.min);
      tube.hi[k] = std::min(tube.hi[k], pos.rotation.limit.max);
      tube.target[k] = std::clamp(tube.target[k], pos.rotation.limit.min, pos.rotation.limit.max);
      if (tube.lo[k] > tube.hi[k]) tube.lo[k] = tube.hi[k] = tube.target[k];
    }
  }
  return tube;
}

/// a2 through the tube with |Δa2| <= rate · Δs, as near its target as that allows: forward
/// reachable intervals, backward intervals from which the end stays reachable, then a greedy
/// pass. False (a2 unchanged) if no such a2 exists at this rate.
bool followTube(const A2Tube& tube, double rate, std::vector<AngleSample>& samples) {
  const std::size_t n = samples.size();
  std::vector<double> lo(tube.lo), hi(tube.hi), step(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    step[k] = rate * std::max(samples[k].arc - samples[k - 1].arc, 0.0);
    lo[k] = std::max(lo[k], lo[k - 1] - step[k]);
    hi[k] = std::min(hi[k], hi[k - 1] + step[k]);
    if (lo[k] > hi[k] + 1e-12) return false;
  }
  for (std::size_t k = n - 1; k-- > 0;) {
    lo[k] = std::max(lo[k], lo[k + 1] - step[k + 1]);
    hi[k] = std::min(hi[k], hi[k + 1] + step[k + 1]);
  }
  double previous = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    double l = lo[k], h = hi[k];
    if (k > 0) {
      l = std::max(l, previous - step[k]);
      h = std::min(h, previous + step[k]);
    }
    previous = std::min(std::max(tube.target[k], l), std::max(l, h));
    samples[k].a2 = previous;
  }
  return true;
}

/// a2 along the path: the slowest rate of r0 · 2^k (k <= 10) that fits the tube; else each
/// point's target within its own interval.
void chooseRotations(const A2Tube& tube, double a2Rate, std::vector<AngleSample>& samples) {
  for (int k = 0; k <= 10; ++k) {
    if (followTube(tube, a2Rate * std::ldexp(1.0, k), samples)) return;
  }
  for (std::size_t k = 0; k < samples.size(); ++k) {
    samples[k].a2 = std::clamp(tube.target[k], tube.lo[k], std::max(tube.lo[k], tube.hi[k]));
  }
}

/// A sample on the straight segment a → b at fraction t (exact angles not yet computed).
AngleSample interpolateSample(const PositionerDescription& pos, const Vec3& gravity,
                              const AngleSample& a, const AngleSample& b, double t,
                              const MotionOptions& options) {
  auto blend = [t](const Vec3& x, const Vec3& y) {
    const Vec3 m = (1.0 - t) * x + t * y;
    return m.norm() > 1e-12 ? Vec3(m.normalized()) : x;
  };
  AngleSample s;
  s.position = (1.0 - t) * a.position + t * b.position;
  s.normal = blend(a.normal, b.normal);
  s.deposition = blend(a.deposition, b.deposition);
  s.v = blend(a.v, b.v);
  s.index = a.index;
  s.inserted = true;
  s.arc = (1.0 - t) * a.arc + t * b.arc;
  s.flags = kMotionInserted | (a.flags & b.flags & kMotionSmoothed) |
            ((a.flags | b.flags) & kMotionGravityDeviated);
  alignSample(pos, gravity, s, options);
  return s;
}

/// An inserted sample outside the band with a2 interpolated: a2 moved into its own tube (the
/// exact alignment nearest that a2), so V stays within the band angle of gravity.
void projectIntoTube(const PositionerDescription& pos, const Vec3& gravity, AngleSample& s,
                     const AngleSample& before, const MotionOptions& options) {
  const double a2 = s.a2;
  chooseAngles(pos, gravity, s, before.a1, a2, true, options);
  continueExactA2(pos, s, a2);
  s.a2 = a2;
  if (s.fixed) {
    s.a2 = s.exactA2;
    return;
  }
  const double ratio = std::sin(options.nearSingularBand) * (1.0 - 1e-9) /
                       std::max(std::sin(s.align.axisAngle), 1e-300);
  const double width = ratio >= 1.0 ? 0.5 * kPi : std::asin(ratio);
  s.a2 = std::clamp(a2, s.exactA2 - width, s.exactA2 + width);
}

/// Splits every segment whose a2 step exceeds maxA2Step into equal parts; the new samples get
/// a2 interpolated (`exact` false) or their exact angles (true, then a2 is chosen again).
bool insertSamples(const PositionerDescription& pos, const Vec3& gravity,
                   std::vector<AngleSample>& samples, const MotionOptions& options, bool exact) {
  std::vector<AngleSample> out;
  bool inserted = false;
  out.reserve(samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) {
    if (k > 0) {
      const AngleSample& a = samples[k - 1];
      const AngleSample& b = samples[k];
      const double jump = std::abs(b.a2 - a.a2);
      const int parts = static_cast<int>(std::ceil(jump / options.maxA2Step * (1.0 - 1e-12)));
      for (int i = 1; i < parts; ++i) {
        const double t = static_cast<double>(i) / parts;
        AngleSample s = interpolateSample(pos, gravity, a, b, t, options);
        s.a2 = a.a2 + (b.a2 - a.a2) * t;
        if (exact && !s.band) {
          // the exact alignment nearest the a2 chosen so far, so that its tube meets the
          // neighbours' along that a2 (e sweeps fast here: its interpolation is ambiguous)
          chooseAngles(pos, gravity, s, a.a1, s.a2, true, options);
          continueExactA2(pos, s, a.a2 + (b.a2 - a.a2) * t);
          if (!s.fixed) s.a2 = a.a2 + (b.a2 - a.a2) * t;
        } else if (!s.band) {
          projectIntoTube(pos, gravity, s, a, options);
        }
        out.push_back(s);
        inserted = true;
      }
    }
    out.push_back(samples[k]);
  }
  if (inserted) samples = std::move(out);
  return inserted;
}

}  // namespace

std::vector<AngleSample> sampleDepositions(const PlanPath& path, const PositionerDescription& pos,
                                           const Vec3& gravity, const MotionOptions& options,
                                           std::size_t& merged, const std::vector<Vec3>* targets) {
  std::vector<const PathPoint*> pts;
  for (const PathPoint& pt : path.points) pts.push_back(&pt);
  std::vector<Vec3> used = smoothDepositions(pts, path.closed, options);
  std::vector<bool> deviated(pts.size(), false);
  if (targets != nullptr) {
    for (std::size_t k = 0; k < pts.size() && k < targets->size(); ++k) {
      if ((*targets)[k].isZero()) continue;
      used[k] = (*targets)[k].normalized();
      deviated[k] = true;
    }
  }
  const std::size_t count = pts.size();
  std::vector<AngleSample> samples;
  samples.reserve(count + 1);
  auto add = [&](std::size_t k, int index) {
    AngleSample s;
    s.position = pts[k]->position;
    s.normal = pts[k]->normal;
    s.deposition = pts[k]->deposition.normalized();
    s.v = used[k];
    s.index = index;
    if (!samples.empty()) {
      s.arc = samples.back().arc + (s.position - samples.back().position).norm();
    }
    if (deviated[k]) {
      s.flags |= kMotionGravityDeviated;
    } else if (angleBetween(s.v, s.deposition) > 1e-12) {
      s.flags |= kMotionSmoothed;
    }
    alignSample(pos, gravity, s, options);
    samples.push_back(s);
  };
  auto closeToLast = [&](const Vec3& p) {
    return (p - samples.back().position).norm() < options.mergeTolerance;
  };
  for (std::size_t k = 0; k < count; ++k) {
    const bool last = k + 1 == count;
    if (k > 0 && closeToLast(pts[k]->position)) {
      ++merged;
      // an open path ends on its last point: it replaces the kept one before it
      if (last && !path.closed && samples.size() > 1) {
        samples.pop_back();
        add(k, static_cast<int>(k));
      }
      continue;
    }
    if (last && path.closed && samples.size() > 1 &&
        (pts[k]->position - pts[0]->position).norm() < options.mergeTolerance) {
      ++merged;  // the closing move from here would be a near-duplicate of point 0
      continue;
    }
    add(k, static_cast<int>(k));
  }
  if (path.closed) add(0, static_cast<int>(count));  // the closing weld move ends on point 0
  if (samples.size() < 2) add(count - 1, static_cast<int>(count - 1));  // all within tolerance
  return samples;
}

void planPathAngles(const PositionerDescription& pos, const Vec3& gravity, double a2Rate,
                    std::vector<AngleSample>& samples, double& refA1, double& refA2, bool& haveRef,
                    const MotionOptions& options) {
  computeExactAngles(pos, gravity, samples, refA1, refA2, haveRef, options);
  double holdA2 = haveRef ? refA2 : options.initialA2;
  if (!pos.rotation.endless)
    holdA2 = std::clamp(holdA2, pos.rotation.limit.min, pos.rotation.limit.max);
  // a2 through the tube; where it still steps more than maxA2Step, insert points with their own
  // exact alignment and choose again (a few rounds), then split what remains evenly.
  for (int round = 0;; ++round) {
    chooseRotations(computeA2Tube(pos, samples, holdA2, options), a2Rate, samples);
    if (round == 12 || !insertSamples(pos, gravity, samples, options, true)) break;
  }
  for (int round = 0; round < 16 && insertSamples(pos, gravity, samples, options, false);) ++round;
  // the tilt for the chosen a2
  double previousA1 = haveRef ? refA1 : 0.0;
  bool first = true;
  for (AngleSample& s : samples) {
    if (!s.fixed) {
      const double reference = first && !s.band ? s.a1 : previousA1;
      tiltForRotation(pos, gravity, s, reference);
      if (!s.band && std::abs(s.a2 - s.exactA2) > 1e-9) s.flags |= kMotionA2RateLimited;
    }
    previousA1 = s.a1;
    first = false;
  }
  refA1 = samples.back().a1;
  refA2 = samples.back().a2;
  haveRef = true;
}

}  // namespace curvedslicer::detail
