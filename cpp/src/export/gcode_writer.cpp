// G-code writer for a tilt-rotate table (see gcode_writer.hpp). Phase: "export".
#include "curvedslicer/export/gcode_writer.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "curvedslicer/robot/positioner.hpp"
#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

std::string vectorText(const Vec3& v, int decimals) {
  std::string s;
  appendList(s, {v.x(), v.y(), v.z()}, decimals, " ");
  return s;
}

/// The header comments: name, mode, dialect, axes, pivot, table-to-part, units.
void writeHeader(ProgramText& text, const std::string& name, const PositionerDescription& pos,
                 const ExportOptions& options) {
  const bool machine = options.gcodeMode == GcodeMode::Machine;
  const bool linuxcnc = options.gcodeDialect == GcodeDialect::LinuxCnc;
  std::string title = "; curvedslicer G-code for a tilt-rotate table: ";
  title += name;
  text.line(title);
  text.line(machine ? "; mode: machine (X Y Z = point in the positioner base frame after A, C)"
                    : "; mode: tcp (X Y Z = point in the part frame; controller TCP kinematics)");
  std::string dialectLine = "; dialect: ";
  dialectLine += toString(options.gcodeDialect);
  text.line(dialectLine);
  std::string line = "; axes: A = tilt a1, sign ";
  line += std::to_string(pos.tilt.sign);
  line += "; C = rotation a2, sign ";
  line += std::to_string(pos.rotation.sign);
  line += "; degrees";
  text.line(line);
  line = "; pivot: tilt axis point ";
  line += vectorText(pos.tiltAxisPoint, 3);
  line += " mm, direction ";
  line += vectorText(pos.tiltAxisDirection, 6);
  text.line(line);
  line = "; pivot: rotation axis point ";
  line += vectorText(pos.rotationAxisPoint, 3);
  line += " mm, direction ";
  line += vectorText(pos.rotationAxisDirection, 6);
  line += " (at A = 0)";
  text.line(line);
  const Pose& tp = pos.tableToPart;
  line = "; table to part: translation ";
  line += vectorText(tp.translation(), 3);
  line += " mm, rotation rows";
  for (int r = 0; r < 3; ++r) {
    line += ' ';
    line += vectorText(tp.rotation().row(r).transpose(), 9);
  }
  text.line(line);
  std::string units = machine ? "; feed: G93 inverse time on G1 (F = 1/min, the move takes 1/F "
                                "min at the part-relative speed)"
                              : "; feed: G94 F in mm/min relative to the part";
  units += linuxcnc ? "; arc on M3, arc off M5; dwell G4 P seconds"
                    : "; arc on M3, arc off M5; dwell G4 P milliseconds";
  text.line(units);
}

/// Duration (s) of the linear move arriving at point i in machine mode (see the header).
double moveDuration(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  const MotionPoint& p = motion.points[i];
  const MotionPoint& q = motion.points[i - 1];
  const double length = (p.position - q.position).norm();
  if (length > 1e-9 && p.speed > 0.0) return length / p.speed;
  const double planned = p.time - q.time - pathEndDwell(motion, cell, i - 1);
  if (planned > 0.0) return planned;
  const double axes = std::max(std::abs(p.a1 - q.a1) / cell.positioner.tilt.limit.maxSpeed,
                               std::abs(p.a2 - q.a2) / cell.positioner.rotation.limit.maxSpeed);
  return std::max(axes, 1e-3);
}

/// True if the G1 arriving at point i in tcp mode moves no linear axis at the file's resolution
/// (the table turns under a fixed tool point): its F is then the rotary feed in deg/min.
bool turnsTheTableOnly(const MotionPlan& motion, std::size_t i) {
  return (motion.points[i].position - motion.points[i - 1].position).cwiseAbs().maxCoeff() < 5e-5;
}

