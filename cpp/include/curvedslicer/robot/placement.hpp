// Part placement on the positioner table: the part frame in the table frame that the motion
// uses (`PositionerDescription::tableToPart` as given, or the part resting on the table), and
// the check that every weld point of the plan lies on or above the table top and inside the
// positioner's working volume (`PositionerGeometry`, cell.hpp).
//
// Bead bottom rule (PartPlacement::Rest): the points of layer i lie on the level surface
// d = i·h of the geodesic field (h = Plan::parameters.layerThickness, the bead height of a thin
// wall) and the layer's material fills (i-1)·h < d <= i·h; neighbouring beads are s apart
// (s = Plan::parameters.beadSpacing). So a weld point's bead is taken as the rectangle of h
// along -n (the layer normal) by s across the path (w = t × n, t the path tangent), centred
// across on the path: it reaches h·max(n_z, 0) + s/2·|w_z| below the point (table frame). Rest
// lifts the part along the table z until the lowest of these bead bottoms touches the table top
// (flat layers: the lowest weld point one h above the table; layers grown sideways: the outer
// bead's edge on the table); a part resting within 1e-6 mm keeps the cell's placement exactly.
// A start surface facing sideways (the first layer's mean V more than 45° from straight down in
// the table frame: the torch would lie across the table) is first turned by the smallest
// rotation that puts it on the table, and the part centred on the rotation axis.
// Details and the choice of the default in docs/METHODS.md ("Part placement").
// Cost: O(points) per call.
#pragma once

#include <string>
#include <string_view>

#include "curvedslicer/plan/plan.hpp"
#include "curvedslicer/robot/cell.hpp"

namespace curvedslicer {

/// How the part sits on the table.
enum class PartPlacement {
  Rest,  ///< the cell's table_to_part rotation and xy (a start surface facing sideways turned
         ///< onto the table first), moved along the table z so that the lowest bead bottom
         ///< lies on the table top (default)
  Cell,  ///< the cell's table_to_part as given (a measured fixture or substrate placement)
  Auto,  ///< Rest on the lowest riser that keeps the torch clear of the table (planMotion)
};

/// "rest" | "cell" | "auto" (the command line's and the Python module's names).
std::string_view toString(PartPlacement placement);
/// @throws InvalidInput naming the text and the choices.
PartPlacement parsePartPlacement(std::string_view name);

/// The placement of a plan.
struct PartPlacementResult {
  Pose tableToPart = Pose::Identity();  ///< part frame in the table frame, used for the motion
  double lift = 0.0;  ///< mm along the table z added to the cell's table_to_part (Rest)
  std::string note;   ///< what Rest did (for MotionPlan::notes); empty for Cell
};

/// The part placement `placement` gives for `plan` in `cell` (cell.positioner.tableToPart is
/// the starting point; Auto places as Rest on the cell's fixture, planMotion chooses the riser).
/// A plan without points keeps the cell's placement.
PartPlacementResult placePart(const Plan& plan, const Cell& cell, PartPlacement placement);

/// Diameter (mm) of a riser under the part at `tableToPart`: the cell's riser diameter if it
/// gives one, else the substrate plate's side, else the diameter about the rotation axis of the
/// first layer's weld points plus a bead width (the part's footprint), at most the table's.
double riserDiameterFor(const Plan& plan, const Cell& cell, const Pose& tableToPart);

/// Diameter (mm) about the rotation axis that a riser without a substrate plate must cover to
/// carry the part at `tableToPart`: the first layer's weld points within one layer thickness
/// of its lowest (the beads laid on the riser's top itself; a first layer on a raised start
/// surface, e.g. a mandrel, rests on that) plus a bead width; 0 for a plan without points.
double supportDiameterFor(const Plan& plan, const Pose& tableToPart);

/// `cell` with the part placement `tableToPart` (e.g. MotionPlan::tableToPart): the cell the
/// motion was planned in, for writers and readers that use the positioner's kinematics with
/// the part (the G-code header and machine coordinates).
Cell withPartPlacement(Cell cell, const Pose& tableToPart);

/// Checks the plan at `positioner.tableToPart` against the table and the working volume
/// (`positioner.geometry`). @throws InvalidInput naming the lowest point below the table top
/// (layer/path/point, part coordinates, how far below in mm, how many points), else the
/// farthest point outside the working volume's radius, else the highest above its height,
/// with the hint to set the part's placement.
void checkPartPlacement(const Plan& plan, const PositionerDescription& positioner);

}  // namespace curvedslicer
