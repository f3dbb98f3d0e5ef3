// Fanuc LS writer (see ls_writer.hpp). Phase: "export".
#include "curvedslicer/export/ls_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

/// CONFIG : 'F|N U|D T|B, t1, t4, t6' from the point's configuration (its weld's within a weld).
void appendConfig(std::string& b, const RobotConfiguration& c) {
  b += "CONFIG : '";
  b += (c.branch & 4) ? 'F' : 'N';
  b += (c.branch & 2) ? " D" : " U";
  b += (c.branch & 1) ? " B" : " T";
  for (int j : {0, 3, 5}) {
    b += ", ";
    appendInt(b, c.turn[j]);
  }
  b += "',";
}

/// Linear speed in whole mm/sec or cm/min (at least 1); a reduced weld speed rounded down.
double wholeSpeed(double speed, bool reduced) {
  return std::max(1.0, reduced ? std::floor(speed + 1e-9) : std::round(speed));
}

/// The GP1 data of P[k]: Cartesian (UF, UT, CONFIG, X Y Z W P R) or, for a joint move to the home
/// pose, joint representation (J1 … J6 in deg).
void writeRobotPosition(ProgramText& text, const Cell& cell, const MotionPoint& p,
                        const RobotConfiguration& configuration, bool coordinated, int userFrame) {
  text.line("   GP1:");
  std::string& g = text.buffer();
  g += "\tUF : " + std::to_string(userFrame) + ", UT : " + std::to_string(cell.tool.number) + ",";
  if (p.kind == MoveKind::Home) {
    text.endLine();
    for (int row = 0; row < 2; ++row) {
      std::string& j = text.buffer();
      for (int k = 3 * row; k < 3 * row + 3; ++k) {
        j += k % 3 == 0 ? "\tJ" : " deg,\tJ";
        appendInt(j, k + 1);
        j += " = ";
        appendFixed(j, p.joints[k] * kRadToDeg, 4);
      }
      j += row == 0 ? " deg," : " deg";
      text.endLine();
    }
    return;
  }
  const XyzRpy c = toXyzRpy(coordinated ? p.toolInTable : p.toolInWorld);
  g += "\t\t";
  appendConfig(g, configuration);
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
  const PointConfigurations configurations(motion);
  if (std::string mismatch = describeBranchMismatches(motion); !mismatch.empty()) {
    result.warnings.push_back(std::move(mismatch));
  }
  for (std::size_t i = 0; i < count; ++i) {
    const MotionPoint& p = motion.points[i];
    std::string& b = mn.buffer();
    b += lineNumber(++lineNo);
    if (isJointMove(motion, i)) {
      b += "J P[";
      appendInt(b, static_cast<std::int64_t>(i + 1));
      b += "] ";
      appendFixed(b, std::round(jointSpeedPercent(motion, cell, i)), 0);
      b += "% FINE ;";
    } else {
      b += "L P[" + std::to_string(i + 1) + "] ";
      appendFixed(b, wholeSpeed(perSecond ? p.speed : p.speed * 6.0, speedReduced(p)), 0);
      b += perSecond ? "mm/sec " : "cm/min ";
      // CNT only between weld points; exact stops at arc start/end and on arc-off moves, whose
      // corners (retract, travel, approach) must not be rounded towards the part.
      const bool weldInterior = p.kind == MoveKind::Path && !p.pathStart && !p.pathEnd;
      b += weldInterior ? "CNT100" : "FINE";
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
    text.line("P[" + std::to_string(i + 1) + "]{");
    writeRobotPosition(text, cell, p, configurations.at(i), coordinated, userFrame);
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
