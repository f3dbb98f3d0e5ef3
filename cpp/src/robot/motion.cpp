// Motion planning: positioner angles (eq. 16) along paths, world poses, robot inverse
// kinematics and process estimates. Phases (progress stages): "positioner angles",
// "robot kinematics", "estimates".
#include "curvedslicer/robot/motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "curvedslicer/robot/travel.hpp"

namespace curvedslicer {

std::string_view toString(MoveKind kind) {
  switch (kind) {
    case MoveKind::Path:
      return "path";
    case MoveKind::Retract:
      return "retract";
    case MoveKind::Travel:
      return "travel";
    case MoveKind::Approach:
      return "approach";
    case MoveKind::Home:
      return "home";
  }
  return "path";
}

std::string_view toString(UnreachablePolicy policy) {
  return policy == UnreachablePolicy::Warn ? "warn" : "throw";
}

UnreachablePolicy parseUnreachablePolicy(std::string_view name) {
  if (name == "throw") return UnreachablePolicy::Throw;
  if (name == "warn") return UnreachablePolicy::Warn;
  throw InvalidInput("unknown unreachable-point policy: '" + std::string(name) +
                     "'; choose throw (InvalidInput naming the points) or warn (keep the "
                     "closest pose with a warning)");
}

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kDeg = kPi / 180.0;
constexpr std::size_t kExamples = 3;  // example points named per warning

std::string fmt(double value, int precision = 3) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(precision);
  out << value;
  return out.str();
}

std::string pointName(int layer, int path, int index) {
  return "layer " + std::to_string(layer) + " path " + std::to_string(path) + " point " +
         std::to_string(index);
}

std::string pointName(const MotionPoint& p) {
  return pointName(p.layer, p.path, p.index) + " (part " + fmt(p.position.x(), 2) + ", " +
         fmt(p.position.y(), 2) + ", " + fmt(p.position.z(), 2) + " mm)";
}

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

/// Per-path working data of the angle phase.
struct AngleSample {
  Vec3 v;  // V used (part frame)
  bool singular = false;
  GravityAlignment align;
  double a1 = 0.0, a2 = 0.0;  // chosen
  std::uint32_t flags = 0;
};

/// Chooses, for a non-singular point, the branch and unwrapping nearest the reference within
/// the positioner limits, or the feasible pose of least residual.
void chooseAngles(const PositionerDescription& pos, const Vec3& gravity, AngleSample& s,
                  double refA1, double refA2, bool haveRef, const MotionOptions& options) {
  double bestCost = kInf;
  bool bestFeasible = false;
  for (int b = 0; b < 2; ++b) {
    double a1 = s.align.branches[b].a1;
    double a2 = s.align.branches[b].a2;
    const bool rotOk = fitRotation(a2, pos.rotation, refA2);
    const bool tiltOk = pos.tilt.limit.contains(a1) && s.align.feasible;
    const bool feasible = rotOk && tiltOk;
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
  if (bestFeasible) return;
  // No exact alignment within the limits: the feasible pose of least residual among tilt at
  // a limit (with the best rotation) and rotation at a limit (with the best tilt).
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
      double a1 = optimalTiltForRotation(pos, s.v, gravity, a2);
      consider(a1, a2, kMotionRotationLimited);
    }
  }
  for (int b = 0; b < 2; ++b) {
    consider(s.align.branches[b].a1, s.align.branches[b].a2, 0);
  }
  s.a1 = bestA1;
  s.a2 = bestA2;
  s.flags |= bestFlags;
}

/// Tilt for a prescribed rotation (singular zone, rate-limited window), clamped to its limits.
void tiltForRotation(const PositionerDescription& pos, const Vec3& gravity, AngleSample& s,
                     double refA1) {
  double a1 = unwrapNear(optimalTiltForRotation(pos, s.v, gravity, s.a2), refA1);
  bool clamped = false;
  if (!pos.tilt.limit.contains(a1)) {
    // try the other unwrapping before clamping
    const double other = a1 + (a1 > 0 ? -kTwoPi : kTwoPi);
    if (pos.tilt.limit.contains(other)) a1 = other;
  }
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
    // neighbours within 3 sigma, walking outwards in both directions (wrapping when closed)
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
      // turn the original towards the smoothed direction by exactly the bound
      const Vec3 axis = original[i].cross(smoothed).normalized();
      smoothed = Eigen::AngleAxisd(options.maxSmoothingDeviation, axis) * original[i];
    }
    out[i] = smoothed;
  }
  return out;
}

