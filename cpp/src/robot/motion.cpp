// Motion planning: positioner angles (eq. 16) along paths, world poses, robot inverse
// kinematics and process estimates. Phases (progress stages): "positioner angles",
// "torch angles", "robot kinematics", "estimates".
#include "curvedslicer/robot/motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/collision.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "curvedslicer/robot/timing.hpp"
#include "curvedslicer/robot/travel.hpp"
#include "positioner_path.hpp"
#include "torch_tilt.hpp"

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
  if (!(options.nearSingularBand > 0.0 && options.nearSingularBand < kPi / 4)) {
    throw InvalidInput("near-singular band must be in (0, 45) degrees: " +
                       fmt(options.nearSingularBand / kDeg) + " deg; use e.g. 3 degrees");
  }
  if (!(options.maxA2Step > 0.0) || !std::isfinite(options.maxA2Step)) {
    throw InvalidInput("maximum a2 step between path points must be positive: " +
                       fmt(options.maxA2Step / kDeg) + " deg; use e.g. 5 degrees");
  }
  if (!(options.mergeTolerance >= 0.0) || !std::isfinite(options.mergeTolerance)) {
    throw InvalidInput("merge tolerance must be zero or positive: " +
                       fmt(options.mergeTolerance, 4) + " mm; use e.g. 0.01 mm");
  }
  // a merge tolerance as large as the beads would collapse whole welds into single points
  const double spacing = plan.parameters.beadSpacing;
  if (spacing > 0.0 && !(options.mergeTolerance < 0.5 * spacing)) {
    throw InvalidInput("merge tolerance must be below half the bead spacing (" +
                       fmt(0.5 * spacing, 2) + " mm): " + fmt(options.mergeTolerance, 2) +
                       " mm; it merges consecutive path points closer than this, use e.g. 0.01 "
                       "mm");
  }
  // the travel planner raises routes in steps of half the clearance up to its largest lift: a
  // clearance of a few microns would mean millions of steps per move
  if (!(options.clearance >= 0.5 && options.clearance <= 200.0)) {
    throw InvalidInput("clearance must be between 0.5 and 200 mm: " + fmt(options.clearance, 6) +
                       " mm; the torch keeps this distance from the deposit between welds, use "
                       "e.g. 10 mm");
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
  into.coolingWait += e.coolingWait;
  into.cooledLayers += e.cooledLayers;
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
  // one past the last layer with paths: that layer waits for nothing (no layer follows)
  std::size_t lastWelded = 0;
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    if (!plan.layers[l].paths.empty()) lastWelded = l + 1;
  }
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
    // a layer shorter than the minimum layer time waits the rest after its last path
    if (e.paths > 0 && l + 1 < lastWelded && e.totalTime < process.minLayerTime) {
      e.coolingWait = process.minLayerTime - e.totalTime;
      e.cooledLayers = 1;
      e.dwellTime += e.coolingWait;
      e.totalTime = process.minLayerTime;
    }
    if (layers) (*layers)[l] = e;
    addEstimates(total, e);
  }
  return total;
}

namespace {

/// A pulse count rounded, or InvalidInput when it leaves the controller's 32-bit range.
long long checkedPulses(double pulses, const std::string& what, double angle) {
  if (!(std::abs(pulses) <= 2147483647.0)) {
    throw InvalidInput(what + " at " + fmt(angle / kDeg, 3) + " deg gives " + fmt(pulses, 0) +
                       " pulses, beyond the controller's 32-bit range; check its pulses per "
                       "degree in the cell");
  }
  return std::llround(pulses);
}

}  // namespace

long long positionerPulses(const PositionerAxis& axis, double angle) {
  if (!(axis.pulsesPerDegree > 0.0)) {
    throw InvalidInput(
        "positioner pulses per degree are not given in the cell: 0; add "
        "positioner/tilt/pulses_per_degree and positioner/rotation/pulses_per_degree (the "
        "station's parameters) to write station pulses");
  }
  return checkedPulses(axis.sign * (angle / kDeg) * axis.pulsesPerDegree, "positioner axis", angle);
}

std::array<long long, 6> robotPulses(const RobotDescription& robot, const JointVector& joints) {
  if (robot.pulsesPerDegree.size() != 6) {
    throw InvalidInput("robot pulses per degree are not given in the cell: " +
                       std::to_string(robot.pulsesPerDegree.size()) +
                       " values; add robot/pulses_per_degree or write Cartesian positions");
  }
  std::array<long long, 6> pulses{};
  for (int i = 0; i < 6; ++i) {
    pulses[i] = checkedPulses(joints[i] / kDeg * robot.pulsesPerDegree[i],
                              "robot joint " + std::to_string(i + 1), joints[i]);
  }
  return pulses;
}

