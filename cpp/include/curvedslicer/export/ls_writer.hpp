// Fanuc TP program in ASCII form (.LS) for a robot (group 1) with a two-axis positioner
// (group 2, joints J1 = tilt, J2 = rotation in controller degrees).
//
// Layout: /PROG <NAME>, /ATTR (DEFAULT_GROUP = 1,1,*,*,*;), /MN with numbered lines, /POS with
// one P[k] per motion: GP1 {UF, UT, CONFIG 'F|N U|D T|B, t1, t4, t6', X Y Z (mm), W P R (deg,
// R = Rz(R)·Ry(P)·Rx(W))} and GP2 {J1, J2 (deg)}, /END. Coordinated (the cell's default): linear
// moves carry COORD and GP1 positions are the TCP in the positioner's table frame (UF = the
// cell's user frame, which must be the table frame); otherwise UF 0 and world positions. CONFIG
// flip/up/top and the turn numbers of J1, J4, J6 (floor((q + 180°) / 360°)) come from the weld's
// configuration (MotionPathSpan::configuration, constant from the path start to its end) and at
// arc-off points from the point's joints. The first motion is `J P[1] 10% FINE`; a move to the
// cell's home pose `J P[k] p% FINE` with GP1 in joint representation (J1..J6 deg; p from the
// planned duration, writer_support.hpp); every other move (welds and the arc-off retract,
// travel and approach moves) `L P[k] v mm/sec CNT100` between weld points and FINE elsewhere
// (arc start/end, arc-off corners, which must not be rounded towards the part), speed in mm/sec
// or cm/min (whole numbers, a reduced weld speed rounded down; mm/min is written as cm/min). Arc:
// `Arc Start[n]` after a path's first point and `Arc End[m]` after its last (n, m = the cell's arc
// condition numbers); dwell `WAIT t(sec)`. Cost: O(points), about 250 bytes per point.
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
