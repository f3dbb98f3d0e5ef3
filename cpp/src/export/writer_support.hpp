// Internal helpers shared by the program writers: units, controller angles, names, the walk over
// the motion points with progress, where arc-on segments, dwells and layers begin and end, which
// moves are joint moves, and the robot configuration each point states (one per weld).
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/export/program_text.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/configuration.hpp"
#include "curvedslicer/robot/motion.hpp"

namespace curvedslicer::export_detail {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kRadToDeg = 180.0 / kPi;

/// Positioner tilt in controller degrees (sign applied).
inline double tiltDegrees(const Cell& cell, double a1) {
  return cell.positioner.tilt.sign * a1 * kRadToDeg;
}
/// Positioner rotation in controller degrees (sign applied).
inline double rotationDegrees(const Cell& cell, double a2) {
  return cell.positioner.rotation.sign * a2 * kRadToDeg;
}

/// Speed (mm/s) in the controller's unit of the cell.
inline double controllerSpeed(const Cell& cell, double mmPerSecond) {
  switch (cell.process.speedUnit) {
    case SpeedUnit::CentimetresPerMinute:
      return mmPerSecond * 6.0;
    case SpeedUnit::MillimetresPerMinute:
      return mmPerSecond * 60.0;
    case SpeedUnit::MillimetresPerSecond:
      break;
  }
  return mmPerSecond;
}

/// Decimals for a speed in the cell's unit: 1 for mm/s, 0 for per-minute units.
inline int speedDecimals(const Cell& cell) {
  return cell.process.speedUnit == SpeedUnit::MillimetresPerSecond ? 1 : 0;
}

/// The requested program name or the cell's.
inline std::string baseProgramName(const Cell& cell, const ExportOptions& options) {
  return options.programName.empty() ? cell.exportOptions.jobName : options.programName;
}

/// Throws InvalidInput if the motion plan has no points.
inline void requirePoints(const MotionPlan& motion, std::string_view format) {
  if (motion.points.empty()) {
    throw InvalidInput(std::string(format) +
                       " export: the motion plan has no points: 0; plan at least one path");
  }
}

/// True if point i is a path end and the path is its layer's last: the next weld point (the next
/// MoveKind::Path point, past the retract / travel / approach / home points), if any, lies in
/// another layer. Cost: the arc-off points after i.
inline bool endsLayer(const MotionPlan& motion, std::size_t i) {
  const auto& p = motion.points[i];
  if (!p.pathEnd) return false;
  for (std::size_t k = i + 1; k < motion.points.size(); ++k) {
    if (motion.points[k].kind == MoveKind::Path) return motion.points[k].layer != p.layer;
  }
  return true;
}

/// Dwell (s) that belongs to point i's path end: the path dwell plus, after the last path of a
/// layer, the layer dwell and the wait for the minimum layer time that timing gave the layer;
/// 0 if i is no path end.
inline double pathEndDwell(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  const auto& p = motion.points[i];
  if (!p.pathEnd) return 0.0;
  double dwell = cell.process.pathDwell;
  if (endsLayer(motion, i)) {
    dwell += cell.process.layerDwell;
    if (p.layer >= 0 && static_cast<std::size_t>(p.layer) < motion.layers.size()) {
      dwell += motion.layers[static_cast<std::size_t>(p.layer)].coolingWait;
    }
  }
  return dwell;
}

/// Dwell (s) the program waits after point i: a path end's dwell (pathEndDwell) is waited with
/// the torch lifted off the part, i.e. after the retract that follows the path end, or after the
/// path end itself where no retract follows (a motion without travel moves).
inline double dwellAfter(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  const auto& p = motion.points[i];
  if (p.pathEnd) {
    const bool retractFollows =
        i + 1 < motion.points.size() && motion.points[i + 1].kind == MoveKind::Retract;
    return retractFollows ? 0.0 : pathEndDwell(motion, cell, i);
  }
  if (p.kind == MoveKind::Retract && i > 0 && motion.points[i - 1].pathEnd) {
    return pathEndDwell(motion, cell, i - 1);
  }
  return 0.0;
}

/// Reports progress every 4096 points (and cancels through Progress).
inline void reportEvery(const Progress& progress, std::size_t i, std::size_t count) {
  if ((i & 4095u) == 0) {
    progress.report(static_cast<double>(i) / static_cast<double>(count), "export");
  }
}

/// A pose as x y z (mm) and fixed-axis roll/pitch/yaw (deg), R = Rz(yaw)·Ry(pitch)·Rx(roll).
struct XyzRpy {
  double x, y, z, roll, pitch, yaw;
};
inline XyzRpy toXyzRpy(const Pose& pose) {
  const Vec3 t = pose.translation();
  const Vec3 rpy = rollPitchYaw(pose.rotation()) * kRadToDeg;
  return {t.x(), t.y(), t.z(), rpy.x(), rpy.y(), rpy.z()};
}

/// Appends ",value" for each value with fixed decimals.
inline void appendList(std::string& out, std::initializer_list<double> values, int decimals,
                       std::string_view separator = ",") {
  bool first = true;
  for (double v : values) {
    if (!first) out.append(separator);
    first = false;
    appendFixed(out, v, decimals);
  }
}

/// Appends the shortest decimal form of `value` that reads back to the same double.
inline void appendShortest(std::string& out, double value) {
  if (!std::isfinite(value)) {
    throw InvalidInput("a value to export is not a finite number: " + std::to_string(value) +
                       "; check the plan and the cell for NaN or infinite entries");
  }
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, static_cast<std::size_t>(end - buf));
}