/// Positioner angles along one path (points already include a closing point if closed).
/// `refA1/refA2/haveRef`: the end of the previous path.
void planPathAngles(const PositionerDescription& pos, const Vec3& gravity,
                    std::vector<AngleSample>& samples, double& refA1, double& refA2, bool& haveRef,
                    const MotionOptions& options) {
  const std::size_t n = samples.size();
  const double limit = options.maxSingularA2Step;
  // Exact choices (branch + unwrapping) for non-singular points, nearest the previous choice.
  double rA1 = refA1, rA2 = haveRef ? refA2 : options.initialA2;
  bool have = haveRef;
  for (std::size_t i = 0; i < n; ++i) {
    AngleSample& s = samples[i];
    if (s.singular) continue;
    chooseAngles(pos, gravity, s, rA1, rA2, have, options);
    rA1 = s.a1;
    rA2 = s.a2;
    have = true;
  }
  // Windows around singular runs: a2 follows a ramp (or is held) with at most `limit` per
  // point; the window grows over neighbouring points whose exact a2 moves faster than that.
  std::size_t minLo = 0;  // the right boundary of the previous window stays fixed
  std::size_t i = 0;
  while (i < n) {
    if (!samples[i].singular) {
      ++i;
      continue;
    }
    std::size_t lo = std::max(i, minLo), hi = i;
    while (hi < n && samples[hi].singular) ++hi;
    auto growLeft = [&] {
      if (lo <= minLo) return false;
      --lo;
      return true;
    };
    auto growRight = [&] {
      if (hi >= n) return false;
      ++hi;
      while (hi < n && samples[hi].singular) ++hi;  // merge the next singular run
      return true;
    };
    for (bool changed = true; changed;) {
      changed = false;
      if (lo >= 2 && lo > minLo && std::abs(samples[lo - 1].a2 - samples[lo - 2].a2) > limit) {
        changed = growLeft() || changed;
      }
      if (hi + 1 < n && !samples[hi + 1].singular &&
          std::abs(samples[hi + 1].a2 - samples[hi].a2) > limit) {
        changed = growRight() || changed;
      }
      if (lo > 0 && hi < n &&
          std::abs(samples[hi].a2 - samples[lo - 1].a2) >
              static_cast<double>(hi - lo + 1) * limit) {
        const bool left = growLeft();
        const bool right = growRight();
        changed = left || right || changed;
      }
    }
    // Values in [lo, hi): a linear ramp between the exact values at lo-1 and hi, or held.
    const bool hasLeft = lo > 0, hasRight = hi < n;
    const double left = hasLeft ? samples[lo - 1].a2 : 0.0;
    const double right = hasRight ? samples[hi].a2 : 0.0;
    for (std::size_t k = lo; k < hi; ++k) {
      AngleSample& s = samples[k];
      if (hasLeft && hasRight) {
        const double t = static_cast<double>(k - lo + 1) / static_cast<double>(hi - lo + 1);
        s.a2 = left + (right - left) * t;
      } else if (hasLeft) {
        s.a2 = left;
      } else if (hasRight) {
        s.a2 = right;
      } else {
        s.a2 = haveRef ? refA2 : options.initialA2;
        if (!pos.rotation.endless) {
          s.a2 = std::clamp(s.a2, pos.rotation.limit.min, pos.rotation.limit.max);
        }
      }
      const double a1Reference = k > 0 ? samples[k - 1].a1 : (haveRef ? refA1 : 0.0);
      tiltForRotation(pos, gravity, s, s.singular ? a1Reference : s.a1);
      if (!s.singular) s.flags |= kMotionA2RateLimited;
    }
    minLo = hi + 1;
    i = hi;
  }
  refA1 = samples.back().a1;
  refA2 = samples.back().a2;
  haveRef = true;
}

