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

/// rad (0.1°): hysteresis of a configuration. Every boundary above (quadrant, turn, sign, ±180°)
/// is a multiple of 90°, so a configuration is a region of one quadrant per joint; a joint may
/// lie this far beyond its region's boundaries and still belong to it.
inline constexpr double kConfigurationTolerance = 0.00174532925199433;

/// The configuration of a weld whose joints range over [minJoints, maxJoints] (per joint, rad):
/// per joint the quadrant that holds the lowest value once it is raised by `tolerance`, so a
/// joint on a boundary (J4 at ±1e-16 rad) never decides from rounding noise. All joints of the
/// weld lie in it (isWithinConfiguration) unless a joint's range really crosses a boundary;
/// then that joint's quadrant is the one of the middle of its range.
RobotConfiguration configurationOfRange(const JointVector& minJoints, const JointVector& maxJoints,
                                        int branch, double tolerance = kConfigurationTolerance);

/// Whether `joints` lie in the quadrants of `configuration`, each widened by `tolerance`.
bool isWithinConfiguration(const JointVector& joints, const RobotConfiguration& configuration,
                           double tolerance = kConfigurationTolerance);

}  // namespace curvedslicer