namespace {

// ---- positioner angles --------------------------------------------------------------------

/// Appends one path's motion points (part frame, positioner angles, residuals) to `result`.
void appendPathPoints(int l, int p, const std::vector<detail::AngleSample>& samples,
                      const Cell& cell, const Vec3& gravity, const MotionOptions& options,
                      MotionPlan& result, WarningLog& warnings) {
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const detail::AngleSample& s = samples[k];
    MotionPoint m;
    m.layer = l;
    m.path = p;
    m.index = s.index;
    m.position = s.position;
    m.normal = s.normal;
    m.deposition = s.deposition;
    m.usedDeposition = s.v;
    m.a1 = s.a1;
    m.a2 = s.a2;
    m.flags = s.flags;
    m.residual = computeGravityResidual(cell.positioner, m.deposition, gravity, m.a1, m.a2);
    m.pathStart = k == 0;
    m.pathEnd = k + 1 == samples.size();
    m.arcOn = k > 0;
    m.speed = k > 0 ? cell.process.weldSpeed : cell.process.travelSpeed;
    if (m.flags & kMotionNearSingular) {
      ++result.singularPoints;
    } else {
      result.maxResidual = std::max(result.maxResidual, m.residual);
    }
    if (m.flags & (kMotionTiltLimited | kMotionRotationLimited)) {
      ++result.limitedPoints;
      warnings.add("positioner limit: deposition direction cannot be turned onto gravity",
                   pointName(m) + " residual " + fmt(m.residual / kDeg, 2) + " deg");
    } else if ((m.flags & kMotionA2RateLimited) && m.residual > options.residualWarning) {
      warnings.add("a2 blended near the rotation axis leaves a residual above " +
                       fmt(options.residualWarning / kDeg, 2) + " deg",
                   pointName(m) + " residual " + fmt(m.residual / kDeg, 2) + " deg");
    }
    result.points.push_back(m);
  }
}

/// Per plan layer, path and point: the V the positioner turns onto gravity instead of the plan's
/// (zero where it keeps the plan's); see gravityDeviationTargets.
using DeviationTargets = std::vector<std::vector<std::vector<Vec3>>>;

/// Positioner angles (eq. 16) along every path, continuous from one path to the next. a2 is
/// blended at a rate of at most a quarter of the rotation's speed limit at weld speed (rad/mm).
/// `targets` (optional) replaces V where the torch needs a gravity deviation to clear.
void planPositionerAngles(const Plan& plan, const Cell& cell, const Vec3& gravity,
                          const MotionOptions& options, const Progress& progress,
                          MotionPlan& result, WarningLog& warnings,
                          const DeviationTargets* targets = nullptr) {
  progress.report(0.0, "positioner angles");
  const std::size_t pathTotal = std::max<std::size_t>(1, plan.pathCount());
  const double a2Rate = 0.25 * cell.positioner.rotation.limit.maxSpeed / cell.process.weldSpeed;
  std::size_t pathsDone = 0, merged = 0, inserted = 0;
  double refA1 = 0.0, refA2 = options.initialA2;
  bool haveRef = false;
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    for (std::size_t p = 0; p < plan.layers[l].paths.size(); ++p) {
      std::vector<detail::AngleSample> samples =
          detail::sampleDepositions(plan.layers[l].paths[p], cell.positioner, gravity, options,
                                    merged, targets != nullptr ? &(*targets)[l][p] : nullptr);
      detail::planPathAngles(cell.positioner, gravity, a2Rate, samples, refA1, refA2, haveRef,
                             options);
      for (const auto& s : samples) inserted += s.inserted ? 1 : 0;
      MotionPathSpan span{static_cast<int>(l), static_cast<int>(p), result.points.size(), 0, {}};
      appendPathPoints(static_cast<int>(l), static_cast<int>(p), samples, cell, gravity, options,
                       result, warnings);
      span.end = result.points.size();
      result.paths.push_back(span);
      progress.report(static_cast<double>(++pathsDone) / static_cast<double>(pathTotal),
                      "positioner angles");
    }
  }
  if (merged > 0) {
    result.notes.push_back(std::to_string(merged) + " path point(s) closer than " +
                           fmt(options.mergeTolerance, 4) +
                           " mm to the previous one merged (the first kept)");
  }
  if (inserted > 0) {
    result.notes.push_back(std::to_string(inserted) +
                           " point(s) inserted so that a2 steps at most " +
                           fmt(options.maxA2Step / kDeg, 2) + " deg between path points");
  }
}