/// Tool x axis: travel direction (world) made orthogonal to the torch axis z.
Vec3 toolXAxis(const Vec3& travelWorld, const Vec3& z, const Vec3& previous) {
  Vec3 x = travelWorld - z * z.dot(travelWorld);
  if (x.norm() > 1e-9) return x.normalized();
  x = previous - z * z.dot(previous);
  if (x.norm() > 1e-9) return x.normalized();
  x = Vec3::UnitX() - z * z.x();
  if (x.norm() < 1e-6) x = Vec3::UnitY() - z * z.y();
  return x.normalized();
}

void validateInputs(const Plan& plan, const MotionOptions& options) {
  if (!(options.singularZone >= 0.0 && options.singularZone < kPi / 2)) {
    throw InvalidInput("singular zone must be in [0, 90) degrees: " +
                       fmt(options.singularZone / kDeg) + " deg; use e.g. 2 degrees");
  }
  if (!(options.maxSingularA2Step > 0.0)) {
    throw InvalidInput("maximum a2 step in the singular zone must be positive: " +
                       fmt(options.maxSingularA2Step / kDeg) + " deg; use e.g. 2 degrees");
  }
  if (!(options.smoothingLength >= 0.0) || !std::isfinite(options.smoothingLength)) {
    throw InvalidInput("smoothing length must be zero or positive: " +
                       fmt(options.smoothingLength) + " mm; use 0 to switch smoothing off");
  }
  if (!(options.maxSmoothingDeviation >= 0.0)) {
    throw InvalidInput("maximum smoothing deviation must not be negative: " +
                       fmt(options.maxSmoothingDeviation / kDeg) + " deg; use e.g. 5 degrees");
  }
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    const PlanLayer& layer = plan.layers[l];
    for (std::size_t p = 0; p < layer.paths.size(); ++p) {
      const PlanPath& path = layer.paths[p];
      if (path.points.size() < 2) {
        throw InvalidInput("path has fewer than 2 points: " +
                           pointName(static_cast<int>(l), static_cast<int>(p), 0) + " (" +
                           std::to_string(path.points.size()) +
                           " points); drop the path or regenerate the plan");
      }
      for (std::size_t k = 0; k < path.points.size(); ++k) {
        const PathPoint& pt = path.points[k];
        const double dn = pt.deposition.norm();
        if (!pt.position.allFinite() || !pt.deposition.allFinite() || !(dn > 0.5 && dn < 1.5)) {
          throw InvalidInput(
              "path point has a non-finite position or a deposition direction that is not "
              "unit: " +
              pointName(static_cast<int>(l), static_cast<int>(p), static_cast<int>(k)) +
              " (|V| = " + fmt(dn, 6) + "); regenerate the plan");
        }
      }
    }
  }
}

void addEstimates(MotionEstimate& into, const MotionEstimate& e) {
  into.beadLength += e.beadLength;
  into.arcTime += e.arcTime;
  into.travelLength += e.travelLength;
  into.travelTime += e.travelTime;
  into.dwellTime += e.dwellTime;
  into.totalTime += e.totalTime;
  into.wireLength += e.wireLength;
  into.depositedVolume += e.depositedVolume;
  into.depositedMass += e.depositedMass;
  into.paths += e.paths;
  into.points += e.points;
}

void finishEstimate(MotionEstimate& e, const ProcessDescription& process) {
  e.arcTime = e.beadLength / process.weldSpeed;
  e.wireLength = process.wireFeed * 1000.0 / 60.0 * e.arcTime;
  const double area = kPi * 0.25 * process.wireDiameter * process.wireDiameter;
  e.depositedVolume = area * e.wireLength * process.depositionEfficiency;
  e.depositedMass = e.depositedVolume * process.wireDensity / 1000.0;
  e.totalTime = e.arcTime + e.travelTime + e.dwellTime;
}