/// The cell's positioner signs and the pose of the part for controller angles in degrees (the
/// inverse of tiltDegrees / rotationDegrees).
inline double tiltFromDegrees(const Cell& cell, double degrees) {
  return cell.positioner.tilt.sign * degrees / kRadToDeg;
}
inline double rotationFromDegrees(const Cell& cell, double degrees) {
  return cell.positioner.rotation.sign * degrees / kRadToDeg;
}

/// Joint speed (percent of every axis's maximum) of a joint move whose duration is not planned:
/// the program's first move, from wherever the robot stands.
inline constexpr double kUnplannedJointSpeedPercent = 10.0;

/// True if the move arriving at point i is a joint move (MOVJ / PTP / MoveAbsJ / J / G0): the
/// program's first move (from an unknown pose) and every move to the cell's home pose. Every
/// other move is linear: welds at the weld speed, retract / travel / approach and the move onto
/// a path start at the travel speed (MotionPoint::speed).
inline bool isJointMove(const MotionPlan& motion, std::size_t i) {
  return i == 0 || motion.points[i].kind == MoveKind::Home;
}

/// Joint speed (percent) of the joint move arriving at point i: the slowest that still takes no
/// longer than the planned duration (MotionPoint::time difference minus the dwell the time
/// parameterisation counts in between: robot/timing.hpp counts a path's dwell at its path end),
/// i.e. 100 · max over the 6 robot joints and both positioner axes of |Δq| / (duration · max
/// speed), rounded up to 0.01 % and kept within [1, 100]; kUnplannedJointSpeedPercent for the
/// first move and where the plan has no positive duration (times not parameterised).
double jointSpeedPercent(const MotionPlan& motion, const Cell& cell, std::size_t i);

/// Decimals of a speed in the cell's unit: 1 for mm/s, 0 for per-minute units (speedDecimals).
/// Appends `mmPerSecond` in the controller's unit with `decimals` decimals: rounded to nearest,
/// except where the planner lowered the weld speed (kMotionSpeedReduced): rounded down, so a
/// reduced speed is written as reduced and no axis is asked for more than its limit; never below
/// one unit of the last decimal.
inline void appendSpeed(std::string& out, double value, int decimals, bool reduced) {
  if (reduced) {
    const double scale = std::pow(10.0, decimals);
    const double down = std::floor(value * scale + 1e-9) / scale;
    value = std::max(down, 1.0 / scale);
  }
  appendFixed(out, value, decimals);
}

/// True if the planner lowered the weld speed of the move arriving at `p`.
inline bool speedReduced(const MotionPoint& p) {
  return (p.flags & kMotionSpeedReduced) != 0u;
}

/// Wire feed (m/min) of the move arriving at point p: MotionPoint::wireFeed where the motion
/// plan sets it (> 0), else the cell's process wire feed.
inline double wireFeedOf(const Cell& cell, const MotionPoint& p) {
  return p.wireFeed > 0.0 ? p.wireFeed : cell.process.wireFeed;
}

/// One program of a split export: its name and the motion points it moves through.
struct ProgramPart {
  std::string name;
  IndexRange points;
};

/// Splits the motion into programs of at most `limit` lines: `costs[i]` = lines point i needs
/// (an upper bound), `headerLines` = lines every program adds (declarations, DEF/END, …). Cuts
/// go before arc-off points (a path start, retract, travel, approach, home) and inside a weld
/// only where one weld alone is longer than a program. One part named `mainName` if everything
/// fits, else parts named makeSubJobName(mainName, k, count, nameLimit) (called from a main
/// program the writer adds).
/// @throws InvalidInput if `limit` leaves no room for a point after the header, if a sub-program
///         name would equal `mainName`, or if the main program could not call all parts within
///         `limit` lines (`format` names the writer in messages).
std::vector<ProgramPart> splitIntoParts(const MotionPlan& motion,
                                        const std::vector<std::size_t>& costs,
                                        const std::string& mainName, std::size_t limit,
                                        std::size_t headerLines, std::size_t nameLimit,
                                        std::string_view format);

/// For every motion point, the MotionPlan::paths index of the weld it belongs to (the points of a
/// MotionPathSpan from its first point, the path start, to its end), or -1 for arc-off points
/// (retract, travel, approach, home). Cost: O(points).
/// @throws InvalidInput for a span outside the points or two spans claiming one point.
std::vector<int> mapPointsToSpans(const MotionPlan& motion);

/// Empty, or a warning when weld points lie in another IK branch (MotionPoint::configuration)
/// than their weld's stated configuration (MotionPathSpan::configuration.branch): the program
/// would then state a configuration the robot is not in. Names how many points and the first.
std::string describeBranchMismatches(const MotionPlan& motion);

/// The robot configuration the program states at each point: within a weld always the weld's
/// (MotionPathSpan::configuration, chosen by planMotion with hysteresis, constant from the path
/// start to the path end); at arc-off points the configuration of the point's own joints
/// (configurationOf(joints, MotionPoint::configuration)). Never a per-point recomputation inside
/// a weld, so rounding noise (J4 at ±1e-16°, J6 near -180°) cannot flip a bit there.
class PointConfigurations {
 public:
  explicit PointConfigurations(const MotionPlan& motion)
      : motion_(motion), spans_(mapPointsToSpans(motion)) {}
  RobotConfiguration at(std::size_t i) const {
    const int span = spans_[i];
    if (span >= 0) return motion_.paths[static_cast<std::size_t>(span)].configuration;
    const MotionPoint& p = motion_.points[i];
    return configurationOf(p.joints, p.configuration);
  }
  /// MotionPlan::paths index of point i's weld, or -1.
  int spanOf(std::size_t i) const { return spans_[i]; }

 private:
  const MotionPlan& motion_;
  std::vector<int> spans_;
};

}  // namespace curvedslicer::export_detail
