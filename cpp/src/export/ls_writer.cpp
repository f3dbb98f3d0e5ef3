// Fanuc LS writer (see ls_writer.hpp). Phases: "export" (split into programs, then the /MN lines
// and /POS registers of each program).
#include "curvedslicer/export/ls_writer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

/// Fanuc program names: at most 36 characters (R-30iA and later).
constexpr std::size_t kLsNameLength = 36;

const LsControllerSettings& requireLsSettings(const Cell& cell) {
  if (!cell.controller.ls) {
    throw InvalidInput(cell.controller.source +
                       ": /controller/ls is missing; add the Fanuc ArcTool settings "
                       "(weld_equipment, arc_start_schedule, arc_end_schedule, "
                       "max_lines_per_program) to the cell, see resources/schema/cell.schema.json");
  }
  return *cell.controller.ls;
}

/// The weld schedule of the move arriving at point i: the point's own (MotionPoint::weldSchedule)
/// when set, else the cell's Arc Start schedule.
int scheduleOf(const MotionPoint& p, const LsControllerSettings& ls) {
  return p.weldSchedule > 0 ? p.weldSchedule : ls.arcStartSchedule;
}

/// True if the welded move arriving at point i needs an `Arc Start[n]` before it: its schedule
/// differs from the one of the welded move before it (not the first move after the arc start).
bool scheduleChangesAt(const MotionPlan& motion, const LsControllerSettings& ls, std::size_t i) {
  if (i < 2 || !motion.points[i].arcOn || !motion.points[i - 1].arcOn) return false;
  return scheduleOf(motion.points[i], ls) != scheduleOf(motion.points[i - 1], ls);
}

/// The schedule `Arc Start` after the path start at i sets: the next (first welded) move's.
int startScheduleAfter(const MotionPlan& motion, const LsControllerSettings& ls, std::size_t i) {
  if (i + 1 < motion.points.size() && motion.points[i + 1].arcOn) {
    return scheduleOf(motion.points[i + 1], ls);
  }
  return ls.arcStartSchedule;
}

/// /MN lines of point i: a schedule change, the motion, Arc Start, Arc End, WAIT.
std::size_t mnLines(const MotionPlan& motion, const Cell& cell, const LsControllerSettings& ls,
                    std::size_t i) {
  const MotionPoint& p = motion.points[i];
  std::size_t lines = 1;
  if (scheduleChangesAt(motion, ls, i)) ++lines;
  if (p.pathStart) ++lines;
  if (p.pathEnd) ++lines;
  if (dwellAfter(motion, cell, i) > 0.0) ++lines;
  return lines;
}

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
  // Not coordinated: user frame 0 is Fanuc's world frame, the controller's robot frame (on J1's
  // axis at the height of J2), not the cell's world frame.
  const XyzRpy c = toXyzRpy(coordinated ? p.toolInTable
                                        : cell.robot.controllerFrame.inverse() * p.toolInRobotBase);
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

/// "DATE YY-MM-DD  TIME HH:MM:00" from ExportOptions::date ("YYYY/MM/DD HH:MM", validated).
std::string lsDate(const std::string& date) {
  return "DATE " + date.substr(2, 2) + "-" + date.substr(5, 2) + "-" + date.substr(8, 2) +
         "  TIME " + date.substr(11, 5) + ":00";
}

/// /PROG, /ATTR and (for a program that moves) /APPL, up to and including /MN.
void writeHeader(ProgramText& text, const std::string& name, std::size_t lineCount,
                 const ExportOptions& options, const LsControllerSettings& ls, bool moves) {
  const std::string date = lsDate(options.date);
  text.line("/PROG  " + name);
  text.line("/ATTR");
  text.line("OWNER\t\t= MNEDITOR;");
  text.line("COMMENT\t\t= \"curvedslicer\";");
  text.line("PROG_SIZE\t= 0;");
  text.line("CREATE\t\t= " + date + ";");
  text.line("MODIFIED\t= " + date + ";");
  text.line("FILE_NAME\t= ;");
  text.line("VERSION\t\t= 0;");
  text.line("LINE_COUNT\t= " + std::to_string(lineCount) + ";");
  text.line("MEMORY_SIZE\t= 0;");
  text.line("PROTECT\t\t= READ_WRITE;");
  text.line("TCD:  STACK_SIZE\t= 0,");
  text.line("      TASK_PRIORITY\t= 50,");
  text.line("      TIME_SLICE\t= 0,");
  text.line("      BUSY_LAMP_OFF\t= 0,");
  text.line("      ABORT_REQUEST\t= 0,");
  text.line("      PAUSE_REQUEST\t= 0;");
  text.line(moves ? "DEFAULT_GROUP\t= 1,1,*,*,*;" : "DEFAULT_GROUP\t= *,*,*,*,*;");
  text.line("CONTROL_CODE\t= 00000000 00000000;");
  if (moves) {
    text.line("/APPL");
    text.line("  ARC Welding Equipment : " + std::to_string(ls.weldEquipment) + ",*,*,*,*;");
  }
  text.line("/MN");
}

