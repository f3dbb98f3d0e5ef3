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

/// ",S s,T t" of an E6POS: S bit 0 = back (over the shoulder), bit 1 = elbow down, bit 2 = joint
/// 5 negative; T bit k = joint k+1 negative; from the point's configuration (its weld's).
void appendStatusTurn(std::string& b, const RobotConfiguration& c) {
  int s = 0, t = 0;
  if (c.branch & 1) s |= 1;
  if (c.branch & 2) s |= 2;
  if (c.negative[4]) s |= 4;
  for (int j = 0; j < 6; ++j) {
    if (c.negative[j]) t |= 1 << j;
  }
  b += ",S ";
  appendInt(b, s);
  b += ",T ";
  appendInt(b, t);
}

/// An E6AXIS aggregate {A1 … A6, E1, E2} (deg, controller convention) of a joint move.
void appendE6Axis(std::string& b, const Cell& cell, const MotionPoint& p) {
  for (int j = 0; j < 6; ++j) {
    b += j == 0 ? "{A" : ",A";
    appendInt(b, j + 1);
    b += ' ';
    appendFixed(b, p.joints[j] * kRadToDeg, 4);
  }
  appendExternal(b, cell, p);
}

/// $VEL_AXIS / $VEL_EXTAX lines setting every axis to `percent` of its maximum (a planned PTP).
void writeAxisSpeeds(ProgramText& text, double percent) {
  for (int j = 1; j <= 8; ++j) {
    std::string& b = text.buffer();
    b += j <= 6 ? "$VEL_AXIS[" : "$VEL_EXTAX[";
    appendInt(b, j <= 6 ? j : j - 6);
    b += "]=";
    appendFixed(b, percent, 2);
    text.endLine();
  }
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
  const PointConfigurations configurations(motion);
  if (std::string mismatch = describeBranchMismatches(motion); !mismatch.empty()) {
    result.warnings.push_back(std::move(mismatch));
  }
  double lastSpeed = -1.0;
  const std::size_t count = motion.points.size();
  for (std::size_t i = 0; i < count; ++i) {
    reportEvery(progress, i, count);
    const MotionPoint& p = motion.points[i];
    const Pose& tcp = coordinated ? p.toolInTable : p.toolInWorld;
    if (p.kind == MoveKind::Home) {
      if (i > 0) writeAxisSpeeds(text, jointSpeedPercent(motion, cell, i));
      std::string& b = text.buffer();
      b += "PTP ";
      appendE6Axis(b, cell, p);
      text.endLine();
    } else if (i == 0) {
      std::string& b = text.buffer();
      b += "PTP ";
      appendE6Pos(b, cell, p, tcp);
      appendStatusTurn(b, configurations.at(i));
      appendExternal(b, cell, p);
      text.endLine();
    } else {
      if (p.speed != lastSpeed) {
        std::string& v = text.buffer();
        v += "$VEL.CP=";
        appendSpeed(v, p.speed / 1000.0, 5, speedReduced(p));
        text.endLine();
        lastSpeed = p.speed;
      }
      const bool firstWeld = p.arcOn && i > 0 && motion.points[i - 1].pathStart;
      if (firstWeld) text.line("TRIGGER WHEN DISTANCE=0 DELAY=0 DO " + out + "=TRUE");
      if (p.pathEnd) text.line("TRIGGER WHEN DISTANCE=1 DELAY=0 DO " + out + "=FALSE");
      std::string& b = text.buffer();
      b += "LIN ";
      appendE6Pos(b, cell, p, tcp);
      appendStatusTurn(b, configurations.at(i));
      appendExternal(b, cell, p);
      if (p.kind == MoveKind::Path && !p.pathEnd && !p.pathStart) b += " C_DIS";
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