// ---- weld process per point ----------------------------------------------------

/// The plan's bead width at a motion point (0: the plan's bead spacing); inserted points and
/// the closing move of a closed path take the plan point they follow / repeat.
double planWidthAt(const Plan& plan, const MotionPoint& m) {
  const std::vector<PathPoint>& points =
      plan.layers[static_cast<std::size_t>(m.layer)].paths[static_cast<std::size_t>(m.path)].points;
  if (points.empty()) return 0.0;
  const auto i = static_cast<std::size_t>(std::max(m.index, 0));
  return points[i < points.size() ? i : 0].width;
}

/// Bead width, wire feed and weld speed of every path point: where the plan gives a bead width
/// (adaptive width) and the cell has a bead model, the model's WFS and TS for that width at the
/// plan's layer thickness (warning where the model cannot reach both); elsewhere the cell's wire
/// feed and weld speed (the process set up for the nominal bead, the bead spacing).
void assignWeldProcess(const Plan& plan, const Cell& cell, MotionPlan& result,
                       WarningLog& warnings) {
  const ProcessDescription& process = cell.process;
  const double height = plan.parameters.layerThickness;
  const bool useModel = !process.beadModel.empty() && height > 0.0;
  std::map<double, BeadSetting> settings;  // per bead width (one layer height per plan)
  bool widths = false;                     // the plan gives bead widths (adaptive width)
  for (MotionPoint& m : result.points) {
    if (m.kind != MoveKind::Path) continue;
    const double width = planWidthAt(plan, m);
    m.beadWidth = width > 0.0 ? width : plan.parameters.beadSpacing;
    if (!m.arcOn) continue;
    m.wireFeed = process.wireFeed;
    m.nominalSpeed = process.weldSpeed;
    widths = widths || width > 0.0;
    if (!useModel || !(width > 0.0)) continue;
    auto it = settings.find(width);
    if (it == settings.end()) {
      it = settings.emplace(width, solveBeadSetting(process.beadModel, width, height)).first;
    }
    const BeadSetting& b = it->second;
    m.wireFeed = b.wireFeed;
    m.speed = b.travelSpeed;
    m.nominalSpeed = b.travelSpeed;
    if (!b.reached) {
      warnings.add(
          "bead model cannot give the bead width at the layer thickness (nearest table "
          "setting used)",
          pointName(m) + ": wanted " + fmt(width, 2) + " x " + fmt(height, 2) + " mm, model " +
              fmt(b.achieved.width, 2) + " x " + fmt(b.achieved.height, 2) + " mm (short by " +
              fmt(width - b.achieved.width, 2) + " x " + fmt(height - b.achieved.height, 2) +
              " mm) at WFS " + fmt(b.wireFeed, 2) + " m/min, TS " + fmt(b.travelSpeed, 2) +
              " mm/s");
    }
  }
  if (widths && !process.beadModel.empty() && !(height > 0.0)) {
    result.notes.push_back("bead model not used: the plan has no layer thickness (" +
                           fmt(height, 3) + " mm); cell wire feed and weld speed used");
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
  void setToolPoses(const MotionPathSpan& span, double roll);
  void solvePath(const MotionPathSpan& span);
  double centringRoll(const MotionPathSpan& span) const;
  void setConfiguration(MotionPathSpan& span);
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
  double roll = 0.0;
  for (std::size_t s = 0; s < result_.paths.size(); ++s) {
    MotionPathSpan& span = result_.paths[s];
    const Vec3 startX = previousX_;
    setToolPoses(span, roll);
    solvePath(span);
    if (!options_.toolAlongTravel) {
      // the torch is round: turn the fixed tool x about the torch axis so that joint 6 sits
      // in the middle of a quadrant away from ±180° (and its config bits stay put)
      const double centred = roll + centringRoll(span);
      if (std::abs(centred - roll) > 1e-9) {
        roll = centred;
        previousX_ = startX;
        setToolPoses(span, roll);
        solvePath(span);
      }
    }
    setConfiguration(span);
    recordFailures(span);
    previousJoints_ = result_.points[span.end - 1].joints;
    haveJoints_ = true;
    progress.report(static_cast<double>(s + 1) / static_cast<double>(result_.paths.size()),
                    "robot kinematics");
  }
  reportFailures();
}

/// TCP poses (independent of the robot joints). `roll` (rad) turns the fixed world tool x
/// about gravity (toolAlongTravel off).
void RobotKinematicsPass::setToolPoses(const MotionPathSpan& span, double roll) {
  const PositionerDescription& pos = cell_.positioner;
  const Vec3 fixedX = Eigen::AngleAxisd(roll, gravity_) * Vec3::UnitX();
  for (std::size_t k = span.begin; k < span.end; ++k) {
    MotionPoint& m = result_.points[k];
    const Pose partInWorld = computePartInWorld(pos, m.a1, m.a2);
    const Vec3 pointWorld = partInWorld * m.position;
    // travel direction: central difference along the path, turned into world
    const Vec3 next = k + 1 < span.end ? result_.points[k + 1].position : m.position;
    const Vec3 prev = k > span.begin ? result_.points[k - 1].position : m.position;
    Vec3 travel = partInWorld.linear() * (next - prev);
    if (!options_.toolAlongTravel) travel = fixedX;
    // the torch along gravity, or tilted by its lean (torch_tilt.hpp) to clear the deposit
    Vec3 z = gravity_;
    if (m.torchAngle > 0.0) {
      const Vec3 up = -(partInWorld.linear().transpose() * gravity_);
      z = -(partInWorld.linear() * detail::tiltedTorchUp(up, m.torchLean));
    }
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

/// The extra tool roll (rad) that moves the middle of joint 6's range along the path to the
/// nearest of ±45° + 360°k inside its limits; 0 when joint 6 does not follow the roll (a bent
/// torch) or the path has unreachable points. dJ6/droll is measured at the path's first point.
double RobotKinematicsPass::centringRoll(const MotionPathSpan& span) const {
  double low = kInf, high = -kInf;
  for (std::size_t k = span.begin; k < span.end; ++k) {
    const MotionPoint& m = result_.points[k];
    if (m.flags & kMotionRobotLimit) return 0.0;
    low = std::min(low, m.joints[5]);
    high = std::max(high, m.joints[5]);
  }
  const MotionPoint& first = result_.points[span.begin];
  constexpr double kProbe = 0.1;
  Pose turned = first.toolInRobotBase;
  turned.linear() = first.toolInRobotBase.linear() * Eigen::AngleAxisd(kProbe, Vec3::UnitZ());
  const IkResult ik = solveInverseKinematics(cell_.robot, turned * tcpInverse_, first.joints[3]);
  double slope = 0.0;
  for (const IkSolution& sol : ik.solutions) {
    if (sol.configuration != first.configuration) continue;
    slope = (unwrapNear(sol.joints[5], first.joints[5]) - first.joints[5]) / kProbe;
  }
  if (!(std::abs(std::abs(slope) - 1.0) < 0.2)) return 0.0;
  const JointLimit& limit = cell_.robot.joints[5];
  const double middle = 0.5 * (low + high), half = 0.5 * (high - low);
  double best = middle, bestDistance = kInf;
  for (int k = -2; k <= 2; ++k) {
    for (double centre : {-kPi / 4, kPi / 4}) {
      const double target = centre + k * kTwoPi;
      if (target - half < limit.min || target + half > limit.max) continue;
      if (std::abs(target - middle) < bestDistance) {
        bestDistance = std::abs(target - middle);
        best = target;
      }
    }
  }
  return (best - middle) / (slope > 0 ? 1.0 : -1.0);
}

/// The weld's configuration from its joint ranges with hysteresis; points outside its region
/// (a joint really crossing a boundary) are flagged and warned about.
void RobotKinematicsPass::setConfiguration(MotionPathSpan& span) {
  JointVector low, high;
  low.fill(kInf);
  high.fill(-kInf);
  for (std::size_t k = span.begin; k < span.end; ++k) {
    for (int j = 0; j < 6; ++j) {
      low[j] = std::min(low[j], result_.points[k].joints[j]);
      high[j] = std::max(high[j], result_.points[k].joints[j]);
    }
  }
  span.configuration = configurationOfRange(low, high, result_.points[span.begin].configuration);
  for (std::size_t k = span.begin; k < span.end; ++k) {
    MotionPoint& m = result_.points[k];
    if (isWithinConfiguration(m.joints, span.configuration)) continue;
    m.flags |= kMotionConfigurationChange;
    for (int j = 0; j < 6; ++j) {
      const double quadrantLow = span.configuration.quadrant[j] * kPi / 2;
      if (m.joints[j] < quadrantLow - kConfigurationTolerance ||
          m.joints[j] > quadrantLow + kPi / 2 + kConfigurationTolerance) {
        warnings_.add("joint " + std::to_string(j + 1) +
                          " passes a multiple of 90 deg within welds (a real motion, not rounding: "
                          "the programs state one configuration per weld, the quadrant of the "
                          "middle of its range, and run linear moves without configuration "
                          "monitoring: RAPID ConfL\\Off, KRL S/T on PTP only)",
                      pointName(m));
      }
    }
  }
}

/// The arc-off move to the path start may re-centre the wrist joints (R, T) by a turn; tries
/// that when the nearest start would run a joint into its limit along the path. The first path
/// has no previous joints: its shifts are taken from the controller's zero (the unshifted start
/// is the solution nearest to it), so a path that turns T by a whole turn can start a turn lower
/// or higher whatever the joint's zero offset.
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
    const std::size_t n = solvePathJoints(span, shiftedStart(t), haveJoints_ || t > 0);
    lastRun = t;
    if (n < fewest) {
      fewest = n;
      bestShift = t;
    }
    if (n == 0) break;
  }
  if (bestShift != lastRun) {
    solvePathJoints(span, shiftedStart(bestShift), haveJoints_ || bestShift > 0);
  }
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
      inside = inside && violatedInterference(cell_.robot, q) == nullptr;
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
      cost += 1e3 * std::max(0.0, interferenceExcess(cell_.robot, q));
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
    if ((m.flags & kMotionConfigurationChange) && m.configuration != span.configuration.branch) {
      warnings_.add("robot configuration (IK branch) changes within a weld (joint limits)",
                    pointName(m));
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
    if (const JointInequality* limit = violatedInterference(cell_.robot, m.joints)) {
      joints += std::string(joints.empty() ? "" : ", ") + "interference limit " + limit->name +
                " (robot/interference)";
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

}  // namespace

namespace {

std::string mm(double value) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(1);
  out << value;
  return out.str();
}

/// The deepest collision with `obstacle` in `motion` (index into motion.collisions), or -1.
int deepestHit(const MotionPlan& motion, CollisionObstacle obstacle) {
  int deepest = -1;
  for (std::size_t k = 0; k < motion.collisions.size(); ++k) {
    const CollisionReport& c = motion.collisions[k];
    if (c.obstacle != obstacle) continue;
    if (deepest < 0 || c.depth > motion.collisions[deepest].depth) deepest = static_cast<int>(k);
  }
  return deepest;
}

/// The note of the torch angles used (none when every torch runs along gravity).
void noteTorchTilts(const detail::TorchTiltSummary& tilt, const ProcessDescription& process,
                    MotionPlan& result) {
  if (tilt.tilted == 0) return;
  result.notes.push_back("torch tilted off gravity on " + std::to_string(tilt.tilted) +
                         " path point(s) to clear the deposit, the table or the fixture: "
                         "largest " +
                         mm(tilt.maxAngle / kDeg) + " deg (torch window " +
                         mm(process.maxTorchAngle / kDeg) + " deg, process/max_torch_angle_deg)");
}

// ---- gravity deviation --------------------------------------------------------------------

/// rad (1°): how far inside the torch window a torch that needed a gravity deviation is left,
/// so that the torch search, run again on the turned part, finds its clearing direction within
/// the window despite its finite set of directions.
constexpr double kDeviationMargin = 0.0174532925199433;

/// Where the torch pass with the torch and gravity deviation windows together tilted a torch
/// further than the torch window, the V for the positioner: the V it aligned turned by the
/// excess (plus kDeviationMargin, at most the gravity deviation window) towards the torch's
/// lean, so that gravity in the part frame moves towards the torch and the same torch
/// direction relative to the part lies within the torch window off gravity. The tilts are
/// smooth along a path (at most kTiltRate), so are these deviations. Empty when no torch needs
/// one.
DeviationTargets gravityDeviationTargets(const Plan& plan, const MotionPlan& motion,
                                         const ProcessDescription& process) {
  const double start = std::max(0.0, process.maxTorchAngle - kDeviationMargin);
  std::size_t points = 0;
  DeviationTargets targets(plan.layers.size());
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    targets[l].resize(plan.layers[l].paths.size());
    for (std::size_t p = 0; p < plan.layers[l].paths.size(); ++p) {
      targets[l][p].assign(plan.layers[l].paths[p].points.size(), Vec3::Zero());
    }
  }
  for (const MotionPoint& m : motion.points) {
    if (m.kind != MoveKind::Path || (m.flags & kMotionInserted) || m.torchAngle <= start) continue;
    std::vector<Vec3>& path =
        targets[static_cast<std::size_t>(m.layer)][static_cast<std::size_t>(m.path)];
    if (m.index < 0 || static_cast<std::size_t>(m.index) >= path.size()) continue;  // closing move
    const double deviation = std::min(process.maxGravityDeviation, m.torchAngle - start);
    const Vec3 up = -m.usedDeposition.normalized();
    const Vec3 toward = m.torchLean - up * up.dot(m.torchLean);
    if (!(toward.norm() > 1e-12)) continue;
    path[static_cast<std::size_t>(m.index)] =
        -detail::tiltedTorchUp(up, deviation * toward.normalized());
    ++points;
  }
  if (points == 0) targets.clear();
  return targets;
}

/// The note of the gravity deviations used to clear the torch (none: no note).
void noteGravityDeviations(const MotionPlan& motion, const ProcessDescription& process,
                           MotionPlan& result) {
  std::size_t count = 0;
  double largest = 0.0;
  for (const MotionPoint& m : motion.points) {
    if (m.kind != MoveKind::Path || !(m.flags & kMotionGravityDeviated)) continue;
    ++count;
    largest = std::max(largest, m.residual);
  }
  if (count == 0) return;
  result.notes.push_back("deposition direction turned off gravity on " + std::to_string(count) +
                         " path point(s) where no torch angle within the torch window clears: "
                         "largest " +
                         mm(largest / kDeg) + " deg (gravity deviation window " +
                         mm(process.maxGravityDeviation / kDeg) +
                         " deg, process/max_gravity_deviation_deg)");
}

/// Per layer and in total the largest torch angle and gravity deviation of the path points.
void recordDeviations(MotionPlan& result) {
  for (const MotionPoint& m : result.points) {
    if (m.kind != MoveKind::Path) continue;
    for (MotionEstimate* e : {&result.total, &result.layers[static_cast<std::size_t>(m.layer)]}) {
      e->maxTorchAngle = std::max(e->maxTorchAngle, m.torchAngle);
      e->maxGravityDeviation = std::max(e->maxGravityDeviation, m.residual);
    }
  }
}

/// PartPlacement::Auto (planMotion's comment): raise the riser until the torch clears the table.
MotionPlan planMotionOnLowestRiser(const Plan& plan, const Cell& givenCell,
                                   const MotionOptions& options, const Progress& progress) {
  constexpr int kAttempts = 12;
  constexpr double kMargin = 2.0;  // mm above the deepest reach into the table
  Cell cell = givenCell;
  FixtureGeometry& fixture = cell.positioner.fixture;
  const Pose restPose = placePart(plan, cell, PartPlacement::Rest).tableToPart;
  fixture.riserDiameter = riserDiameterFor(plan, cell, restPose);
  const double firstDiameter = fixture.riserDiameter;
  // without a substrate plate the riser's top carries the first layer's beads laid on it: it is
  // never narrowed below them
  const double support = fixture.hasSubstrate() ? 0.0 : supportDiameterFor(plan, restPose);
  const double narrowest = std::max(0.25 * firstDiameter, support);
  MotionOptions trial = options;
  trial.placement = PartPlacement::Rest;
  trial.allowCollisions = true;  // to see every collision of a trial height
  std::string tried;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    const double lo = 1.0 - std::pow(0.5, attempt), hi = 1.0 - std::pow(0.5, attempt + 1);
    tried += (tried.empty() ? "" : ", ") + mm(fixture.riserHeight) +
             (fixture.riserDiameter < firstDiameter ? " (" + mm(fixture.riserDiameter) + " across)"
                                                    : std::string());
    MotionPlan motion;
    try {
      validateFixture(fixture, cell.positioner.geometry, "part placement auto: fixture ");
      motion = planMotion(plan, cell, trial, progress.sub(lo, hi));
    } catch (const InvalidInput& e) {
      if (attempt == 0) throw;
      throw InvalidInput("part placement auto: a riser of " + mm(fixture.riserHeight) +
                         " mm, needed to keep the torch clear of the table, leaves the part "
                         "outside what the cell can run: " +
                         e.what());
    }
    const int table = deepestHit(motion, CollisionObstacle::Table);
    if (table >= 0) {
      fixture.riserHeight += motion.collisions[table].depth + kMargin;
      continue;
    }
    // a riser this placement chose (the cell gives none) is narrowed by the torch's deepest
    // reach into it, down to a quarter of its first width and never below the beads it carries:
    // a part standing on it with a raised start surface (a mandrel) or a plate then overhangs it
    const int riserHit = deepestHit(motion, CollisionObstacle::Riser);
    const double narrowed =
        riserHit < 0 ? 0.0
                     : fixture.riserDiameter - 2.0 * (motion.collisions[riserHit].depth + kMargin);
    const bool choosesRiser = !(givenCell.positioner.fixture.riserDiameter > 0.0);
    if (riserHit >= 0 && choosesRiser && narrowed >= narrowest && !options.allowCollisions) {
      fixture.riserDiameter = narrowed;
      continue;
    }
    for (const CollisionObstacle obstacle :
         {CollisionObstacle::Riser, CollisionObstacle::Substrate}) {
      const int hit = deepestHit(motion, obstacle);
      if (hit < 0 || options.allowCollisions) continue;
      const CollisionReport& c = motion.collisions[hit];
      const bool riser = obstacle == CollisionObstacle::Riser;
      const bool carried = riser && choosesRiser && support > 0.0 &&
                           fixture.riserDiameter - 2.0 * (c.depth + kMargin) < support;
      throw InvalidInput(
          "part placement auto: on a riser of " + mm(fixture.riserHeight) + " mm the torch hits " +
          (riser ? "the riser" : "the substrate plate") + " at " + describeMove(motion, c.point) +
          " by " + mm(c.depth) + " mm, which no riser height clears" +
          (carried ? " and a narrower riser would not carry the first layer's beads laid on it (" +
                         mm(support) + " mm across)"
                   : std::string()) +
          "; give " +
          (carried ? std::string("a substrate plate that carries them on a narrower riser "
                                 "(positioner/fixture substrate_size_mm and riser_diameter_mm), "
                                 "a wider torch or gravity deviation window "
                                 "(process/max_torch_angle_deg, max_gravity_deviation_deg)")
           : riser ? "a narrower riser (positioner/fixture riser_diameter_mm, now " +
                         mm(fixture.riserDiameter) + " mm)"
                   : "a smaller plate (positioner/fixture substrate_size_mm, now " +
                         mm(fixture.substrateSize) + " mm)") +
          ", or allow collisions (--allow-collisions) to export anyway");
    }
    const bool raised = fixture.riserHeight > givenCell.positioner.fixture.riserHeight;
    const std::string note =
        "part placement auto: " +
        (raised ? "a riser of " + mm(fixture.riserHeight) + " mm (" + mm(fixture.riserDiameter) +
                      " mm across) is the lowest tried that keeps the torch clear of the table and "
                      "the riser on every move (tried " +
                      tried + " mm)"
                : std::string("the torch clears the table on every move without raising the "
                              "cell's riser (") +
                      mm(fixture.riserHeight) + " mm)");
    // Collisions with the deposit remain errors unless allowed: plan once more as asked.
    if (!motion.collisions.empty() && !options.allowCollisions) {
      MotionOptions asAsked = options;
      asAsked.placement = PartPlacement::Rest;
      motion = planMotion(plan, cell, asAsked, progress.sub(hi, 1.0));
    }
    motion.notes.push_back(note);
    progress.report(1.0, "estimates");
    return motion;
  }
  throw InvalidInput("part placement auto: no riser up to " + mm(fixture.riserHeight) +
                     " mm (tried " + tried +
                     " mm) keeps the torch clear of the table; place the part "
                     "by hand (--placement cell) or use a slimmer torch envelope");
}

/// A note naming the layers that wait for the minimum layer time (none: no note).
void noteCoolingWaits(const ProcessDescription& process, MotionPlan& motion) {
  if (motion.total.cooledLayers == 0) return;
  double longest = 0.0;
  int where = -1;
  for (std::size_t l = 0; l < motion.layers.size(); ++l) {
    if (motion.layers[l].coolingWait > longest) {
      longest = motion.layers[l].coolingWait;
      where = static_cast<int>(l);
    }
  }
  motion.notes.push_back("minimum layer time " + fmt(process.minLayerTime, 1) +
                         " s: " + std::to_string(motion.total.cooledLayers) +
                         " layer(s) take less and wait the rest after "
                         "their last path, " +
                         fmt(motion.total.coolingWait, 1) + " s in all, longest " +
                         fmt(longest, 1) + " s after layer " + std::to_string(where) +
                         " (the cell's process/min_layer_time_s; 0 turns it off)");
}

}  // namespace