/// Everything one program needs besides its points.
struct LsContext {
  const MotionPlan& motion;
  const Cell& cell;
  const ExportOptions& options;
  const LsControllerSettings& ls;
  const PointConfigurations& configurations;
  const Progress& progress;
};

/// The /MN line of the move arriving at point i, its register P[k].
void appendMotionLine(std::string& b, const LsContext& c, std::size_t i, std::size_t k) {
  const MotionPoint& p = c.motion.points[i];
  if (isJointMove(c.motion, i)) {
    b += "J P[";
    appendInt(b, static_cast<std::int64_t>(k));
    b += "] ";
    appendFixed(b, std::round(jointSpeedPercent(c.motion, c.cell, i)), 0);
    b += "% FINE ;";
    return;
  }
  const bool perSecond = c.cell.process.speedUnit == SpeedUnit::MillimetresPerSecond;
  b += "L P[" + std::to_string(k) + "] ";
  appendFixed(b, wholeSpeed(perSecond ? p.speed : p.speed * 6.0, speedReduced(p)), 0);
  b += perSecond ? "mm/sec " : "cm/min ";
  // CNT only between weld points; exact stops at arc start/end and on arc-off moves, whose
  // corners (retract, travel, approach) must not be rounded towards the part.
  const bool weldInterior = p.kind == MoveKind::Path && !p.pathStart && !p.pathEnd;
  b += weldInterior ? "CNT100" : "FINE";
  if (c.cell.exportOptions.coordinated) b += " COORD";
  b += " ;";
}

/// One program holding the points `range` (absolute indices into motion.points).
ExportFile writeProgram(const LsContext& c, const std::string& name, IndexRange range,
                        std::size_t& motionCount, std::size_t& arcCount) {
  const LineEnding ending = c.cell.exportOptions.lineEnding;
  ProgramText mn(ending);
  std::size_t lineNo = 0;
  for (std::size_t i = range.begin; i < range.end; ++i) {
    const MotionPoint& p = c.motion.points[i];
    if (scheduleChangesAt(c.motion, c.ls, i)) {
      mn.line(lineNumber(++lineNo) + "Arc Start[" + std::to_string(scheduleOf(p, c.ls)) + "] ;");
    }
    std::string& b = mn.buffer();
    b += lineNumber(++lineNo);
    appendMotionLine(b, c, i, i - range.begin + 1);
    mn.endLine();
    ++motionCount;
    if (p.pathStart) {
      mn.line(lineNumber(++lineNo) + "Arc Start[" +
              std::to_string(startScheduleAfter(c.motion, c.ls, i)) + "] ;");
      ++arcCount;
    }
    if (p.pathEnd) {
      mn.line(lineNumber(++lineNo) + "Arc End[" + std::to_string(c.ls.arcEndSchedule) + "] ;");
    }
    const double dwell = dwellAfter(c.motion, c.cell, i);
    if (dwell > 0.0) {
      std::string& w = mn.buffer();
      w += lineNumber(++lineNo) + "WAIT ";
      appendFixed(w, dwell, 2);
      w += "(sec) ;";
      mn.endLine();
    }
  }
  ProgramText text(ending);
  writeHeader(text, name, lineNo, c.options, c.ls, true);
  text.buffer() += mn.take();  // already line-terminated
  text.line("/POS");
  const bool coordinated = c.cell.exportOptions.coordinated;
  const int userFrame = coordinated ? c.cell.exportOptions.userFrame : 0;
  const std::string frames =
      "\tUF : " + std::to_string(userFrame) + ", UT : " + std::to_string(c.cell.tool.number) + ",";
  for (std::size_t i = range.begin; i < range.end; ++i) {
    reportEvery(c.progress, i, c.motion.points.size());
    const MotionPoint& p = c.motion.points[i];
    text.line("P[" + std::to_string(i - range.begin + 1) + "]{");
    writeRobotPosition(text, c.cell, p, c.configurations.at(i), coordinated, userFrame);
    text.line("   GP2:");
    text.line(frames);
    std::string& j = text.buffer();
    j += "\tJ1 = ";
    appendFixed(j, tiltDegrees(c.cell, p.a1), 4);
    j += " deg,\tJ2 = ";
    appendFixed(j, rotationDegrees(c.cell, p.a2), 4);
    j += " deg";
    text.endLine();
    text.line("};");
  }
  text.line("/END");
  ExportFile file;
  file.name = name + ".LS";
  file.lines = text.lineCount() + lineNo;
  file.text = text.take();
  return file;
}

