// Fanuc TP programs in ASCII form (.LS, ArcTool) for a robot (group 1) with a two-axis positioner
// (group 2, joints J1 = tilt, J2 = rotation in controller degrees).
//
// Layout of one program: /PROG <NAME>; the full /ATTR block (OWNER, COMMENT, PROG_SIZE, CREATE
// and MODIFIED from ExportOptions::date, FILE_NAME, VERSION, LINE_COUNT, MEMORY_SIZE, PROTECT,
// TCD, DEFAULT_GROUP = 1,1,*,*,*, CONTROL_CODE); /APPL with the ArcTool section `ARC Welding
// Equipment : n,*,*,*,*;` (n = controller/ls weld_equipment); /MN with numbered lines; /POS with
// one position register P[k] per motion, numbered from 1 in each program: GP1 {UF, UT, CONFIG
// 'F|N U|D T|B, t1, t4, t6', X Y Z (mm), W P R (deg, R = Rz(R)·Ry(P)·Rx(W))} and GP2 {J1, J2
// (deg)}; /END. Coordinated (the cell's default): linear moves carry COORD and GP1 positions are
// the TCP in the positioner's table frame (UF = the cell's user frame, which must be the table
// frame); otherwise UF 0 and positions in Fanuc's world frame, the controller's robot frame
// `RobotDescription::controllerFrame` (on J1's axis at the height of J2). CONFIG flip/up/top and the turn numbers of J1, J4,
// J6 (floor((q + 180°) / 360°)) come from the weld's configuration (MotionPathSpan::configuration,
// constant from the path start to its end) and at arc-off points from the point's joints.
//
// Motion: the first motion `J P[k] 10% FINE`; a move to the cell's home pose `J P[k] p% FINE`
// with GP1 in joint representation (J1..J6 deg; p from the planned duration, writer_support.hpp);
// every other move (welds and the arc-off retract, travel and approach moves) `L P[k] v mm/sec
// CNT100` between weld points and FINE elsewhere (arc start/end, arc-off corners, which must not
// be rounded towards the part), speed in mm/sec or cm/min (whole numbers, a reduced weld speed
// rounded down; mm/min is written as cm/min) — the weld speed relative to the part, per move.
// Arc: `Arc Start[n]` after a path's first point and `Arc End[m]` after its last, n = the weld
// schedule of the first welded move (MotionPoint::weldSchedule when > 0, else controller/ls
// arc_start_schedule), m = controller/ls arc_end_schedule; within a weld a move whose schedule
// differs from the one in force is preceded by `Arc Start[n']` (ArcTool changes the schedule on
// the fly). Arc Start waits for the arc to strike (ArcTool's arc detection) before the next move.
// Dwell `WAIT t(sec)`.
//
// Splitting: when a program's /MN lines exceed controller/ls max_lines_per_program, the points are
// packed into programs <NAME><k> (k zero-padded), cut before an arc-off move where possible (a
// longer weld continues in the next program with the arc on, with a warning); the main program
// <NAME> holds one `CALL <NAME><k> ;` per program. Names: A–Z, 0–9, '_', at most 36 characters.
// Files: <NAME>.LS (main) and <NAME><k>.LS.
//
// Preconditions: the cell has controller/ls (else InvalidInput naming the field and the cell
// file). Cost: O(points), about 250 bytes per point.
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
