// Arc-off moves that clear the part: between two welds the torch retracts from the path end
// back up its own axis, travels at the clearance above everything deposited so far and
// approaches the next path start down its axis there; the program starts and ends at the home
// pose.
//
// Method (docs/METHODS.md, "Travel and collisions"): the deposit so far is the capsules of the
// welded segments (robot/collision.hpp). The retract and approach heights along the torch axes
// (the torch's own direction in the part frame: the layer normal can point anywhere on a small
// layer patch such as a blade tip's island, the torch's axis is where the torch came from) are
// the lowest (from clearance + bead radius up, in steps of clearance / 2) whose TCP keeps the
// clearance from the deposit and whose torch clears it and the table. The travel between them
// is the straight segment, or, where that comes closer than the clearance to the deposit or the
// torch would collide on the way, a route lifted by the smallest multiple of clearance / 2 along
// the mean of the two torch axes (via points above both ends). Positioner angles of arc-off points
// are linear in the route's arc length between the path end and the next path start; robot joints
// come from inverse kinematics, continuous with the previous point (the approach: with the next
// path start). A route whose via points the robot cannot reach is skipped for the next lift; when
// no lift up to TravelSetup::maxLift clears and is reachable, the straight route stays and a
// warning names the move (the collision check then reports what the torch hits). A retract or
// approach point the robot cannot reach is an InvalidInput naming it (UnreachablePolicy::Warn: a
// warning, joints held).
//
// Preconditions: `motion` holds the path points with positioner angles, TCP poses and joints
// (planMotion's kinematics pass); MotionPlan::paths covers them. Cost: per arc-off move a few
// hundred deposit queries (deposit_index) and a few IK solutions.
#pragma once

#include "curvedslicer/plan/plan.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/collision.hpp"
#include "curvedslicer/robot/motion.hpp"

namespace curvedslicer {

/// What the travel planner needs from the cell (travelSetupOf), and how far it may lift.
struct TravelSetup {
  HomePose home;               ///< cell.home
  CollisionGeometry geometry;  ///< collisionGeometryOf(cell)
  double maxLift = 300.0;      ///< mm, highest lift of a route (and retract/approach) above the
                               ///< clearance height before giving up (the collision check reports)
};

/// The cell's home pose and collision geometry, the default maximum lift.
TravelSetup travelSetupOf(const Cell& cell);

/// Inserts retract, travel, approach and home points into `motion` (see the file comment) and
/// updates MotionPlan::paths to the path points' new positions.
/// @param beadRadius  mm, deposit capsule radius (depositBeadRadius of the plan)
/// @throws InvalidInput for a non-positive clearance, or an arc-off point the robot cannot reach
///         (UnreachablePolicy::Throw), naming the move.
/// Progress stage "travel" (per path); Cancelled when `progress` asks.
void insertTravelMoves(MotionPlan& motion, const Cell& cell, const TravelSetup& setup,
                       double beadRadius, const MotionOptions& options,
                       const Progress& progress = {});

/// planMotion's arc-off phase: insertTravelMoves, then checkMotionCollisions (collision.hpp),
/// both with the plan's deposit bead radius (depositBeadRadius).
/// Progress: "travel" (first half), "collisions" (second half).
void planArcOffMoves(const Plan& plan, const Cell& cell, const TravelSetup& setup,
                     const MotionOptions& options, MotionPlan& motion,
                     const Progress& progress = {});

}  // namespace curvedslicer
