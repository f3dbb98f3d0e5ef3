// Internal helpers shared by the program writers: units, controller angles, names, the walk over
// the motion points with progress, and where arc-on segments, dwells and layers begin and end.
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/export/program_text.hpp"
#include "curvedslicer/robot/cell.hpp"
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

/// True if, after point i, a layer ends (i is a path end and the next point, if any, lies in
/// another layer).
inline bool endsLayer(const MotionPlan& motion, std::size_t i) {
  const auto& p = motion.points[i];
  return p.pathEnd && (i + 1 == motion.points.size() || motion.points[i + 1].layer != p.layer);
}

/// Dwell (s) after point i: the path dwell after every path end plus the layer dwell after the
/// last path of a layer.
inline double dwellAfter(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  const auto& p = motion.points[i];
  if (!p.pathEnd) return 0.0;
  double dwell = cell.process.pathDwell;
  if (endsLayer(motion, i)) dwell += cell.process.layerDwell;
  return dwell;
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

}  // namespace curvedslicer::export_detail
