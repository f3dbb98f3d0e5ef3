// Fanuc LS writer (see ls_writer.hpp). Phase: "export".
#include "curvedslicer/export/ls_writer.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

/// Turn number of a joint: 0 within ±180°, else ±1 per further turn.
int turnNumber(double angle) {
  const double deg = angle * kRadToDeg;
  return static_cast<int>(std::round(deg / 360.0));
}

std::string lineNumber(std::size_t n) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%4zu:  ", n);
  return buf;
}

}  // namespace

ExportResult LsWriter::write(const MotionPlan& motion, const Cell& cell,
                             const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "LS");
  checkJointLimits(motion, cell);
  const bool coordinated = cell.exportOptions.coordinated;
  const std::string name = makeProgramName(baseProgramName(cell, options), 36, true);
  const bool perSecond = cell.process.speedUnit == SpeedUnit::MillimetresPerSecond;
  const int userFrame = coordinated ? cell.exportOptions.userFrame : 0;
  const std::size_t count = motion.points.size();

  // ---- /MN ----------------------------------------------------------------------------------
  ProgramText mn(cell.exportOptions.lineEnding);
  std::size_t lineNo = 0;
  ExportResult result;
  result.format = ExportFormat::Ls;
  for (std::size_t i = 0; i < count; ++i) {
    const MotionPoint& p = motion.points[i];
    std::string& b = mn.buffer();
    b += lineNumber(++lineNo);
    if (i == 0) {
      b += "J P[1] 10% FINE ;";
    } else {
      const double speed = perSecond ? p.speed : p.speed * 6.0;
      b += "L P[" + std::to_string(i + 1) + "] ";
      appendFixed(b, std::max(1.0, std::round(speed)), 0);
      b += perSecond ? "mm/sec " : "cm/min ";
      b += p.pathEnd ? "FINE" : "CNT100";
      if (coordinated) b += " COORD";
      b += " ;";
    }
    mn.endLine();
    ++result.motionCount;
    if (p.pathStart) {
      mn.line(lineNumber(++lineNo) + "Arc Start[" + std::to_string(cell.process.arcStartCondition) +
              "] ;");
      ++result.arcCount;
    }
    if (p.pathEnd) {
      mn.line(lineNumber(++lineNo) + "Arc End[" + std::to_string(cell.process.arcEndCondition) +
              "] ;");
    }
    const double dwell = dwellAfter(motion, cell, i);
    if (dwell > 0.0) {
      std::string& w = mn.buffer();
      w += lineNumber(++lineNo) + "WAIT ";
      appendFixed(w, dwell, 2);
      w += "(sec) ;";
      mn.endLine();
    }
  }

  // ---- header, /POS -------------------------------------------------------------------------
  ProgramText text(cell.exportOptions.lineEnding);
  text.line("/PROG  " + name);
  text.line("/ATTR");
  text.line("OWNER\t\t= MNEDITOR;");
  text.line("COMMENT\t\t= \"curvedslicer\";");
  text.line("LINE_COUNT\t= " + std::to_string(lineNo) + ";");
  text.line("PROTECT\t\t= READ_WRITE;");
  text.line("DEFAULT_GROUP\t= 1,1,*,*,*;");
  text.line("/MN");
  std::string body = mn.take();
  text.buffer() += body;  // already line-terminated
  text.line("/POS");
  for (std::size_t i = 0; i < count; ++i) {
    reportEvery(progress, i, count);
    const MotionPoint& p = motion.points[i];
    const XyzRpy c = toXyzRpy(coordinated ? p.toolInTable : p.toolInWorld);
    text.line("P[" + std::to_string(i + 1) + "]{");
    text.line("   GP1:");
    std::string& g = text.buffer();
    g += "\tUF : " + std::to_string(userFrame) + ", UT : " + std::to_string(cell.tool.number) +
         ",\t\tCONFIG : '";
    g += (p.configuration & 4) ? 'F' : 'N';
    g += (p.configuration & 2) ? " D" : " U";
    g += (p.configuration & 1) ? " B" : " T";
    g += ", " + std::to_string(turnNumber(p.joints[0])) + ", " +
         std::to_string(turnNumber(p.joints[3])) + ", " + std::to_string(turnNumber(p.joints[5])) +
         "',";
    text.endLine();
    std::string& x = text.buffer();
    x += "\tX = ";
    appendFixed(x, c.x, 3);
    x += "  mm,\tY = ";
    appendFixed(x, c.y, 3);
    x += "  mm,\tZ = ";
    appendFixed(x, c.z, 3);
    x += "  mm,";
    text.endLine();
    std::string& w = text.buffer();
    w += "\tW = ";
    appendFixed(w, c.roll, 4);
    w += " deg,\tP = ";
    appendFixed(w, c.pitch, 4);
    w += " deg,\tR = ";
    appendFixed(w, c.yaw, 4);
    w += " deg";
    text.endLine();
    text.line("   GP2:");
    text.line("\tUF : " + std::to_string(userFrame) + ", UT : " + std::to_string(cell.tool.number) +
              ",");
    std::string& j = text.buffer();
    j += "\tJ1 = ";
    appendFixed(j, tiltDegrees(cell, p.a1), 4);
    j += " deg,\tJ2 = ";
    appendFixed(j, rotationDegrees(cell, p.a2), 4);
    j += " deg";
    text.endLine();
    text.line("};");
  }
  text.line("/END");
  ExportFile file;
  file.name = name + ".LS";
  file.lines = text.lineCount() + lineNo;
  file.text = text.take();
  result.files.push_back(std::move(file));
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
