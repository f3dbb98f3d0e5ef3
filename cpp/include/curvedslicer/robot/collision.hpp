// Collision check of a planned motion: the torch envelope against the material deposited up to
// each move and against the positioner table, for every weld move and every arc-off move (retract,
// travel, approach, home), with FCL (the Flexible Collision Library, Pan, Chitta, Manocha 2012).
//
// Model (docs/METHODS.md, "Travel and collisions"):
//   deposit   every welded segment of the paths before the move (and of the current path up to
//             the move) is a capsule of radius `depositBeadRadius` (half the bead width) around
//             the segment, in the part frame;
//   torch     the cell's cone (TorchEnvelope: from `stickout` above the TCP, the nozzle, with
//             `radius` there, to `stickout + length` with `topRadius`) covered by four capsules
//             along the torch axis, each with the cone's largest radius over its quarter (a
//             cylinder envelope, radius == topRadius, is one capsule); the lowest's axis starts
//             one radius above the nozzle, and below it the nozzle is a flat-ended cylinder of
//             the cone's radius there, from the nozzle face up (a round end would miss the
//             face's rim); the highest capsule's round end reaches the top;
//   table     a cylinder (disc) of the positioner table: top face at the table frame's origin,
//             normal along its z axis, tableRadius and tableThickness (PositionerGeometry);
//   fixture   the riser (a cylinder on the table top) and the substrate plate (a box on the
//             riser or the table) of FixtureGeometry, in the table frame.
// Weld moves are checked at their end point (the torch pose while the next segment is laid);
// arc-off moves at samples no further apart than half the envelope radius, linear in the part
// frame (joint-interpolated for moves from or to the home pose, through forward kinematics).
// Broad phase: the deposit in a uniform grid of chunked segments with exact segment distances
// (robot/deposit_index); narrow phase and contacts: FCL (capsule/capsule, capsule/cylinder,
// cylinder/capsule for the nozzle, whose distance to a bead is also computed exactly).
//
// Preconditions: the motion comes from planMotion (toolInPart, a1/a2, joints set). Cost: about a
// microsecond per weld point plus the samples of arc-off moves (tests/bench/README.md).
#pragma once

#include <string>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/plan/plan.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"

namespace curvedslicer {

/// The cell's torch envelope (tool/envelope, a cone from the nozzle up the torch), the
/// positioner's table disc (positioner/geometry) and the fixture on it (positioner/fixture), as
/// the collision check uses them.
struct CollisionGeometry {
  TorchEnvelope torch;       ///< cell.tool.envelope
  PositionerGeometry table;  ///< cell.positioner.geometry (table radius and thickness)
  FixtureGeometry fixture;   ///< cell.positioner.fixture (riser and substrate plate)
};

/// The collision geometry of a cell: its torch envelope, positioner geometry and fixture.
CollisionGeometry collisionGeometryOf(const Cell& cell);

/// Radius of the deposit capsules (mm): half the bead width (= bead spacing) of the plan, or
/// the layer thickness when the plan has no bead spacing, or 1 mm when it has neither.
double depositBeadRadius(const PlanParameters& parameters);

/// "layer 3 path 2 point 17 (weld move)" / "approach move to layer 3 path 2" — how messages name
/// the move arriving at motion.points[index].
std::string describeMove(const MotionPlan& motion, std::size_t index);

/// InvalidInput naming the sizes unless the torch envelope, the table and the bead radius are
/// positive and the envelope is longer than twice its widest radius.
void validateCollisionGeometry(const CollisionGeometry& geometry, double beadRadius);

/// Checks every move of `motion` (see the file comment). Colliding moves get kMotionCollision
/// and a CollisionReport; with options.allowCollisions they are also summarised in the
/// warnings, otherwise InvalidInput names the first few moves, what they hit and by how much.
/// @param beadRadius  mm, capsule radius of the deposit (depositBeadRadius of the plan)
/// Progress stage "collisions" (every 16,384 points); Cancelled when `progress` asks.
void checkMotionCollisions(MotionPlan& motion, const Cell& cell, const CollisionGeometry& geometry,
                           double beadRadius, const MotionOptions& options,
                           const Progress& progress = {});

}  // namespace curvedslicer
