// ABB RAPID writer (see rapid_writer.hpp). Phase: "export".
#include "curvedslicer/export/rapid_writer.hpp"

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

/// eax_a (tilt), eax_b (rotation) in controller degrees, the unused four as 9E9.
void appendExternal(std::string& b, const Cell& cell, const MotionPoint& p) {
  appendFixed(b, tiltDegrees(cell, p.a1), 4);
  b += ',';
  appendFixed(b, rotationDegrees(cell, p.a2), 4);
  b += ",9E9,9E9,9E9,9E9";
}

/// An inline robtarget [[x,y,z],[q1..q4],[cf1,cf4,cf6,cfx],[eax_a,eax_b,9E9,9E9,9E9,9E9]]; the
/// confdata from the point's configuration (its weld's within a weld): the quadrants of joints
/// 1, 4 and 6 and the IK branch bits.
void appendRobtarget(std::string& b, const Cell& cell, const MotionPoint& p, const Pose& tcp,
                     const RobotConfiguration& c) {
  const Vec3 t = tcp.translation();
  Eigen::Quaterniond q(tcp.rotation());
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one sign for the same rotation
  b += "[[";
  appendList(b, {t.x(), t.y(), t.z()}, 3);
  b += "],[";
  appendList(b, {q.w(), q.x(), q.y(), q.z()}, 8);
  b += "],[";
  b += std::to_string(c.quadrant[0]) + "," + std::to_string(c.quadrant[3]) + "," +
       std::to_string(c.quadrant[5]) + "," + std::to_string(c.branch);
  b += "],[";
  appendExternal(b, cell, p);
  b += "]]";
}

/// An inline jointtarget [[j1..j6],[eax_a,eax_b,9E9,9E9,9E9,9E9]] (deg, controller convention).
void appendJointtarget(std::string& b, const Cell& cell, const MotionPoint& p) {
  b += "[[";
  for (int j = 0; j < 6; ++j) {
    if (j > 0) b += ',';
    appendFixed(b, p.joints[j] * kRadToDeg, 4);
  }
  b += "],[";
  appendExternal(b, cell, p);
  b += "]]";
}

/// Inline speeddata [v_tcp,500,5000,1000]: TCP speed (mm/s; a reduced weld speed rounded down),
/// orientation (deg/s), linear and rotating external axes.
void appendSpeeddata(std::string& b, const MotionPoint& p) {
  b += '[';
  appendSpeed(b, p.speed, 2, speedReduced(p));
  b += ",500,5000,1000]";
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
  // Configuration monitoring (see rapid_writer.hpp): joint moves go to the stated configuration,
  // linear moves follow the nearest one.
  text.line("    ConfJ \\On;");
  text.line("    ConfL \\Off;");
  if (coordinated) text.line("    ActUnit STN1;");
  ExportResult result;
  result.format = ExportFormat::Rapid;
  const PointConfigurations configurations(motion);
  if (std::string mismatch = describeBranchMismatches(motion); !mismatch.empty()) {
    result.warnings.push_back(std::move(mismatch));
  }
  const std::size_t count = motion.points.size();
  for (std::size_t i = 0; i < count; ++i) {
    reportEvery(progress, i, count);
    const MotionPoint& p = motion.points[i];
    const Pose& tcp = coordinated ? p.toolInTable : p.toolInWorld;
    std::string& b = text.buffer();
    if (p.kind == MoveKind::Home) {
      b += "    MoveAbsJ ";
      appendJointtarget(b, cell, p);
      b += ", ";
      appendSpeeddata(b, p);
      b += ", fine, " + tool + ";";
    } else {
      b += i == 0 ? "    MoveJ " : "    MoveL ";
      appendRobtarget(b, cell, p, tcp, configurations.at(i));
      b += ", ";
      appendSpeeddata(b, p);
      b += ", ";
      const bool weldInterior = p.kind == MoveKind::Path && !p.pathStart && !p.pathEnd;
      b += (weldInterior && i > 0) ? "z1" : "fine";
      b += ", " + tool + " \\WObj:=" + wobj + ";";
    }
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
