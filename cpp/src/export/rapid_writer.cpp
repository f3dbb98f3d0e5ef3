// ABB RAPID writer (see rapid_writer.hpp). Phase: "export".
#include "curvedslicer/export/rapid_writer.hpp"

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

/// Quadrant of a joint angle as ABB counts it: floor(angle / 90°).
int quadrant(double angle) {
  return static_cast<int>(std::floor(angle * kRadToDeg / 90.0));
}

void appendRobtarget(std::string& b, const Cell& cell, const MotionPoint& p, const Pose& tcp) {
  const Vec3 t = tcp.translation();
  Eigen::Quaterniond q(tcp.rotation());
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one sign for the same rotation
  b += "[[";
  appendList(b, {t.x(), t.y(), t.z()}, 3);
  b += "],[";
  appendList(b, {q.w(), q.x(), q.y(), q.z()}, 8);
  b += "],[";
  b += std::to_string(quadrant(p.joints[0])) + "," + std::to_string(quadrant(p.joints[3])) + "," +
       std::to_string(quadrant(p.joints[5])) + "," + std::to_string(p.configuration);
  b += "],[";
  appendFixed(b, tiltDegrees(cell, p.a1), 4);
  b += ',';
  appendFixed(b, rotationDegrees(cell, p.a2), 4);
  b += ",9E9,9E9,9E9,9E9]]";
}

}  // namespace

ExportResult RapidWriter::write(const MotionPlan& motion, const Cell& cell,
                                const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "RAPID");
  checkJointLimits(motion, cell);
  const bool coordinated = cell.exportOptions.coordinated;
  const std::string name = makeProgramName(baseProgramName(cell, options), 32, false);
  const std::string signal = "doArc" + std::to_string(options.arcOutput);
  const std::string tool = "tool" + std::to_string(cell.tool.number);
  const std::string wobj = coordinated ? "wobjTable" : "wobj0";
  ProgramText text(cell.exportOptions.lineEnding);
  text.line("MODULE " + name);
  text.line("  ! curvedslicer: " + std::to_string(motion.points.size()) + " points, " +
            std::to_string(motion.paths.size()) +
            " paths; eax_a = positioner tilt, eax_b = rotation (deg)");
  if (coordinated) {
    text.line("  ! positions: TCP in the positioner table frame (mechanical unit STN1)");
    text.line(
        "  TASK PERS wobjdata wobjTable := [FALSE, FALSE, \"STN1\", [[0,0,0],[1,0,0,0]], "
        "[[0,0,0],[1,0,0,0]]];");
  } else {
    text.line("  ! positions: TCP in the world frame");
  }
  text.line("  PROC main()");
  if (coordinated) text.line("    ActUnit STN1;");
  ExportResult result;
  result.format = ExportFormat::Rapid;
  const std::size_t count = motion.points.size();
  for (std::size_t i = 0; i < count; ++i) {
    reportEvery(progress, i, count);
    const MotionPoint& p = motion.points[i];
    const Pose& tcp = coordinated ? p.toolInTable : p.toolInWorld;
    std::string& b = text.buffer();
    b += i == 0 ? "    MoveJ " : "    MoveL ";
    appendRobtarget(b, cell, p, tcp);
    b += ", [";
    appendFixed(b, p.speed, 2);
    b += ",500,5000,1000], ";
    b += (p.pathStart || p.pathEnd || i == 0) ? "fine" : "z1";
    b += ", " + tool + " \\WObj:=" + wobj + ";";
    text.endLine();
    ++result.motionCount;
    if (p.pathStart) {
      text.line("    SetDO " + signal + ", 1;");
      ++result.arcCount;
    }
    if (p.pathEnd) text.line("    SetDO " + signal + ", 0;");
    const double dwell = dwellAfter(motion, cell, i);
    if (dwell > 0.0) {
      std::string& w = text.buffer();
      w += "    WaitTime ";
      appendFixed(w, dwell, 2);
      w += ';';
      text.endLine();
    }
  }
  if (coordinated) text.line("    DeactUnit STN1;");
  text.line("  ENDPROC");
  text.line("ENDMODULE");
  ExportFile file;
  file.name = name + ".mod";
  file.lines = text.lineCount();
  file.text = text.take();
  result.files.push_back(std::move(file));
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
