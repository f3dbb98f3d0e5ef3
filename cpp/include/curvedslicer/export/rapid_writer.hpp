// ABB RAPID modules (.mod) for a robot with a two-axis positioner (the cell's mechanical unit)
// whose axes are the external axes eax_a (tilt) and eax_b (rotation) in controller degrees.
// Settings from the cell's "controller"/"rapid" section (RapidController); a cell without it (or,
// coordinated, without mech_unit) is refused (InvalidInput naming the field and the cell file).
//
// Files: NAME.mod, MODULE NAME: the declarations — `PERS tooldata tWaam<n>` (robhold TRUE, the
// cell's TCP in the flange frame, load = tool_mass_kg at tool_cog_mm) and `TASK PERS wobjdata`
// — and PROC main(). When the program needs more lines than the cell allows
// (controller/rapid/max_lines_per_module, else export/max_lines_per_job), it is split before
// arc-off points into modules NAME1.mod … NAMEk.mod (MODULE NAMEk with PROC pNAMEk()), and main()
// calls `pNAME1;` … in order; else main() holds the motions.
//
// Coordinated (the cell's default): `wobjTable := [FALSE, FALSE, "<mech_unit>", [[0,0,0],
// [1,0,0,0]], [[0,0,0],[1,0,0,0]]]` moves with the positioner (the unit's frame must be
// calibrated to the table frame), `ActUnit <mech_unit>;` … `DeactUnit`, positions = TCP in the
// table frame; otherwise a fixed wobjWorld and world positions. A move to the cell's home pose is
// `MoveAbsJ` to an inline jointtarget [[j1..j6],[eax_a,eax_b,9E9,9E9,9E9,9E9]] (deg). Every other
// motion has an inline robtarget [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax_a,eax_b,9E9,…]]
// (quaternion w,x,y,z; cf = quadrant of joints 1, 4, 6, floor(q / 90°); cfx = the IK branch
// bits) — within a weld the weld's configuration (MotionPathSpan::configuration), at arc-off
// points the one of the point's joints — and inline speeddata [v_tcp,500,5000,1000] (a reduced
// weld speed rounded down); any other first motion is MoveJ, the rest MoveL with zone z1 between
// weld points and `fine` elsewhere. `ConfJ \On;` and `ConfL \Off;` (linear moves follow the
// nearest configuration, as a continuous weld must; the cf values stay the planned ones).
//
// Arc (plain signals, no ArcWare): after the move onto a path start `SetAO <wire_feed_signal>,
// wfs;` (m/min, if named), `SetDO <arc_signal>, 1;` and, if named, `WaitDI
// <arc_established_signal>, 1;`; `SetAO` again before a weld move whose wire feed changes
// (MotionPoint::wireFeed, the cell's process wire feed where it is 0); `SetDO <arc_signal>, 0;`
// after the path end; dwell `WaitTime t;`. Cost: O(points), about 150 bytes per point.
#pragma once

#include "curvedslicer/export/exporter.hpp"

namespace curvedslicer {

class RapidWriter final : public ProgramExporter {
 public:
  ExportFormat format() const override { return ExportFormat::Rapid; }
  ExportResult write(const MotionPlan& motion, const Cell& cell, const ExportOptions& options,
                     const Progress& progress) const override;
};

}  // namespace curvedslicer
