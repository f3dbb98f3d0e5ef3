// ABB RAPID writer (see rapid_writer.hpp). Phase: "export" (split into modules, then each).
#include "curvedslicer/export/rapid_writer.hpp"

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

/// Lines of the single or main module besides its motions: MODULE, two comments, tooldata,
/// wobjdata, PROC main(), ConfJ, ConfL, ActUnit, DeactUnit, ENDPROC, ENDMODULE.
constexpr std::size_t kRapidHeaderLines = 12;

/// The cell's RAPID settings. @throws InvalidInput naming /controller/rapid and the cell's source.
const RapidController& requireRapid(const Cell& cell) {
  const auto& rapid = cell.controller.rapid;
  if (!rapid) {
    throw InvalidInput(cell.controller.source +
                       ": /controller/rapid is missing: (absent); add the RAPID settings "
                       "(arc_signal, tool_mass_kg, …, see resources/schema/cell.schema.json) to "
                       "the cell");
  }
  if (cell.exportOptions.coordinated && rapid->mechUnit.empty()) {
    throw InvalidInput(cell.controller.source +
                       ": /controller/rapid/mech_unit is missing: (absent); name the positioner's "
                       "mechanical unit (e.g. \"STN1\") for a coordinated export");
  }
  return *rapid;
}

/// A quaternion [q1,q2,q3,q4] (w first, w ≥ 0) of a rotation.
void appendQuaternion(std::string& b, const Mat3& rotation) {
  Eigen::Quaterniond q(rotation);
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one sign for the same rotation
  b += '[';
  appendList(b, {q.w(), q.x(), q.y(), q.z()}, 8);
  b += ']';
}

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
  b += "[[";
  appendList(b, {t.x(), t.y(), t.z()}, 3);
  b += "],";
  appendQuaternion(b, tcp.rotation());
  b += ",[";
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

/// Upper bound of the lines point i needs: the motion, SetAO before a weld move, SetAO + SetDO +
/// WaitDI after a path start, SetDO after a path end, WaitTime.
std::size_t pointLines(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  const MotionPoint& p = motion.points[i];
  std::size_t lines = 1;
  if (p.arcOn) ++lines;
  if (p.pathStart) lines += 3;
  if (p.pathEnd) ++lines;
  if (dwellAfter(motion, cell, i) > 0.0) ++lines;
  return lines;
}

/// Names the moves of every module use.
struct RapidNames {
  std::string tool, wobj;
};

/// Writes the motions of one module's procedure.
class RapidPartWriter {
 public:
  RapidPartWriter(const MotionPlan& motion, const Cell& cell, const RapidController& rapid,
                  const RapidNames& names, const PointConfigurations& configurations,
                  ProgramText& text)
      : motion_(motion),
        cell_(cell),
        rapid_(rapid),
        names_(names),
        configurations_(configurations),
        text_(text) {}

  void writePoint(std::size_t i, ExportResult& result);

 private:
  void writeWireFeed(std::size_t i);
  void writeMotion(std::size_t i);

  const MotionPlan& motion_;
  const Cell& cell_;
  const RapidController& rapid_;
  const RapidNames& names_;
  const PointConfigurations& configurations_;
  ProgramText& text_;
  double lastWireFeed_ = -1.0;
};

void RapidPartWriter::writeWireFeed(std::size_t i) {
  if (rapid_.wireFeedSignal.empty()) return;
  const double wfs = wireFeedOf(cell_, motion_.points[i]);
  if (wfs == lastWireFeed_) return;
  lastWireFeed_ = wfs;
  std::string& b = text_.buffer();
  b += "    SetAO " + rapid_.wireFeedSignal + ", ";
  appendFixed(b, wfs, 3);
  b += ';';
  text_.endLine();
}

void RapidPartWriter::writeMotion(std::size_t i) {
  const MotionPoint& p = motion_.points[i];
  const Pose& tcp = cell_.exportOptions.coordinated ? p.toolInTable : p.toolInWorld;
  std::string& b = text_.buffer();
  if (p.kind == MoveKind::Home) {
    b += "    MoveAbsJ ";
    appendJointtarget(b, cell_, p);
    b += ", ";
    appendSpeeddata(b, p);
    b += ", fine, " + names_.tool + ";";
  } else {
    b += i == 0 ? "    MoveJ " : "    MoveL ";
    appendRobtarget(b, cell_, p, tcp, configurations_.at(i));
    b += ", ";
    appendSpeeddata(b, p);
    b += ", ";
    const bool weldInterior = p.kind == MoveKind::Path && !p.pathStart && !p.pathEnd;
    b += (weldInterior && i > 0) ? "z1" : "fine";
    b += ", " + names_.tool + " \\WObj:=" + names_.wobj + ";";
  }
  text_.endLine();
}

void RapidPartWriter::writePoint(std::size_t i, ExportResult& result) {
  const MotionPoint& p = motion_.points[i];
  if (p.arcOn) writeWireFeed(i);
  writeMotion(i);
  ++result.motionCount;
  if (p.pathStart) {
    ++result.arcCount;
    lastWireFeed_ = -1.0;  // every weld sets its wire feed
    if (i + 1 < motion_.points.size()) writeWireFeed(i + 1);
    text_.line("    SetDO " + rapid_.arcSignal + ", 1;");
    if (!rapid_.arcEstablishedSignal.empty()) {
      text_.line("    WaitDI " + rapid_.arcEstablishedSignal + ", 1;");
    }
  }
  if (p.pathEnd) text_.line("    SetDO " + rapid_.arcSignal + ", 0;");
  const double dwell = dwellAfter(motion_, cell_, i);
  if (dwell > 0.0) {
    std::string& w = text_.buffer();
    w += "    WaitTime ";
    appendFixed(w, dwell, 2);
    w += ';';
    text_.endLine();
  }
}

