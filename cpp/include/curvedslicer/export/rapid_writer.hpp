// ABB RAPID module (.mod) for a robot with a two-axis positioner (mechanical unit STN1) whose axes
// are the external axes eax_a (tilt) and eax_b (rotation) in controller degrees.
//
// Layout: MODULE <NAME> … PROC main() … ENDPROC ENDMODULE. Coordinated (the cell's default): a
// work object moving with the positioner, `TASK PERS wobjdata wobjTable := [FALSE, FALSE,
// "STN1", [[0,0,0],[1,0,0,0]], [[0,0,0],[1,0,0,0]]]` (the unit's frame must be calibrated to the
// table frame), `ActUnit STN1;`, positions = TCP in the table frame; otherwise wobj0 and world
// positions. Every motion has an inline robtarget [[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],
// [eax_a,eax_b,9E9,9E9,9E9,9E9]] (quaternion w,x,y,z; cf = quadrant of joints 1, 4, 6; cfx = the
// IK configuration bits) and inline speeddata [v_tcp,500,5000,1000]; the first motion is MoveJ,
// the rest MoveL with zone `fine` at path ends and starts, z1 elsewhere; the tool is the
// controller's `tool<number>` (the cell's tool number). Arc: `SetDO doArc<n>, 1;` after a path's
// first point, `SetDO doArc<n>, 0;` after its last (n = ExportOptions::arcOutput); dwell
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
