// A hand-made motion plan for the configuration and arc-off tests: the arc-off points a planned
// motion has (home at both ends, approach, retract, travel) around two welds whose joints sit on
// the boundaries rounding noise flips (J4 exactly 0 among ±1e-16 rad; J6 crossing -180°), with
// MotionPathSpan::configuration set as planMotion's hysteresis keeps it (the first point's), and
// the reading back of a robot program of any of the four formats.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/robot/configuration.hpp"
#include "export_test_support.hpp"
#include "program_readers.hpp"
#include "program_readers_krl_rapid.hpp"

namespace curvedslicer::testing {

/// A hand-made point of `kind` at `position` (part frame) with robot joints `joints`.
inline MotionPoint makePoint(MoveKind kind, int path, int index, const Vec3& position,
                             const JointVector& joints, int branch, double speed) {
  MotionPoint p;
  p.kind = kind;
  p.layer = 0;
  p.path = path;
  p.index = index;
  p.position = position;
  p.a1 = 0.2;
  p.a2 = 0.1 * index;
  p.joints = joints;
  p.configuration = branch;
  const Vec3 rpy(kPiT, 0.0, 0.0);
  p.toolInRobotBase = makePose(Vec3(1100.0, 0.0, 530.0) + position, rpy);
  p.toolInWorld = p.toolInRobotBase;
  p.toolInTable = makePose(position, rpy);
  p.toolInPart = p.toolInTable;
  p.speed = speed;
  return p;
}

/// Appends a weld of `n` points whose joint `noisyJoint` takes the values `noise` in turn (rad),
/// with the span's configuration that of the first point (as planMotion's hysteresis would keep).
inline void addWeld(MotionPlan& motion, int path, const JointVector& base, int noisyJoint,
                    const std::vector<double>& noise, int branch, double z) {
  MotionPathSpan span;
  span.layer = 0;
  span.path = path;
  span.begin = motion.points.size();
  const double time = motion.points.empty() ? 0.0 : motion.points.back().time;
  for (std::size_t i = 0; i < noise.size(); ++i) {
    JointVector q = base;
    q[noisyJoint] = noise[i];
    q[0] += 0.01 * static_cast<double>(i);
    MotionPoint p = makePoint(MoveKind::Path, path, static_cast<int>(i),
                              Vec3(-20.0 + 5.0 * static_cast<double>(i), 10.0 * path, z), q, branch,
                              i == 0 ? 50.0 : 8.0);
    p.pathStart = i == 0;
    p.pathEnd = i + 1 == noise.size();
    p.arcOn = i > 0;
    p.time = time + 1.0 + static_cast<double>(i);
    motion.points.push_back(p);
  }
  span.end = motion.points.size();
  const MotionPoint& first = motion.points[span.begin];
  span.configuration = configurationOf(first.joints, first.configuration);
  motion.paths.push_back(span);
}

/// Home, approach, weld 0 (J4 exactly 0 among ±1e-16 rad), retract, travel, approach, weld 1
/// (J6 crossing -180° by ±1e-13 rad, wrist flip branch), retract, home. Arc-off points have
/// joints of their own (J4 -17°, J6 -143°) so their stated configuration differs from the welds'.
inline MotionPlan makeNoisyMotion() {
  MotionPlan motion;
  const JointVector home{0.0, 0.0, 0.0, 0.0, -1.5707963267948966, 0.0};
  const JointVector offArc{0.4, 0.3, -0.2, -0.3, -0.9, -2.5};
  const auto addOff = [&](MoveKind kind, int path, const Vec3& at, const JointVector& q) {
    MotionPoint p = makePoint(kind, path, -1, at, q, 0, 50.0);
    p.time = motion.points.empty() ? 0.0 : motion.points.back().time + 1.0;
    motion.points.push_back(p);
  };
  addOff(MoveKind::Home, 0, Vec3(0, 0, 300), home);
  addOff(MoveKind::Approach, 0, Vec3(-20, 0, 12), offArc);
  addWeld(motion, 0, {0.5, 0.2, -0.3, 0.0, -0.8, 0.3}, 3, {0.0, 1e-16, -1e-16, 0.0, -1e-16, 1e-16},
          0, 2.0);
  addOff(MoveKind::Retract, 0, Vec3(5, 0, 12), offArc);
  addOff(MoveKind::Travel, 1, Vec3(-7, 5, 12), offArc);
  addOff(MoveKind::Approach, 1, Vec3(-20, 10, 12), offArc);
  addWeld(motion, 1, {0.5, 0.2, -0.3, 0.2, 0.8, 0.0}, 5,
          {-kPiT + 1e-13, -kPiT - 1e-13, -kPiT, -kPiT + 1e-13, -kPiT - 1e-13}, 4, 2.0);
  addOff(MoveKind::Retract, 1, Vec3(0, 10, 12), offArc);
  addOff(MoveKind::Home, 1, Vec3(0, 0, 300), home);
  return motion;
}

/// The program of `format` for `motion`, read back.
inline ReadProgram exportAndRead(const MotionPlan& motion, const Cell& cell, ExportFormat format) {
  const ExportResult r = exportProgram(motion, cell, format);
  switch (format) {
    case ExportFormat::Jbi:
      return readJbiProgram(r, cell);
    case ExportFormat::Krl:
      return readKrlExport(r, cell).program;
    case ExportFormat::Rapid:
      return readRapidExport(r, cell).program;
    case ExportFormat::Ls:
      return readLsProgram(r, cell);
    default:
      break;
  }
  ADD_FAILURE() << "no reader for " << toString(format);
  return {};
}

inline constexpr ExportFormat kRobotFormats[] = {ExportFormat::Jbi, ExportFormat::Krl,
                                                 ExportFormat::Rapid, ExportFormat::Ls};

}  // namespace curvedslicer::testing
