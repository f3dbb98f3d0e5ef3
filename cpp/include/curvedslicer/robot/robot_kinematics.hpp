// Forward and closed-form inverse kinematics of a six-axis robot with an ortho-parallel arm and a
// spherical wrist (RobotKinematics in cell.hpp: parameters a1, a2, b, c1..c4, the usual
// industrial geometry; method after Brandstötter, Angerer, Hofbaur 2014, "An analytical solution
// of the inverse kinematics problem of industrial serial manipulators with an ortho-parallel
// basis and a spherical wrist", derived and written here for this model's zero pose).
//
// Inverse kinematics: the wrist centre is the flange origin minus c4 along the flange axis;
// joint 1 from its azimuth (front/back), joint 3 from the law of cosines (elbow up/down), joint 2
// from the angle of the wrist centre in the arm plane, joints 4-6 as X-Y-X Euler angles of the
// wrist rotation (flip / no flip) — up to 8 solutions. Joint angles in and out are controller
// angles (rad), converted through RobotDescription::jointSigns/jointOffsets.
// Preconditions: validated cell. Cost: about a microsecond per call.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"

namespace curvedslicer {

/// Flange pose in the robot base frame for controller joint angles (rad).
Pose computeFlangePose(const RobotDescription& robot, const JointVector& joints);

/// The arm's joint points in the robot base frame (mm) for controller joint angles (rad), for
/// drawing the arm and checking it for collisions: base origin, joint 1's axis at the height of
/// joint 2 (c1), shoulder (joint 2 axis), elbow (joint 3 axis), the forearm's root (the elbow
/// moved by the forearm offset a2, where the joint-4 axis begins), wrist centre, flange origin
/// (= computeFlangePose(robot, joints).translation()); and `side`, the unit direction of joint 2's
/// axis (the model's y turned by joint 1).
struct ArmPoints {
  Vec3 base = Vec3::Zero();
  Vec3 column = Vec3::Zero();
  Vec3 shoulder = Vec3::Zero();
  Vec3 elbow = Vec3::Zero();
  Vec3 forearmRoot = Vec3::Zero();
  Vec3 wrist = Vec3::Zero();
  Vec3 flange = Vec3::Zero();
  Vec3 side = Vec3::UnitY();
};

/// Joint points of the arm for controller joint angles (rad), robot base frame (mm).
ArmPoints computeArmPoints(const RobotDescription& robot, const JointVector& joints);

/// The angle at the elbow (rad) between the upper arm (joint 3 towards joint 2) and the forearm
/// (joint 3 towards the wrist centre): π with the arm stretched, 0 with the forearm lying on the
/// upper arm.
double elbowAngle(const RobotDescription& robot, const JointVector& joints);

/// Elbow angle below which the arm counts as folded (the forearm on the upper arm): 10°. The
/// bundled KUKA and ABB arms, whose ranges come from the makers' descriptions, reach 17.9° and
/// 20.2° at their joint 3 limits, so this catches only a range no arm can travel.
inline constexpr double kFoldedElbowAngle = 0.17453292519943295;

/// A joint vector within the joint ranges and the interference limits whose elbow angle is below
/// `minElbowAngle`, searched on a 1° grid of joints 2 and 3 (the other joints 0); nullopt when
/// there is none. Cost: up to about 10⁵ joint-point evaluations (milliseconds).
std::optional<JointVector> findFoldedPose(const RobotDescription& robot,
                                          double minElbowAngle = kFoldedElbowAngle);

/// One inverse-kinematics solution.
struct IkSolution {
  JointVector joints{};   ///< rad, controller convention, each in (-π, π] before unwrapping
  int configuration = 0;  ///< bits: 1 = back (over the shoulder), 2 = elbow down, 4 = wrist flip
  bool withinLimits = false;   ///< all joints (possibly after ±2π) within RobotDescription
                               ///< limits and its interference limits
  bool wristSingular = false;  ///< |joint 5| ~ 0: only joint 4 + joint 6 determined
};

/// Result of inverse kinematics for one flange pose.
struct IkResult {
  std::vector<IkSolution> solutions;  ///< up to 8, ordered by configuration bits
  /// mm the wrist centre lies beyond the arm's reach (0 when reachable): outside the annulus the
  /// upper arm and forearm can reach, or inside the cylinder of radius |b| about joint 1.
  double reachShortfall = 0.0;
};

/// All closed-form solutions for a flange pose (robot base frame). `wristReference` (controller
/// joint 4, rad) fixes the split of joint 4 / joint 6 at a wrist singularity.
IkResult solveInverseKinematics(const RobotDescription& robot, const Pose& flangeInBase,
                                double wristReference = 0.0);

/// Moves each joint by multiples of 2π to the value nearest `reference` that lies within its
/// limits (or nearest the range if none does); when those violate one of the robot's
/// interference limits (RobotDescription::interference), the other turns of the coupled joints
/// within their ranges are tried and the satisfying one nearest `reference` taken. Returns false
/// if some joint is out of limits or no turn satisfies the interference limits.
bool unwrapJoints(const RobotDescription& robot, JointVector& joints, const JointVector& reference);

}  // namespace curvedslicer
