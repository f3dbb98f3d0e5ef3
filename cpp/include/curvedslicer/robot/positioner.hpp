// Two-axis tilt-rotate positioner: forward kinematics and gravity alignment of a direction
// (paper §3.2, eq. 16: turn the rotation axis by a2 so that V lies in the plane normal to the
// tilt axis, then tilt by a1 so that it points along gravity G).
//
// Method: eq. 16 for general (not necessarily perpendicular) axes, in closed form: the tilt a1
// must bring G, turned back about the tilt axis, to the cone of directions the rotation axis can
// turn V onto (same angle to the rotation axis as V): A·cos a1 + B·sin a1 = d, two solutions
// a1 = atan2(B, A) ± acos(d / hypot(A, B)) (the two branches); a2 then turns V onto that
// direction about the rotation axis (Paden–Kahan subproblem 1). For the usual cell (tilt about
// x, rotation about the table z, gravity -z) this is a2 = atan2(vx, vy) and |a1| the angle of V
// to -z, the second branch (a2 + π, -a1).
// Preconditions: unit axis directions; cell validated. Cost: a few dozen flops.
#pragma once

#include <array>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/robot/cell.hpp"

namespace curvedslicer {

/// Positioner joint angles (model convention, rad).
struct PositionerAngles {
  double a1 = 0.0;  ///< tilt
  double a2 = 0.0;  ///< rotation
};

/// Table frame in the positioner base frame at a1 = a2 = 0.
Pose computeTableZeroPose(const PositionerDescription& positioner);

/// Part frame in the positioner base frame for joint angles (a1, a2).
Pose computePartInPositionerBase(const PositionerDescription& positioner, double a1, double a2);

/// Part frame in world: positioner.base · computePartInPositionerBase.
Pose computePartInWorld(const PositionerDescription& positioner, double a1, double a2);

/// Table frame (turning with a1, a2) in world.
Pose computeTableInWorld(const PositionerDescription& positioner, double a1, double a2);

/// Result of the gravity alignment of one direction.
struct GravityAlignment {
  std::array<PositionerAngles, 2> branches;  ///< both closed-form solutions, a2 in (-π, π]
  bool feasible = true;    ///< false: no angles align V exactly (axes not general enough); the
                           ///< branches then hold the closest alignment
  double axisAngle = 0.0;  ///< rad, angle between V and the rotation-axis line (0 .. π/2);
                           ///< small = singular (a2 undetermined)
};

/// Solves eq. 16: both (a1, a2) with R_tilt(a1)·R_rot(a2)·V = G. `depositionInPart` is V in the
/// part frame (unit), `gravityInWorld` G in world (unit). Joint limits are not applied.
GravityAlignment alignWithGravity(const PositionerDescription& positioner,
                                  const Vec3& depositionInPart, const Vec3& gravityInWorld);

/// The tilt a1 that, for a fixed a2, turns V closest to gravity (used in the singular zone and
/// at a rotation limit); unconstrained, in (-π, π].
double optimalTiltForRotation(const PositionerDescription& positioner, const Vec3& depositionInPart,
                              const Vec3& gravityInWorld, double a2);

/// The rotation a2 that, for a fixed a1, turns V closest to gravity (used at a tilt limit).
double optimalRotationForTilt(const PositionerDescription& positioner, const Vec3& depositionInPart,
                              const Vec3& gravityInWorld, double a1);

/// Angle (rad) between V transformed by the positioner at (a1, a2) and gravity.
double computeGravityResidual(const PositionerDescription& positioner, const Vec3& depositionInPart,
                              const Vec3& gravityInWorld, double a1, double a2);

/// Recovers (a1, a2) from a part pose in the positioner base frame (inverse of
/// computePartInPositionerBase for poses it can produce); a2 in (-π, π].
PositionerAngles solvePositionerPose(const PositionerDescription& positioner,
                                     const Pose& partInPositionerBase);

/// angle + 2πk for the integer k that puts it closest to `reference` (rad).
double unwrapNear(double angle, double reference);

}  // namespace curvedslicer
