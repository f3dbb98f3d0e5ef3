// G-code (RS-274, LinuxCNC dialect) for a tilt-rotate table: A = tilt, C = rotation, in
// controller degrees (the cell's positioner signs applied).
//
// Two modes (ExportOptions::gcodeMode):
//   tcp      X Y Z are the point in the part frame; the controller's tool-centre-point
//            kinematics (e.g. LinuxCNC xyzac-trt with TCP on) turns them into machine motion;
//   machine  X Y Z are already transformed by the table's forward kinematics: the point in the
//            positioner base frame for the given A, C (computePartInPositionerBase), so a plain
//            trivial-kinematics controller reproduces the path.
// The header records the mode, the axis letters and signs, the pivot (tilt axis point and
// direction, rotation axis point and direction in the positioner base frame) and the table-to-part
// transform, so the file can be checked without the cell. Moves: first point and home G0, the
// rest (welds and the arc-off retract, travel and approach moves) G1 with F = speed in mm/min
// (weld speed relative to the part — a reduced one rounded down —, travel speed off the arc); arc
// on `M3` after a path's first point, off `M5` after its last; dwell `G4 P<s>`; `M2` at the end.
// Cost: O(points), about 60 bytes per point.
#pragma once

#include "curvedslicer/export/exporter.hpp"

namespace curvedslicer {

class GcodeWriter final : public ProgramExporter {
 public:
  ExportFormat format() const override { return ExportFormat::Gcode; }
  ExportResult write(const MotionPlan& motion, const Cell& cell, const ExportOptions& options,
                     const Progress& progress) const override;
};

}  // namespace curvedslicer