/// Collects warnings per cause with a few example points.
class WarningLog {
 public:
  void add(const std::string& cause, const std::string& example) {
    for (auto& entry : entries_) {
      if (entry.cause == cause) {
        ++entry.count;
        if (entry.examples.size() < kExamples) entry.examples.push_back(example);
        return;
      }
    }
    entries_.push_back({cause, 1, {example}});
  }
  void flush(std::vector<std::string>& out) const {
    for (const auto& e : entries_) {
      std::string text = e.cause + ": " + std::to_string(e.count) + " point(s), e.g. ";
      for (std::size_t i = 0; i < e.examples.size(); ++i) {
        text += (i ? "; " : "") + e.examples[i];
      }
      out.push_back(text);
    }
  }

 private:
  struct Entry {
    std::string cause;
    std::size_t count;
    std::vector<std::string> examples;
  };
  std::vector<Entry> entries_;
};

}  // namespace

MotionEstimate estimatePlan(const Plan& plan, const ProcessDescription& process,
                            std::vector<MotionEstimate>* layers) {
  MotionEstimate total;
  if (layers) layers->assign(plan.layers.size(), MotionEstimate{});
  const Vec3* previousEnd = nullptr;
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    MotionEstimate e;
    for (const PlanPath& path : plan.layers[l].paths) {
      if (path.points.empty()) continue;
      for (std::size_t k = 1; k < path.points.size(); ++k) {
        e.beadLength += (path.points[k].position - path.points[k - 1].position).norm();
      }
      if (path.closed) {
        e.beadLength += (path.points.front().position - path.points.back().position).norm();
      }
      if (previousEnd) e.travelLength += (path.points.front().position - *previousEnd).norm();
      previousEnd = path.closed ? &path.points.front().position : &path.points.back().position;
      e.dwellTime += process.pathDwell;
      e.points += path.points.size();
      ++e.paths;
    }
    e.dwellTime += process.layerDwell;
    e.travelTime = e.travelLength / process.travelSpeed;
    finishEstimate(e, process);
    if (layers) (*layers)[l] = e;
    addEstimates(total, e);
  }
  return total;
}

long long positionerPulses(const PositionerAxis& axis, double angle) {
  return axis.sign * std::llround(angle / kDeg * axis.pulsesPerDegree);
}

std::array<long long, 6> robotPulses(const RobotDescription& robot, const JointVector& joints) {
  if (robot.pulsesPerDegree.size() != 6) {
    throw InvalidInput("robot pulses per degree are not given in the cell: " +
                       std::to_string(robot.pulsesPerDegree.size()) +
                       " values; add robot/pulses_per_degree or write Cartesian positions");
  }
  std::array<long long, 6> pulses{};
  for (int i = 0; i < 6; ++i) {
    pulses[i] = std::llround(joints[i] / kDeg * robot.pulsesPerDegree[i]);
  }
  return pulses;
}

