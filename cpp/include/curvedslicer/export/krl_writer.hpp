// KUKA KRL programs (.src with its .dat) for a robot with a two-axis positioner as external axes
// E1 (tilt) and E2 (rotation), in controller degrees (sign applied). Settings from the cell's
// "controller"/"krl" section (KrlController); a cell without it is refused (InvalidInput naming
// /controller/krl and the cell file).
//
// Files: NAME.src + NAME.dat. When the program needs more lines than the cell allows
// (controller/krl/max_lines_per_file, else export/max_lines_per_job), it is split before arc-off
// points into NAME1.src/.dat … NAMEk.src/.dat, each DEF NAMEk() moving through its points, and
// NAME.src (with an empty NAME.dat) initialises and calls them in order (`NAME1()` …). Every
// position is declared once in the .dat of the program using it (`DECL E6POS XP<k>={…}`,
// numbered from 1 per program) and used by name in the .src (`LIN XP<k>`).
//
// Initialisation (the single or the main program): the stop-message interrupt, BAS(#INITMOV,0),
// $TOOL=TOOL_DATA[tool number]; coordinated (the cell's default): the base follows the
// positioner, `$BASE=EK(MACHINE_DEF[2].ROOT,MACHINE_DEF[2].MECH_TYPE,BASE_DATA[n])` (n =
// base_number, which must be the table frame), `$ACT_EX_AX=2`, every position the TCP in the
// table frame; otherwise `$BASE=$NULLFRAME` and positions in the world frame; `$APO.CDIS` = the
// cell's approximation distance (mm).
//
// Motions: a move to the cell's home pose is a PTP to an E6AXIS {A1..A6, E1..E6} (deg; a later
// one preceded by $VEL_AXIS[1..6] and $VEL_EXTAX[1..2] = the percentage its planned duration
// needs, writer_support.hpp); any other first motion is a PTP to an E6POS; every further point
// (welds and the arc-off retract, travel and approach moves) is a LIN to an E6POS {X,Y,Z (mm),
// A,B,C (deg; A about z, B about y, C about x: KUKA's tool frame, x along the torch, the cell's
// TCP frame turned -90 deg about its y as KUKA's flange is), S, T, E1..E6}, `$VEL.CP` (m/s; a
// reduced weld speed rounded down) set when the speed changes, C_DIS only between weld points. S
// and T (T bit k set when joint k+1 < 0; S bit 0 = back (overhead area), bit 1 = elbow up (A3 at
// or above the stretched-arm angle, KUKA's definition), bit 2 = joint 5 < 0)
// come from the weld's configuration (MotionPathSpan::configuration, constant from the path start
// to its end) and at arc-off points from the point's own joints.
//
// Arc (output arc_on_output = n): with an arc-established input m, after the (exact-stop) move
// onto the path start `$OUT[n]=TRUE` and `WAIT FOR $IN[m]`; without one, `TRIGGER WHEN
// DISTANCE=0 DELAY=0 DO $OUT[n]=TRUE` before the first welded LIN, so the advance run never
// stops. Off: `TRIGGER WHEN DISTANCE=1 DELAY=0 DO $OUT[n]=FALSE` before the path's last LIN.
// Wire feed (wire_feed_analog_output = k): `$ANOUT[k]` = wire feed / full scale, set at the path
// start and by a TRIGGER wherever the wire feed of a weld move changes (MotionPoint::wireFeed,
// the cell's process wire feed where it is 0). Dwell `WAIT SEC t`.
// Cost: O(points), about 130 bytes per point.
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
