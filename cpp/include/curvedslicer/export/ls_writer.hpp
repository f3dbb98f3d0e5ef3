// Fanuc TP program in ASCII form (.LS) for a robot (group 1) with a two-axis positioner
// (group 2, joints J1 = tilt, J2 = rotation in controller degrees).
//
// Layout: /PROG <NAME>, /ATTR (DEFAULT_GROUP = 1,1,*,*,*;), /MN with numbered lines, /POS with
// one P[k] per motion: GP1 {UF, UT, CONFIG 'F|N U|D T|B, t1, t4, t6', X Y Z (mm), W P R (deg,
// R = Rz(R)·Ry(P)·Rx(W))} and GP2 {J1, J2 (deg)}, /END. Coordinated (the cell's default): linear
// moves carry COORD and GP1 positions are the TCP in the positioner's table frame (UF = the
// cell's user frame, which must be the table frame); otherwise UF 0 and world positions. The
// first motion is `J P[1] 10% FINE`, then `L P[k] v mm/sec CNT100` (FINE at path ends), speed in
// mm/sec or cm/min (whole numbers; mm/min is written as cm/min). Arc: `Arc Start[n]` after a
// path's first point and `Arc End[m]` after its last (n, m = the cell's arc condition numbers);
// dwell `WAIT t(sec)`. Cost: O(points), about 250 bytes per point.
#pragma once

#include "curvedslicer/export/exporter.hpp"

namespace curvedslicer {

class LsWriter final : public ProgramExporter {
 public:
  ExportFormat format() const override { return ExportFormat::Ls; }
  ExportResult write(const MotionPlan& motion, const Cell& cell, const ExportOptions& options,
                     const Progress& progress) const override;
};

}  // namespace curvedslicer