namespace {

// ---- positioner angles --------------------------------------------------------------------

/// The path's points as welded (a closed path ends on point 0 again) with their deposition
/// directions after smoothing, aligned with gravity.
std::vector<AngleSample> sampleDepositions(const PlanPath& path, const PositionerDescription& pos,
                                           const Vec3& gravity, const MotionOptions& options,
                                           std::vector<const PathPoint*>& pts) {
  for (const PathPoint& pt : path.points) pts.push_back(&pt);
  std::vector<Vec3> used = smoothDepositions(pts, path.closed, options);
  if (path.closed) {  // the closing weld move ends on point 0 again
    pts.push_back(&path.points.front());
    used.push_back(used.front());
  }
  std::vector<AngleSample> samples(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    AngleSample& s = samples[k];
    s.v = used[k];
    s.align = alignWithGravity(pos, s.v, gravity);
    s.singular = s.align.axisAngle < options.singularZone;
    if (s.singular) s.flags |= kMotionSingular;
    if (angleBetween(s.v, pts[k]->deposition.normalized()) > 1e-12) s.flags |= kMotionSmoothed;
  }
  return samples;
}

/// Appends one path's motion points (part frame, positioner angles, residuals) to `result`.
void appendPathPoints(int l, int p, const std::vector<const PathPoint*>& pts,
                      const std::vector<AngleSample>& samples, const Cell& cell,
                      const Vec3& gravity, const MotionOptions& options, MotionPlan& result,
                      WarningLog& warnings) {
  for (std::size_t k = 0; k < pts.size(); ++k) {
    MotionPoint m;
    m.layer = l;
    m.path = p;
    m.index = static_cast<int>(k);
    m.position = pts[k]->position;
    m.normal = pts[k]->normal;
    m.deposition = pts[k]->deposition.normalized();
    m.usedDeposition = samples[k].v;
    m.a1 = samples[k].a1;
    m.a2 = samples[k].a2;
    m.flags = samples[k].flags;
    m.residual = computeGravityResidual(cell.positioner, m.deposition, gravity, m.a1, m.a2);
    m.pathStart = k == 0;
    m.pathEnd = k + 1 == pts.size();
    m.arcOn = k > 0;
    m.speed = k > 0 ? cell.process.weldSpeed : cell.process.travelSpeed;
    if (m.flags & kMotionSingular) {
      ++result.singularPoints;
    } else {
      result.maxResidual = std::max(result.maxResidual, m.residual);
    }
    if (m.flags & (kMotionTiltLimited | kMotionRotationLimited)) {
      ++result.limitedPoints;
      warnings.add("positioner limit: deposition direction cannot be turned onto gravity",
                   pointName(m) + " residual " + fmt(m.residual / kDeg, 2) + " deg");
    } else if ((m.flags & kMotionA2RateLimited) && m.residual > options.residualWarning) {
      warnings.add("a2 rate limit near the singular zone leaves a residual above " +
                       fmt(options.residualWarning / kDeg, 2) + " deg",
                   pointName(m) + " residual " + fmt(m.residual / kDeg, 2) + " deg");
    }
    result.points.push_back(m);
  }
}

/// Positioner angles (eq. 16) along every path, continuous from one path to the next.
void planPositionerAngles(const Plan& plan, const Cell& cell, const Vec3& gravity,
                          const MotionOptions& options, const Progress& progress,
                          MotionPlan& result, WarningLog& warnings) {
  progress.report(0.0, "positioner angles");
  const std::size_t pathTotal = std::max<std::size_t>(1, plan.pathCount());
  std::size_t pathsDone = 0;
  double refA1 = 0.0, refA2 = options.initialA2;
  bool haveRef = false;
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    for (std::size_t p = 0; p < plan.layers[l].paths.size(); ++p) {
      std::vector<const PathPoint*> pts;
      std::vector<AngleSample> samples =
          sampleDepositions(plan.layers[l].paths[p], cell.positioner, gravity, options, pts);
      planPathAngles(cell.positioner, gravity, samples, refA1, refA2, haveRef, options);
      MotionPathSpan span{static_cast<int>(l), static_cast<int>(p), result.points.size(), 0};
      appendPathPoints(static_cast<int>(l), static_cast<int>(p), pts, samples, cell, gravity,
                       options, result, warnings);
      span.end = result.points.size();
      result.paths.push_back(span);
      progress.report(static_cast<double>(++pathsDone) / static_cast<double>(pathTotal),
                      "positioner angles");
    }
  }
}

// ---- robot kinematics ---------------------------------------------------------------------

/// Robot joints along the paths: TCP poses, inverse kinematics continuous along each path, the
/// points it cannot reach. Carries the joints and tool x axis from one path to the next.
class RobotKinematicsPass {
 public:
  RobotKinematicsPass(const Cell& cell, const Vec3& gravity, const MotionOptions& options,
                      MotionPlan& result, WarningLog& warnings)
      : cell_(cell),
        gravity_(gravity),
        options_(options),
        result_(result),
        warnings_(warnings),
        baseInverse_(cell.robot.base.inverse()),
        tcpInverse_(cell.tool.tcp.inverse()),
        shortfall_(result.points.size(), 0.0) {}