/// deg/min of a rotary-only move in tcp mode: the combined A, C turn over the planned duration.
double rotaryFeed(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  const MotionPoint& p = motion.points[i];
  const MotionPoint& q = motion.points[i - 1];
  const double dA = tiltDegrees(cell, p.a1) - tiltDegrees(cell, q.a1);
  const double dC = rotationDegrees(cell, p.a2) - rotationDegrees(cell, q.a2);
  const double planned = p.time - q.time - pathEndDwell(motion, cell, i - 1);
  return 60.0 * std::hypot(dA, dC) / (planned > 0.0 ? planned : moveDuration(motion, cell, i));
}

/// The dwell line in the dialect's unit.
void appendDwell(std::string& b, double seconds, GcodeDialect dialect) {
  b += "G4 P";
  if (dialect == GcodeDialect::LinuxCnc) {
    appendFixed(b, seconds, 2);
  } else {
    appendFixed(b, std::round(seconds * 1000.0), 0);
  }
}

/// The lines of point i: the move, M3, M5, G4.
std::size_t pointLines(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  const MotionPoint& p = motion.points[i];
  return 1 + (p.pathStart ? 1 : 0) + (p.pathEnd ? 1 : 0) +
         (dwellAfter(motion, cell, i) > 0.0 ? 1 : 0);
}

/// Appends the lines of points `range`: moves, M3 / M5, dwells.
void writePoints(ProgramText& text, const MotionPlan& motion, const Cell& cell,
                 const ExportOptions& options, IndexRange range, const Progress& progress,
                 ExportResult& result) {
  const bool machine = options.gcodeMode == GcodeMode::Machine;
  const PositionerDescription& pos = cell.positioner;
  for (std::size_t i = range.begin; i < range.end; ++i) {
    reportEvery(progress, i, motion.points.size());
    const MotionPoint& p = motion.points[i];
    const Vec3 xyz =
        machine ? Vec3(computePartInPositionerBase(pos, p.a1, p.a2) * p.position) : p.position;
    std::string& b = text.buffer();
    const bool rapid = isJointMove(motion, i);  // first move and home: G0
    b += rapid ? "G0 X" : "G1 X";
    appendFixed(b, xyz.x(), 4);
    b += " Y";
    appendFixed(b, xyz.y(), 4);
    b += " Z";
    appendFixed(b, xyz.z(), 4);
    b += " A";
    appendFixed(b, tiltDegrees(cell, p.a1), 5);
    b += " C";
    appendFixed(b, rotationDegrees(cell, p.a2), 5);
    if (!rapid) {
      b += " F";
      if (machine) {
        appendFixed(b, 60.0 / moveDuration(motion, cell, i), 4);
      } else if (turnsTheTableOnly(motion, i)) {
        // at least the resolution: F must be positive, even for a move that turns nothing
        appendFixed(b, std::max(rotaryFeed(motion, cell, i), 1e-4), 4);
      } else {  // a speed below the resolution is written as the resolution (0.1 mm/min)
        appendSpeed(b, p.speed * 60.0, 1, speedReduced(p) || p.speed * 60.0 < 0.1);
      }
    }
    text.endLine();
    ++result.motionCount;
    if (p.pathStart) {
      text.line("M3");
      ++result.arcCount;
    }
    if (p.pathEnd) text.line("M5");
    const double dwell = dwellAfter(motion, cell, i);
    if (dwell > 0.0) {
      appendDwell(text.buffer(), dwell, options.gcodeDialect);
      text.endLine();
    }
  }
}

/// Names of the sub-programs: linuxcnc `<name>_<k>` in lower case (O-word subroutine files are
/// looked up by their lower-case name), generic `O<1000 + k>` (program numbers).
std::string subProgramName(const std::string& name, std::size_t k, bool linuxcnc) {
  if (!linuxcnc) return "O" + std::to_string(1000 + k);
  std::string lower = name + "_" + std::to_string(k);
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return lower;
}

