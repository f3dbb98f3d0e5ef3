// Yaskawa Motoman INFORM job files (.JBI) for a robot (RB1) with a two-axis station (ST1).
//
// Layout of one job (CRLF or LF from the cell's export options; names upper case, at most the
// cell's maxNameLength characters, 8 on NX100, 32 on DX100 and later):
//   /JOB  //NAME n  //POS  ///NPOS C,0,EC,0,0,0  ///TOOL t
//   robot positions C00000… : ///POSTYPE PULSE + ///PULSE (robot pulses from the cell's pulses
//     per degree) or ///POSTYPE BASE + ///RECTAN + ///RCONF (x, y, z in mm and Rx, Ry, Rz in deg
//     of the TCP in the controller's robot frame `RobotDescription::controllerFrame`, for
//     Yaskawa on the S axis at the height of the L axis; R = Rz·Ry·Rx; RCONF = flip, elbow down, back, R/T/S
//     at or beyond 180°, repeated whenever it changes: within a weld the weld's configuration
//     (MotionPathSpan::configuration, constant from ARCON to ARCOF), at arc-off points the one
//     of the point's joints); station positions EC00000… always ///POSTYPE PULSE (tilt,
//     rotation pulses = sign · round(deg · ppd));
//   //INST  ///DATE  ///ATTR SC,RW[,RJ]  ///GROUP1 RB1  ///GROUP2 ST1  NOP … END
// Instructions per point: the program's first point `MOVJ C VJ=10.00 +MOVJ EC VJ=10.00` (10 % joint
// speed for the unplanned move from wherever the robot stands); a move to the cell's home pose
// `MOVJ C VJ=p +MOVJ EC VJ=p` (p from the planned duration, writer_support.hpp); every further
// point, welds and the arc-off retract / travel / approach moves alike, `SMOVL C V=v +MOVJ EC`
// when the cell asks for coordinated motion (speed v relative to the part), else `MOVL C V=v
// +MOVJ EC`; v is the point's speed (weld, reduced weld — rounded down — or travel) in the cell's
// speed unit. After the first point of a path `ARCON ASF#(n)` (condition file) or `ARCON AC=…
// AV=… T=…` (direct) — ARCON waits for the welder's arc-confirm signal — and, when the cell
// names one (controller/jbi arc_wait_input n > 0), `WAIT IN#(n)=ON`; after its last point
// `ARCOF AEF#(n)` or `ARCOF`; `TIMER T=…` for the path (+ layer) dwell, if any, after the
// retract that follows the path end (torch off the part).
//
// Splitting: when the instructions (NOP … END inclusive) exceed the cell's maxLinesPerJob, the
// points are packed into sub-jobs <NAME><k> (k zero-padded), cut before an arc-off move (path
// start, retract, travel, approach, home) where possible (a path longer than a job continues in
// the next job with the arc on); each sub-job declares and
// references only its own positions (numbered from 0); the main job <NAME> is `NOP`, one
// `CALL JOB:<NAME><k>` per sub-job, `END`. Files: <NAME>.JBI (main) and <NAME><k>.JBI.
//
// Preconditions: motion plan for this cell; position type Pulse or Base (User is refused: the
// user frame is not part of the cell). Cost: O(points), about 120 bytes per point.
#pragma once

#include "curvedslicer/export/exporter.hpp"

namespace curvedslicer {

class JbiWriter final : public ProgramExporter {
 public:
  ExportFormat format() const override { return ExportFormat::Jbi; }
  ExportResult write(const MotionPlan& motion, const Cell& cell, const ExportOptions& options,
                     const Progress& progress) const override;
};

}  // namespace curvedslicer