/// The main program: one CALL per program.
ExportFile writeMainProgram(const std::string& name, const std::vector<std::string>& programs,
                            const Cell& cell, const ExportOptions& options,
                            const LsControllerSettings& ls) {
  ProgramText text(cell.exportOptions.lineEnding);
  writeHeader(text, name, programs.size(), options, ls, false);
  for (std::size_t k = 0; k < programs.size(); ++k) {
    text.line(lineNumber(k + 1) + "CALL " + programs[k] + " ;");
  }
  text.line("/POS");
  text.line("/END");
  ExportFile file;
  file.name = name + ".LS";
  file.lines = text.lineCount();
  file.text = text.take();
  return file;
}

/// The points of each program: all in one if they fit, else chunks cut before arc-off moves.
std::vector<IndexRange> splitIntoPrograms(const MotionPlan& motion, const Cell& cell,
                                          const LsControllerSettings& ls) {
  const std::size_t count = motion.points.size();
  std::vector<std::size_t> costs(count);
  std::vector<bool> breaks(count);
  std::size_t total = 0;
  for (std::size_t i = 0; i < count; ++i) {
    costs[i] = mnLines(motion, cell, ls, i);
    breaks[i] = !motion.points[i].arcOn;
    total += costs[i];
  }
  const std::size_t limit = static_cast<std::size_t>(ls.maxLinesPerProgram);
  if (total <= limit) return {{0, count}};
  return splitAtLimit(costs, breaks, limit);
}

}  // namespace

ExportResult LsWriter::write(const MotionPlan& motion, const Cell& cell,
                             const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "LS");
  const LsControllerSettings& ls = requireLsSettings(cell);
  checkJointLimits(motion, cell);
  const std::string mainName = makeProgramName(baseProgramName(cell, options), kLsNameLength, true);
  ExportResult result;
  result.format = ExportFormat::Ls;
  const PointConfigurations configurations(motion);
  if (std::string mismatch = describeBranchMismatches(motion); !mismatch.empty()) {
    result.warnings.push_back(std::move(mismatch));
  }
  const std::vector<IndexRange> chunks = splitIntoPrograms(motion, cell, ls);
  if (chunks.size() > static_cast<std::size_t>(ls.maxLinesPerProgram)) {
    throw InvalidInput("the program needs more programs than the main program can call: " +
                       std::to_string(chunks.size()) + " programs, at most " +
                       std::to_string(ls.maxLinesPerProgram) +
                       " lines; raise controller/ls max_lines_per_program");
  }
  std::vector<std::string> names;
  for (std::size_t k = 0; k < chunks.size() && chunks.size() > 1; ++k) {
    names.push_back(makeSubJobName(mainName, k + 1, chunks.size(), kLsNameLength));
    if (names.back() == mainName) {
      throw InvalidInput("a program would have the main program's name: " + mainName +
                         "; choose a program name that does not end in digits");
    }
  }
  if (chunks.size() > 1) {
    result.files.push_back(writeMainProgram(mainName, names, cell, options, ls));
    result.warnings.push_back("the program is split into " + std::to_string(chunks.size()) +
                              " programs of at most " + std::to_string(ls.maxLinesPerProgram) +
                              " lines, called from " + mainName);
  } else {
    names.push_back(mainName);
  }
  const LsContext context{motion, cell, options, ls, configurations, progress};
  for (std::size_t k = 0; k < chunks.size(); ++k) {
    result.files.push_back(
        writeProgram(context, names[k], chunks[k], result.motionCount, result.arcCount));
    const std::size_t end = chunks[k].end;
    if (end < motion.points.size() && motion.points[end].arcOn) {
      const MotionPoint& last = motion.points[end - 1];
      result.warnings.push_back("path " + std::to_string(last.path) + " of layer " +
                                std::to_string(last.layer) +
                                " is longer than a program and continues in the next program");
    }
  }
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