/// The declarations of the single or main module: comments, tooldata, wobjdata.
void writeDeclarations(ProgramText& text, const MotionPlan& motion, const Cell& cell,
                       const RapidController& rapid, const RapidNames& names) {
  const bool coordinated = cell.exportOptions.coordinated;
  text.line("  ! curvedslicer: " + std::to_string(motion.points.size()) + " points, " +
            std::to_string(motion.paths.size()) +
            " paths; eax_a = positioner tilt, eax_b = rotation (deg)");
  text.line(coordinated ? "  ! positions: TCP in the positioner table frame (mechanical unit " +
                              rapid.mechUnit + ")"
                        : "  ! positions: TCP in the world frame");
  std::string& b = text.buffer();
  b += "  PERS tooldata " + names.tool + " := [TRUE,[[";
  const Vec3 t = cell.tool.tcp.translation();
  appendList(b, {t.x(), t.y(), t.z()}, 3);
  b += "],";
  appendQuaternion(b, cell.tool.tcp.rotation());
  b += "],[";
  appendFixed(b, rapid.toolMass, 3);
  b += ",[";
  appendList(b, {rapid.toolCog.x(), rapid.toolCog.y(), rapid.toolCog.z()}, 3);
  b += "],[1,0,0,0],0,0,0]];";
  text.endLine();
  if (coordinated) {
    text.line("  TASK PERS wobjdata " + names.wobj + " := [FALSE, FALSE, \"" + rapid.mechUnit +
              "\", [[0,0,0],[1,0,0,0]], [[0,0,0],[1,0,0,0]]];");
  } else {
    text.line("  TASK PERS wobjdata " + names.wobj +
              " := [FALSE, TRUE, \"\", [[0,0,0],[1,0,0,0]], [[0,0,0],[1,0,0,0]]];");
  }
}

/// PROC main() up to its first motion: configuration monitoring and the positioner unit.
void beginMain(ProgramText& text, const Cell& cell, const RapidController& rapid) {
  text.line("  PROC main()");
  // Joint moves go to the stated configuration, linear moves follow the nearest one.
  text.line("    ConfJ \\On;");
  text.line("    ConfL \\Off;");
  if (cell.exportOptions.coordinated) text.line("    ActUnit " + rapid.mechUnit + ";");
}

void endMain(ProgramText& text, const Cell& cell, const RapidController& rapid) {
  if (cell.exportOptions.coordinated) text.line("    DeactUnit " + rapid.mechUnit + ";");
  text.line("  ENDPROC");
}

ExportFile finishModule(const std::string& name, ProgramText& text) {
  text.line("ENDMODULE");
  ExportFile file;
  file.name = name + ".mod";
  file.lines = text.lineCount();
  file.text = text.take();
  return file;
}

}  // namespace

ExportResult RapidWriter::write(const MotionPlan& motion, const Cell& cell,
                                const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "RAPID");
  const RapidController& rapid = requireRapid(cell);
  checkJointLimits(motion, cell);
  const LineEnding ending = cell.exportOptions.lineEnding;
  // 31 characters, so the procedure "p<module>" of a split module fits RAPID's 32.
  const std::string name = makeProgramName(baseProgramName(cell, options), 31, false);
  const RapidNames names{"tWaam" + std::to_string(cell.tool.number),
                         cell.exportOptions.coordinated ? "wobjTable" : "wobjWorld"};
  const std::size_t count = motion.points.size();
  std::vector<std::size_t> costs(count);
  for (std::size_t i = 0; i < count; ++i) costs[i] = pointLines(motion, cell, i);
  const std::size_t limit = static_cast<std::size_t>(
      rapid.maxLinesPerModule > 0 ? rapid.maxLinesPerModule : cell.exportOptions.maxLinesPerJob);
  const std::vector<ProgramPart> parts =
      splitIntoParts(motion, costs, name, limit, kRapidHeaderLines, 31, "RAPID");

  ExportResult result;
  result.format = ExportFormat::Rapid;
  const PointConfigurations configurations(motion);
  if (std::string mismatch = describeBranchMismatches(motion); !mismatch.empty()) {
    result.warnings.push_back(std::move(mismatch));
  }
  const bool split = parts.size() > 1;
  ProgramText main(ending);
  main.line("MODULE " + name);
  writeDeclarations(main, motion, cell, rapid, names);
  beginMain(main, cell, rapid);
  if (split) {
    for (const ProgramPart& part : parts) main.line("    p" + part.name + ";");
    endMain(main, cell, rapid);
    result.files.push_back(finishModule(name, main));
    result.warnings.push_back("the program is split into " + std::to_string(parts.size()) +
                              " modules of at most " + std::to_string(limit) +
                              " lines, called from " + name);
  }
  for (const ProgramPart& part : parts) {
    ProgramText module(ending);
    ProgramText& text = split ? module : main;
    if (split) {
      text.line("MODULE " + part.name);
      text.line("  PROC p" + part.name + "()");
    }
    RapidPartWriter writer(motion, cell, rapid, names, configurations, text);
    for (std::size_t i = part.points.begin; i < part.points.end; ++i) {
      reportEvery(progress, i, count);
      writer.writePoint(i, result);
    }
    if (split) {
      text.line("  ENDPROC");
    } else {
      endMain(text, cell, rapid);
    }
    result.files.push_back(finishModule(part.name, text));
  }
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