/// The points of each file: all in the main file if they fit, else chunks of at most `limit`
/// lines cut before arc-off moves where possible.
std::vector<IndexRange> splitIntoFiles(const MotionPlan& motion, const Cell& cell,
                                       std::size_t limit) {
  const std::size_t count = motion.points.size();
  std::vector<std::size_t> costs(count);
  std::vector<bool> breaks(count);
  std::size_t total = 0;
  for (std::size_t i = 0; i < count; ++i) {
    costs[i] = pointLines(motion, cell, i);
    breaks[i] = !motion.points[i].arcOn;
    total += costs[i];
  }
  if (limit == 0 || total <= limit) return {{0, count}};
  return splitAtLimit(costs, breaks, limit);
}

}  // namespace

ExportResult GcodeWriter::write(const MotionPlan& motion, const Cell& cell,
                                const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "G-code");
  checkJointLimits(motion, cell);
  const bool machine = options.gcodeMode == GcodeMode::Machine;
  const bool linuxcnc = options.gcodeDialect == GcodeDialect::LinuxCnc;
  const std::string name = makeProgramName(baseProgramName(cell, options), 64, false);
  const LineEnding ending = cell.exportOptions.lineEnding;
  const int limit = options.gcodeMaxLinesPerFile;
  if (limit != 0 && limit < 10) {
    throw InvalidInput("G-code lines per file must be 0 (no split) or at least 10: " +
                       std::to_string(limit) + "; e.g. 40000");
  }
  // a sub-program file adds at most 3 lines (linuxcnc: sub, endsub, M2) to its points' lines
  const std::vector<IndexRange> chunks =
      splitIntoFiles(motion, cell, limit == 0 ? 0 : static_cast<std::size_t>(limit - 3));
  if (chunks.size() > 8999) {
    throw InvalidInput("the G-code needs more sub-programs than program numbers: " +
                       std::to_string(chunks.size()) +
                       " files; raise the lines per file (--gcode-lines-per-file)");
  }
  ExportResult result;
  result.format = ExportFormat::Gcode;
  ProgramText text(ending);
  writeHeader(text, name, cell.positioner, options);
  text.line(machine ? "G21 G90 G93" : "G21 G90 G94");
  if (!machine) {
    text.line(linuxcnc ? "M429" : "G43.4 H" + std::to_string(cell.tool.number));
  }
  std::vector<ExportFile> subFiles;
  if (chunks.size() == 1) {
    writePoints(text, motion, cell, options, chunks[0], progress, result);
  } else {
    for (std::size_t k = 0; k < chunks.size(); ++k) {
      const std::string sub = subProgramName(name, k + 1, linuxcnc);
      ProgramText part(ending);
      if (linuxcnc) {
        text.line("o<" + sub + "> call");
        part.line("o<" + sub + "> sub");
      } else {
        text.line("M98 P" + sub.substr(1));
        part.line(sub);
      }
      writePoints(part, motion, cell, options, chunks[k], progress, result);
      part.line(linuxcnc ? "o<" + sub + "> endsub" : "M99");
      if (linuxcnc) part.line("M2");
      ExportFile file;
      file.name = sub + ".ngc";
      file.lines = part.lineCount();
      file.text = part.take();
      subFiles.push_back(std::move(file));
    }
    result.warnings.push_back(
        "the G-code is split into " + std::to_string(chunks.size()) + " sub-programs of at most " +
        std::to_string(options.gcodeMaxLinesPerFile) + " lines, called from " + name);
  }
  if (machine) {
    text.line("G94");
  } else {
    text.line(linuxcnc ? "M428" : "G49");
  }
  text.line(linuxcnc ? "M2" : "M30");
  ExportFile file;
  file.name = name + ".ngc";
  file.lines = text.lineCount();
  file.text = text.take();
  result.files.push_back(std::move(file));
  for (ExportFile& f : subFiles) result.files.push_back(std::move(f));
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
