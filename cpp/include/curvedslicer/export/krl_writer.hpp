// KUKA KRL program (.src) for a robot with a two-axis positioner as external axes E1 (tilt) and
// E2 (rotation), in controller degrees (sign applied).
//
// Layout: DEF <NAME>() … END. Coordinated (the cell's default): the base follows the positioner,
// `$BASE=EK(MACHINE_DEF[2].ROOT,MACHINE_DEF[2].MECH_TYPE,BASE_DATA[1])`, `$ACT_EX_AX=2`, and every
// position is the TCP in the positioner's table frame (BASE_DATA[1] must be the table frame);
// otherwise `$BASE=$NULLFRAME` and positions in the world frame. A move to the cell's home pose
// is a PTP to an E6AXIS {A1..A6, E1, E2} (deg; a later one preceded by $VEL_AXIS[1..6] and
// $VEL_EXTAX[1..2] = the percentage its planned duration needs, writer_support.hpp); any other
// first motion is a PTP to an E6POS; every further point (welds and the arc-off retract, travel
// and approach moves) is a LIN with an E6POS aggregate {X,Y,Z (mm), A,B,C (deg; A about z, B
// about y, C about x), S, T, E1, E2}, `$VEL.CP` (m/s; a reduced weld speed rounded down) set
// when the speed changes, C_DIS only between weld points. S and T (T bit k set when joint k+1
// < 0; S bit 0 = back, bit 1 = elbow down, bit 2 = joint 5 < 0) come from the weld's
// configuration (MotionPathSpan::configuration, constant from the path start to its end) and at
// arc-off points from the point's own joints; the controller uses them for PTP only and ignores
// them for LIN, where they document the configuration the plan keeps (and a re-taught point
// keeps it). Arc: `TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[n]=TRUE` before the first welded
// LIN of a path, `TRIGGER WHEN DISTANCE=1 DELAY=0 DO $OUT[n]=FALSE` before its last (n =
// ExportOptions::arcOutput), so the advance run never stops; dwell `WAIT SEC t`.
// Cost: O(points), about 110 bytes per point.
#pragma once

#include "curvedslicer/export/exporter.hpp"

namespace curvedslicer {

class KrlWriter final : public ProgramExporter {
 public:
  ExportFormat format() const override { return ExportFormat::Krl; }
  ExportResult write(const MotionPlan& motion, const Cell& cell, const ExportOptions& options,
                     const Progress& progress) const override;
};

}  // namespace curvedslicer
