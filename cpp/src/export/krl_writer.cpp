// KUKA KRL writer (see krl_writer.hpp). Phase: "export".
#include "curvedslicer/export/krl_writer.hpp"

#include <string>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

void appendE6Pos(std::string& b, const Cell& cell, const MotionPoint& p, const Pose& tcp) {
  const XyzRpy c = toXyzRpy(tcp);
  b += "{X ";
  appendFixed(b, c.x, 3);
  b += ",Y ";
  appendFixed(b, c.y, 3);
  b += ",Z ";
  appendFixed(b, c.z, 3);
  b += ",A ";
  appendFixed(b, c.yaw, 4);
  b += ",B ";
  appendFixed(b, c.pitch, 4);
  b += ",C ";
  appendFixed(b, c.roll, 4);
}

void appendExternal(std::string& b, const Cell& cell, const MotionPoint& p) {
  b += ",E1 ";
  appendFixed(b, tiltDegrees(cell, p.a1), 4);
  b += ",E2 ";
  appendFixed(b, rotationDegrees(cell, p.a2), 4);
  b += '}';
}

}  // namespace

ExportResult KrlWriter::write(const MotionPlan& motion, const Cell& cell,
                              const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "KRL");
  checkJointLimits(motion, cell);
  const bool coordinated = cell.exportOptions.coordinated;
  const std::string name = makeProgramName(baseProgramName(cell, options), 24, false);
  const std::string out = "$OUT[" + std::to_string(options.arcOutput) + "]";
  ProgramText text(cell.exportOptions.lineEnding);
  text.line("&ACCESS RVP");
  text.line("&REL 1");
  text.line("DEF " + name + "()");
  text.line("; curvedslicer: " + std::to_string(motion.points.size()) + " points, " +
            std::to_string(motion.paths.size()) +
            " paths; E1 = positioner tilt, E2 = rotation (deg)");
  text.line(coordinated ? "; positions: TCP in the positioner table frame (BASE_DATA[1])"
                        : "; positions: TCP in the world frame");
  text.line("$TOOL=TOOL_DATA[" + std::to_string(cell.tool.number) + "]");
  if (coordinated) {
    text.line("$BASE=EK(MACHINE_DEF[2].ROOT,MACHINE_DEF[2].MECH_TYPE,BASE_DATA[1])");
    text.line("$ACT_EX_AX=2");
  } else {
    text.line("$BASE=$NULLFRAME");
  }
  ExportResult result;
  result.format = ExportFormat::Krl;
  double lastSpeed = -1.0;
  const std::size_t count = motion.points.size();
  for (std::size_t i = 0; i < count; ++i) {
    reportEvery(progress, i, count);
    const MotionPoint& p = motion.points[i];
    const Pose& tcp = coordinated ? p.toolInTable : p.toolInWorld;
    if (i == 0) {
      std::string& b = text.buffer();
      b += "PTP ";
      appendE6Pos(b, cell, p, tcp);
      int s = 0, t = 0;
      if (p.configuration & 1) s |= 1;
      if (p.configuration & 2) s |= 2;
      if (p.joints[4] < 0.0) s |= 4;
      for (int j = 0; j < 6; ++j) {
        if (p.joints[j] < 0.0) t |= 1 << j;
      }
      b += ",S " + std::to_string(s) + ",T " + std::to_string(t);
      appendExternal(b, cell, p);
      text.endLine();
    } else {
      if (p.speed != lastSpeed) {
        std::string& v = text.buffer();
        v += "$VEL.CP=";
        appendFixed(v, p.speed / 1000.0, 5);
        text.endLine();
        lastSpeed = p.speed;
      }
      const bool firstWeld = p.arcOn && i > 0 && motion.points[i - 1].pathStart;
      if (firstWeld) text.line("TRIGGER WHEN DISTANCE=0 DELAY=0 DO " + out + "=TRUE");
      if (p.pathEnd) text.line("TRIGGER WHEN DISTANCE=1 DELAY=0 DO " + out + "=FALSE");
      std::string& b = text.buffer();
      b += "LIN ";
      appendE6Pos(b, cell, p, tcp);
      appendExternal(b, cell, p);
      if (!p.pathEnd && !p.pathStart) b += " C_DIS";
      text.endLine();
    }
    ++result.motionCount;
    if (p.pathStart) ++result.arcCount;
    const double dwell = dwellAfter(motion, cell, i);
    if (dwell > 0.0) {
      std::string& w = text.buffer();
      w += "WAIT SEC ";
      appendFixed(w, dwell, 2);
      text.endLine();
    }
  }
  text.line("END");
  ExportFile file;
  file.name = name + ".src";
  file.lines = text.lineCount();
  file.text = text.take();
  result.files.push_back(std::move(file));
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