MotionPlan planMotion(const Plan& plan, const Cell& givenCell, const MotionOptions& options,
                      const Progress& progress) {
  if (options.placement == PartPlacement::Auto) {
    validateCell(givenCell);
    return planMotionOnLowestRiser(plan, givenCell, options, progress);
  }
  validateCell(givenCell);
  validateInputs(plan, options);
  // Placement (placement.hpp): the rest of the planning uses the cell with the part placed.
  const PartPlacementResult placement = placePart(plan, givenCell, options.placement);
  Cell cell = givenCell;
  cell.positioner.tableToPart = placement.tableToPart;
  checkPartPlacement(plan, cell.positioner);
  const Vec3 gravity = cell.gravity.normalized();
  MotionPlan result;
  result.tableToPart = placement.tableToPart;
  result.fixture = cell.positioner.fixture;
  result.notes = givenCell.notes;
  if (!placement.note.empty()) result.notes.push_back(placement.note);
  result.points.reserve(plan.pointCount() + plan.pathCount());
  const std::vector<std::string> cellNotes = result.notes;
  WarningLog warnings;
  planPositionerAngles(plan, cell, gravity, options, progress.sub(0.0, 0.3), result, warnings);
  assignWeldProcess(plan, cell, result, warnings);
  const TravelSetup travel = travelSetupOf(cell);
  const double beadRadius = depositBeadRadius(plan.parameters);
  validateCollisionGeometry(travel.geometry, beadRadius);
  // The torch window and the gravity deviation window together bound how far the torch may
  // lean against the part; where it leans further than the torch window, the positioner turns
  // V off gravity by the excess (gravityDeviationTargets) and the torch is searched again.
  const ProcessDescription& process = cell.process;
  detail::TorchTiltSummary tilt =
      detail::planTorchTilts(result, cell, travel.geometry, gravity, beadRadius,
                             process.maxTorchAngle + process.maxGravityDeviation,
                             progress.sub(0.3, 0.35), process.maxTorchAngle);
  const DeviationTargets targets =
      process.maxGravityDeviation > 0.0 && tilt.maxAngle > process.maxTorchAngle
          ? gravityDeviationTargets(plan, result, process)
          : DeviationTargets{};
  if (!targets.empty() || tilt.maxAngle > process.maxTorchAngle) {
    MotionPlan turned;
    turned.tableToPart = result.tableToPart;
    turned.fixture = result.fixture;
    turned.notes = cellNotes;
    turned.points.reserve(result.points.size());
    WarningLog turnedWarnings;
    planPositionerAngles(plan, cell, gravity, options, progress.sub(0.35, 0.37), turned,
                         turnedWarnings, targets.empty() ? nullptr : &targets);
    assignWeldProcess(plan, cell, turned, turnedWarnings);
    tilt = detail::planTorchTilts(turned, cell, travel.geometry, gravity, beadRadius,
                                  process.maxTorchAngle, progress.sub(0.37, 0.4), 0.0, &result);
    result = std::move(turned);
    warnings = std::move(turnedWarnings);
  }
  noteTorchTilts(tilt, cell.process, result);
  noteGravityDeviations(result, cell.process, result);
  RobotKinematicsPass(cell, gravity, options, result, warnings).run(progress.sub(0.4, 0.95));
  result.nearSingularBand = options.nearSingularBand;
  planArcOffMoves(plan, cell, travel, options, result, progress.sub(0.95, 0.95));
  progress.report(0.95, "estimates");
  warnings.flush(result.warnings);
  // time parameterisation (after the travel moves): times, speeds, estimates
  result.total = estimatePlan(plan, cell.process, &result.layers);
  parameteriseTime(result, cell, TimingOptions{options.timeParameterise});
  noteCoolingWaits(cell.process, result);
  recordDeviations(result);
  progress.report(1.0, "estimates");
  return result;
}

}  // namespace curvedslicer