  void run(const Progress& progress);

 private:
  void setToolPoses(const MotionPathSpan& span);
  void solvePath(const MotionPathSpan& span);
  std::size_t solvePathJoints(const MotionPathSpan& span, const JointVector& start, bool haveStart);
  IkSolution chooseSolution(const IkResult& ik, const JointVector& reference, bool pathStart,
                            int pathConfiguration, bool& inside) const;
  void recordFailures(const MotionPathSpan& span);
  void reportFailures() const;

  const Cell& cell_;
  const Vec3 gravity_;
  const MotionOptions& options_;
  MotionPlan& result_;
  WarningLog& warnings_;
  const Pose baseInverse_;
  const Pose tcpInverse_;
  JointVector previousJoints_{};
  bool haveJoints_ = false;
  std::vector<std::string> failures_;
  std::size_t failureCount_ = 0;
  Vec3 previousX_ = Vec3::UnitX();
  // Reach shortfall per point (mm, > 0 only where no IK solution exists).
  std::vector<double> shortfall_;
};

void RobotKinematicsPass::run(const Progress& progress) {
  progress.report(0.0, "robot kinematics");
  for (std::size_t s = 0; s < result_.paths.size(); ++s) {
    const MotionPathSpan& span = result_.paths[s];
    setToolPoses(span);
    solvePath(span);
    recordFailures(span);
    previousJoints_ = result_.points[span.end - 1].joints;
    haveJoints_ = true;
    progress.report(static_cast<double>(s + 1) / static_cast<double>(result_.paths.size()),
                    "robot kinematics");
  }
  reportFailures();
}

/// TCP poses (independent of the robot joints).
void RobotKinematicsPass::setToolPoses(const MotionPathSpan& span) {
  const PositionerDescription& pos = cell_.positioner;
  for (std::size_t k = span.begin; k < span.end; ++k) {
    MotionPoint& m = result_.points[k];
    const Pose partInWorld = computePartInWorld(pos, m.a1, m.a2);
    const Vec3 pointWorld = partInWorld * m.position;
    // travel direction: central difference along the path, turned into world
    const Vec3 next = k + 1 < span.end ? result_.points[k + 1].position : m.position;
    const Vec3 prev = k > span.begin ? result_.points[k - 1].position : m.position;
    Vec3 travel = partInWorld.linear() * (next - prev);
    if (!options_.toolAlongTravel) travel = Vec3::UnitX();
    const Vec3 z = gravity_;
    const Vec3 x = toolXAxis(travel, z, previousX_);
    previousX_ = x;
    m.toolInWorld = Pose::Identity();
    m.toolInWorld.linear().col(0) = x;
    m.toolInWorld.linear().col(1) = z.cross(x);
    m.toolInWorld.linear().col(2) = z;
    m.toolInWorld.translation() = pointWorld;
    m.toolInRobotBase = baseInverse_ * m.toolInWorld;
    m.toolInTable = computeTableInWorld(pos, m.a1, m.a2).inverse() * m.toolInWorld;
    m.toolInPart = partInWorld.inverse() * m.toolInWorld;
  }
}

/// The arc-off move to the path start may re-centre the wrist joints (R, T) by a turn; tries
/// that when the nearest start would run a joint into its limit along the path.
void RobotKinematicsPass::solvePath(const MotionPathSpan& span) {
  const double shifts[5][2] = {{0, 0}, {0, -kTwoPi}, {0, kTwoPi}, {-kTwoPi, 0}, {kTwoPi, 0}};
  std::size_t bestShift = 0, lastRun = 0;
  std::size_t fewest = std::numeric_limits<std::size_t>::max();
  auto shiftedStart = [&](std::size_t t) {
    JointVector start = previousJoints_;
    start[3] += shifts[t][0];
    start[5] += shifts[t][1];
    return start;
  };
  for (std::size_t t = 0; t < 5; ++t) {
    if (t > 0 && !haveJoints_) break;
    const std::size_t n = solvePathJoints(span, shiftedStart(t), haveJoints_);
    lastRun = t;
    if (n < fewest) {
      fewest = n;
      bestShift = t;
    }
    if (n == 0) break;
  }
  if (bestShift != lastRun) solvePathJoints(span, shiftedStart(bestShift), haveJoints_);
}

