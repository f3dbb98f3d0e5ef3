// KUKA KRL program (.src) for a robot with a two-axis positioner as external axes E1 (tilt) and
// E2 (rotation), in controller degrees (sign applied).
//
// Layout: DEF <NAME>() … END. Coordinated (the cell's default): the base follows the positioner,
// `$BASE=EK(MACHINE_DEF[2].ROOT,MACHINE_DEF[2].MECH_TYPE,BASE_DATA[1])`, `$ACT_EX_AX=2`, and every
// position is the TCP in the positioner's table frame (BASE_DATA[1] must be the table frame);
// otherwise `$BASE=$NULLFRAME` and positions in the world frame. The first motion is a PTP with S
// and T (T bit k set when joint k+1 < 0; S bit 0 = back, bit 1 = elbow down, bit 2 = joint 5 < 0,
// from the IK configuration); every further point is a LIN with an E6POS aggregate
// {X,Y,Z (mm), A,B,C (deg; A about z, B about y, C about x), E1, E2}, `$VEL.CP` (m/s) set when the
// speed changes. Arc: `TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[n]=TRUE` before the first welded
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
