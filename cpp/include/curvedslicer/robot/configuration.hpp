// Robot configuration as controllers state it: the IK branch (shoulder, elbow, wrist) and, per
// joint, the quadrant (ABB cf1/cf4/cf6), the turn number (Fanuc J1/J4/J6 turns), the sign (KUKA
// Turn bits) and whether it is at or beyond ±180° (Yaskawa RCONF R/T/S bits). A weld must not
// change any of these: planMotion chooses one configuration per path (MotionPathSpan) with
// hysteresis so that joints sitting on a boundary (J4 at ±1e-16°, J6 near -180°) do not decide
// it from rounding noise; the exporters write that, never a per-point recomputation inside a weld.
// Cost: trivial.
#pragma once

#include <array>

#include "curvedslicer/robot/cell.hpp"

namespace curvedslicer {

struct RobotConfiguration {
  int branch = 0;  ///< IK bits: 1 = back (over the shoulder), 2 = elbow down, 4 = wrist flip
  std::array<int, 6> quadrant{};    ///< floor(q / 90°) per controller joint (ABB cf1, cf4, cf6)
  std::array<int, 6> turn{};        ///< floor((q + 180°) / 360°) (Fanuc turn numbers)
  std::array<bool, 6> negative{};   ///< q < 0 (KUKA Turn bit of the joint)
  std::array<bool, 6> beyond180{};  ///< |q| >= 180° (Yaskawa RCONF R, T, S bits)
  bool operator==(const RobotConfiguration&) const = default;
};

/// The configuration of one joint vector (controller convention, rad) with IK branch bits
/// `branch`, as a controller computes it: no hysteresis.
RobotConfiguration configurationOf(const JointVector& joints, int branch);

}  // namespace curvedslicer
