// G-code (RS-274) for a tilt-rotate table: A = tilt, C = rotation, in controller degrees (the
// cell's positioner signs applied).
//
// Two modes (ExportOptions::gcodeMode):
//   tcp      X Y Z are the point in the part frame; the controller's tool-centre-point control
//            turns them into machine motion, switched on at the start and off at the end with the
//            dialect's codes; F (G94, mm/min) is then the speed relative to the part; a move that
//            only turns the table (X Y Z change by less than 0.00005 mm) has F in deg/min, the
//            combined A, C turn over its duration (as below), as RS-274 reads F for rotary-only
//            moves;
//   machine  X Y Z are already transformed by the table's forward kinematics: the point in the
//            positioner base frame for the given A, C (computePartInPositionerBase), so a plain
//            trivial-kinematics controller reproduces the path. A constant F would make the speed
//            relative to the part vary with the table's turning, so linear moves use inverse-time
//            feed (G93): F = 60 / t per move, t (s) = the move's part-frame length / its speed
//            (weld speed relative to the part, reduced where the planner lowered it, or travel
//            speed); for a move without part-frame length (the table turns under a fixed tool
//            point) t is the planned duration (MotionPoint::time), else the slowest table axis's
//            time at its maximum speed.
// Dialects (ExportOptions::gcodeDialect):
//   generic   ISO / Fanuc-style 5-axis controller: dwell `G4 P<ms>` (P in milliseconds, whole),
//             TCP on `G43.4 H<tool>` (TCP control type 1), off `G49`, end `M30`;
//   linuxcnc  LinuxCNC with xyzac-trt switchable kinematics: dwell `G4 P<s>` (seconds), TCP on
//             `M429` and off `M428` (the user M-codes of LinuxCNC's switchkins configurations that
//             select the TCP and identity kinematics), end `M2`.
// The header records the mode, the dialect, the axis letters and signs, the pivot (tilt axis
// point and direction, rotation axis point and direction in the positioner base frame) and the
// table-to-part transform, so the file can be checked without the cell. Moves: first point and
// home G0, the rest (welds and the arc-off retract, travel and approach moves) G1; arc on `M3`
// after a path's first point, off `M5` after its last; the path (+ layer) dwell after the retract.
// Splitting: when the lines of the points exceed ExportOptions::gcodeMaxLinesPerFile, the points
// are packed into sub-programs, cut before an arc-off move where possible; the main file keeps
// the header, the start and end codes and one call per sub-program: linuxcnc `o<name_k> call`
// with the file name_k.ngc holding `o<name_k> sub` … `o<name_k> endsub` `M2` (lower case: O-word
// subroutine files are found by their lower-case name); generic `M98 P<n>` with the file O<n>.ngc
// holding `O<n>` … `M99` (n = 1001, 1002, …). Modal state (G93, TCP, M3) carries into the calls.
// Cost: O(points), about 70 bytes per point.
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
