// G-code writer for a tilt-rotate table (see gcode_writer.hpp). Phase: "export".
#include "curvedslicer/export/gcode_writer.hpp"

#include <algorithm>
#include <cmath>
#include <string>

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
  const double axes =
      std::max(std::abs(p.a1 - q.a1) / cell.positioner.tilt.limit.maxSpeed,
               std::abs(p.a2 - q.a2) / cell.positioner.rotation.limit.maxSpeed);
  return std::max(axes, 1e-3);
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

}  // namespace

ExportResult GcodeWriter::write(const MotionPlan& motion, const Cell& cell,
                                const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "G-code");
  checkJointLimits(motion, cell);
  const bool machine = options.gcodeMode == GcodeMode::Machine;
  const bool linuxcnc = options.gcodeDialect == GcodeDialect::LinuxCnc;
  const PositionerDescription& pos = cell.positioner;
  const std::string name = makeProgramName(baseProgramName(cell, options), 64, false);
  ProgramText text(cell.exportOptions.lineEnding);
  writeHeader(text, name, pos, options);
  text.line(machine ? "G21 G90 G93" : "G21 G90 G94");
  if (!machine) {
    text.line(linuxcnc ? "M429" : "G43.4 H" + std::to_string(cell.tool.number));
  }
  ExportResult result;
  result.format = ExportFormat::Gcode;
  const std::size_t count = motion.points.size();
  for (std::size_t i = 0; i < count; ++i) {
    reportEvery(progress, i, count);
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
      } else {
        appendSpeed(b, p.speed * 60.0, 1, speedReduced(p));
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
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