/// Joints along one path from a start reference; sets joints and flags, returns a badness:
/// 1e6 per point without a solution inside the limits plus 1 per configuration change.
std::size_t RobotKinematicsPass::solvePathJoints(const MotionPathSpan& span,
                                                 const JointVector& start, bool haveStart) {
  std::size_t pathFailures = 0, configurationChanges = 0;
  JointVector previous = start;
  bool have = haveStart;
  int pathConfiguration = -1;
  for (std::size_t k = span.begin; k < span.end; ++k) {
    MotionPoint& m = result_.points[k];
    m.flags &= ~(kMotionRobotLimit | kMotionWristSingular | kMotionConfigurationChange);
    const Pose flange = m.toolInRobotBase * tcpInverse_;
    const IkResult ik = solveInverseKinematics(cell_.robot, flange, have ? previous[3] : 0.0);
    if (ik.solutions.empty()) {
      ++pathFailures;
      m.flags |= kMotionRobotLimit;
      if (have) m.joints = previous;  // Warn policy: hold the last joints
      shortfall_[k] = std::max(ik.reachShortfall, 1e-3);
      continue;
    }
    shortfall_[k] = 0.0;
    const JointVector reference = have ? previous : JointVector{};
    bool bestInside = false;
    const IkSolution best =
        chooseSolution(ik, reference, k == span.begin, pathConfiguration, bestInside);
    m.joints = best.joints;
    m.configuration = best.configuration;
    if (best.wristSingular) m.flags |= kMotionWristSingular;
    if (pathConfiguration < 0) {
      pathConfiguration = best.configuration;
    } else if (best.configuration != pathConfiguration) {
      m.flags |= kMotionConfigurationChange;
      ++configurationChanges;
    }
    if (!bestInside) {
      m.flags |= kMotionRobotLimit;
      ++pathFailures;
    }
    previous = m.joints;
    have = true;
  }
  return 1000000 * pathFailures + configurationChanges;
}

/// The IK solution nearest `reference` (joints unwrapped towards it), preferring those inside
/// the limits and in the path's configuration; `inside` says whether it is within the limits.
IkSolution RobotKinematicsPass::chooseSolution(const IkResult& ik, const JointVector& reference,
                                               bool pathStart, int pathConfiguration,
                                               bool& bestInside) const {
  double bestCost = kInf;
  IkSolution best;
  for (const IkSolution& sol : ik.solutions) {
    JointVector q = sol.joints;
    bool inside;
    if (pathStart) {
      // arc-off move to the path start: any turn of a joint that lands inside its limits
      inside = unwrapJoints(cell_.robot, q, reference);
    } else {
      // along the path joints move continuously: the nearest turn must be inside the limits
      inside = true;
      for (int j = 0; j < 6; ++j) {
        q[j] = unwrapNear(q[j], reference[j]);
        inside = inside && cell_.robot.joints[j].contains(q[j]);
      }
    }
    double cost = 0.0;
    for (int j = 0; j < 6; ++j) cost += std::abs(q[j] - reference[j]);
    if (!inside) {
      // outside the limits: prefer the solution that violates them least (clear messages)
      cost += 1e6;
      for (int j = 0; j < 6; ++j) {
        const JointLimit& lim = cell_.robot.joints[j];
        cost += 1e3 * std::max({0.0, lim.min - q[j], q[j] - lim.max});
      }
    }
    if (pathConfiguration >= 0 && sol.configuration != pathConfiguration) cost += 1e3;
    if (cost < bestCost) {
      bestCost = cost;
      best = sol;
      best.joints = q;
      bestInside = inside;
    }
  }
  return best;
}

