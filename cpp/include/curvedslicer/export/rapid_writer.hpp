// ABB RAPID module (.mod) for a robot with a two-axis positioner (mechanical unit STN1) whose axes
// are the external axes eax_a (tilt) and eax_b (rotation) in controller degrees.
//
// Layout: MODULE <NAME> … PROC main() … ENDPROC ENDMODULE. Coordinated (the cell's default): a
// work object moving with the positioner, `TASK PERS wobjdata wobjTable := [FALSE, FALSE,
// "STN1", [[0,0,0],[1,0,0,0]], [[0,0,0],[1,0,0,0]]]` (the unit's frame must be calibrated to the
// table frame), `ActUnit STN1;`, positions = TCP in the table frame; otherwise wobj0 and world
// positions. A move to the cell's home pose is `MoveAbsJ` to an inline jointtarget [[j1..j6],
// [eax_a,eax_b,9E9,9E9,9E9,9E9]] (deg). Every other motion has an inline robtarget
// [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax_a,eax_b,9E9,9E9,9E9,9E9]] (quaternion w,x,y,z;
// cf = quadrant of joints 1, 4, 6, floor(q / 90°); cfx = the IK branch bits) — within a weld the
// weld's configuration (MotionPathSpan::configuration, constant from the path start to its end),
// at arc-off points the one of the point's joints — and inline speeddata [v_tcp,500,5000,1000]
// (a reduced weld speed rounded down); any other first motion is MoveJ, the rest MoveL (welds and
// the arc-off retract, travel and approach moves) with zone z1 between weld points and `fine`
// elsewhere (arc start/end, arc-off corners); the tool is the controller's `tool<number>`.
// Configuration monitoring: `ConfJ \On;` (joint moves reach the stated configuration, so the
// program starts in the planned one) and `ConfL \Off;` (linear moves follow the nearest
// configuration, as a continuous weld must; with ConfL \On, the IRC5 default, the controller
// checks the robtarget's configuration on linear moves and stops the program on a mismatch,
// which a joint lying on a quadrant boundary — J4 at 0° under a vertical torch — can trigger
// from rounding alone). The cf values are still the planned ones and constant within a weld, so
// a user who prefers ConfL \On meets no flip inside a weld. Arc: `SetDO doArc<n>, 1;` after a
// path's first point, `SetDO doArc<n>, 0;` after its last (n = ExportOptions::arcOutput); dwell
// `WaitTime t;`. Cost: O(points), about 150 bytes per point.
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
