// G-code writer for a tilt-rotate table (see gcode_writer.hpp). Phase: "export".
#include "curvedslicer/export/gcode_writer.hpp"

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

}  // namespace

ExportResult GcodeWriter::write(const MotionPlan& motion, const Cell& cell,
                                const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "G-code");
  checkJointLimits(motion, cell);
  const bool machine = options.gcodeMode == GcodeMode::Machine;
  const PositionerDescription& pos = cell.positioner;
  const std::string name = makeProgramName(baseProgramName(cell, options), 64, false);
  ProgramText text(cell.exportOptions.lineEnding);
  text.buffer() += "; curvedslicer G-code for a tilt-rotate table: ";
  text.buffer() += name;
  text.endLine();
  text.line(machine ? "; mode: machine (X Y Z = point in the positioner base frame after A, C)"
                    : "; mode: tcp (X Y Z = point in the part frame; controller TCP kinematics)");
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
  text.line("; feed F in mm/min (G94); arc on M3, arc off M5; dwell G4 P seconds");
  text.line("G21 G90 G94");
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
      appendSpeed(b, p.speed * 60.0, 1, speedReduced(p));
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
      std::string& w = text.buffer();
      w += "G4 P";
      appendFixed(w, dwell, 2);
      text.endLine();
    }
  }
  text.line("M2");
  ExportFile file;
  file.name = name + ".ngc";
  file.lines = text.lineCount();
  file.text = text.take();
  result.files.push_back(std::move(file));
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