/// Records what the chosen run left: configuration changes, unreachable points.
void RobotKinematicsPass::recordFailures(const MotionPathSpan& span) {
  for (std::size_t k = span.begin; k < span.end; ++k) {
    const MotionPoint& m = result_.points[k];
    if (m.flags & kMotionConfigurationChange) {
      warnings_.add("robot configuration changes within a path (joint limits)", pointName(m));
    }
    if (!(m.flags & kMotionRobotLimit)) continue;
    ++failureCount_;
    if (failures_.size() >= 5) continue;
    if (shortfall_[k] > 0.0) {
      failures_.push_back(pointName(m) + " misses by " + fmt(shortfall_[k], 1) + " mm");
      continue;
    }
    std::string joints;
    for (int j = 0; j < 6; ++j) {
      const JointLimit& lim = cell_.robot.joints[j];
      if (!lim.contains(m.joints[j])) {
        joints += std::string(joints.empty() ? "" : ", ") + "joint " + std::to_string(j + 1) +
                  " at " + fmt(m.joints[j] / kDeg, 1) + " deg (limits " + fmt(lim.min / kDeg, 1) +
                  " .. " + fmt(lim.max / kDeg, 1) + ")";
      }
    }
    failures_.push_back(pointName(m) + " is outside the joint limits: " + joints);
  }
}

void RobotKinematicsPass::reportFailures() const {
  if (failureCount_ == 0) return;
  std::string list;
  for (const auto& f : failures_) list += (list.empty() ? "" : "; ") + f;
  const std::string message = "robot cannot reach " + std::to_string(failureCount_) +
                              " point(s) within its reach and joint limits: " + list +
                              (failureCount_ > failures_.size() ? "; ..." : "") +
                              "; move the positioner or the part (cell positioner/base, "
                              "positioner/table_to_part) or use a longer torch";
  if (options_.unreachable == UnreachablePolicy::Throw) throw InvalidInput(message);
  result_.warnings.push_back(message);
}

// ---- estimates ----------------------------------------------------------------------------

/// Process estimates per layer, the travel time refined with the positioner motion between
/// paths.
void estimateMotion(const Plan& plan, const Cell& cell, MotionPlan& result) {
  const PositionerDescription& pos = cell.positioner;
  result.total = estimatePlan(plan, cell.process, &result.layers);
  MotionEstimate refinedTotal;
  std::vector<double> travelTime(plan.layers.size(), 0.0);
  for (std::size_t s = 0; s < result.paths.size(); ++s) {
    if (s == 0) continue;
    const MotionPoint& from = result.points[result.paths[s - 1].end - 1];
    const MotionPoint& to = result.points[result.paths[s].begin];
    const double distance = (to.position - from.position).norm();
    const double t = std::max({distance / cell.process.travelSpeed,
                               std::abs(to.a1 - from.a1) / pos.tilt.limit.maxSpeed,
                               std::abs(to.a2 - from.a2) / pos.rotation.limit.maxSpeed});
    travelTime[static_cast<std::size_t>(to.layer)] += t;
  }
  for (std::size_t l = 0; l < result.layers.size(); ++l) {
    result.layers[l].travelTime = travelTime[l];
    finishEstimate(result.layers[l], cell.process);
    addEstimates(refinedTotal, result.layers[l]);
  }
  result.total = refinedTotal;
}

}  // namespace

MotionPlan planMotion(const Plan& plan, const Cell& cell, const MotionOptions& options,
                      const Progress& progress) {
  validateCell(cell);
  validateInputs(plan, options);
  const Vec3 gravity = cell.gravity.normalized();
  MotionPlan result;
  result.points.reserve(plan.pointCount() + plan.pathCount());
  WarningLog warnings;
  planPositionerAngles(plan, cell, gravity, options, progress.sub(0.0, 0.4), result, warnings);
  RobotKinematicsPass(cell, gravity, options, result, warnings).run(progress.sub(0.4, 0.95));
  planArcOffMoves(plan, cell, TravelSetup{}, options, result, progress.sub(0.95, 0.95));
  progress.report(0.95, "estimates");
  estimateMotion(plan, cell, result);
  warnings.flush(result.warnings);
  progress.report(1.0, "estimates");
  return result;
}

}  // namespace curvedslicer
