// KUKA KRL writer (see krl_writer.hpp). Phase: "export" (split into programs, then the .src and
// .dat of each).
#include "curvedslicer/export/krl_writer.hpp"

#include <string>
#include <vector>

#include "writer_support.hpp"

namespace curvedslicer {

namespace {

using namespace export_detail;

/// Lines of the single program's or the main program's header and end: &ACCESS, &REL, DEF, two
/// comments, the interrupt declaration and switch, BAS, $TOOL, $BASE, $ACT_EX_AX, $APO.CDIS, END.
constexpr std::size_t kKrlHeaderLines = 13;
/// .dat lines besides the declarations: &ACCESS, &REL, DEFDAT, ENDDAT.
constexpr std::size_t kKrlDatLines = 4;

/// The cell's KRL settings. @throws InvalidInput naming /controller/krl and the cell's source.
const KrlController& requireKrl(const Cell& cell) {
  if (!cell.controller.krl) {
    throw InvalidInput(cell.controller.source +
                       ": /controller/krl is missing: (absent); add the KRL settings "
                       "(arc_on_output, …, see resources/schema/cell.schema.json) to the cell");
  }
  return *cell.controller.krl;
}

/// "X x,Y y,Z z,A a,B b,C c" of a TCP pose (mm, deg; A about z, B about y, C about x).
void appendXyzAbc(std::string& b, const Pose& tcp) {
  const XyzRpy c = toXyzRpy(tcp);
  b += "X ";
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

/// The tool frame a KRL position states for the cell's TCP pose `tcp`. KUKA's flange frame has x
/// out of the flange, the cell's z (it is the cell's flange turned -90 deg about y,
/// resources/cells/README.md), and so has a calibrated $TOOL_DATA: the torch along x. The same
/// TCP point, with the frame turned -90 deg about its own y, so that x is the cell's torch axis.
Pose kukaToolFrame(const Pose& tcp) {
  Pose kuka = tcp;
  kuka.linear() = tcp.linear() * Eigen::AngleAxisd(-0.5 * kPi, Vec3::UnitY()).toRotationMatrix();
  return kuka;
}

/// ",E1 tilt,E2 rotation,E3 0.0,…,E6 0.0}" (controller degrees).
void appendExternal(std::string& b, const Cell& cell, const MotionPoint& p) {
  b += ",E1 ";
  appendFixed(b, tiltDegrees(cell, p.a1), 4);
  b += ",E2 ";
  appendFixed(b, rotationDegrees(cell, p.a2), 4);
  b += ",E3 0.0,E4 0.0,E5 0.0,E6 0.0}";
}

/// ",S s,T t" of an E6POS after KUKA's definition: S bit 0 = the wrist centre behind A1's axis
/// (overhead area: the IK's "back" branch), bit 1 = A3 at or above the angle φ at which the arm is
/// stretched (the IK's elbow-up branch, the usual working pose; 0 for elbow down), bit 2 = A5
/// negative; T bit k = joint k+1 negative; from the point's configuration (its weld's).
void appendStatusTurn(std::string& b, const RobotConfiguration& c) {
  int s = 0, t = 0;
  if (c.branch & 1) s |= 1;
  if (!(c.branch & 2)) s |= 2;
  if (c.negative[4]) s |= 4;
  for (int j = 0; j < 6; ++j) {
    if (c.negative[j]) t |= 1 << j;
  }
  b += ",S ";
  appendInt(b, s);
  b += ",T ";
  appendInt(b, t);
}

/// The .dat declaration of point i's position XP<k>: an E6AXIS {A1 … A6, E1 … E6} for the home
/// pose, else an E6POS {X … C, S, T, E1 … E6}.
void declarePosition(ProgramText& dat, const MotionPlan& motion, const Cell& cell,
                     const PointConfigurations& configurations, std::size_t i, std::size_t k) {
  const MotionPoint& p = motion.points[i];
  std::string& b = dat.buffer();
  b += p.kind == MoveKind::Home ? "DECL E6AXIS XP" : "DECL E6POS XP";
  appendInt(b, static_cast<std::int64_t>(k));
  b += "={";
  if (p.kind == MoveKind::Home) {
    for (int j = 0; j < 6; ++j) {
      b += j == 0 ? "A" : ",A";
      appendInt(b, j + 1);
      b += ' ';
      appendFixed(b, p.joints[j] * kRadToDeg, 4);
    }
  } else {
    appendXyzAbc(b, kukaToolFrame(cell.exportOptions.coordinated ? p.toolInTable : p.toolInWorld));
    appendStatusTurn(b, configurations.at(i));
  }
  appendExternal(b, cell, p);
  dat.endLine();
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

/// Upper bound of the .src lines point i needs (motion, speeds, arc and wire-feed lines, dwell).
std::size_t pointLines(const MotionPlan& motion, const Cell& cell, std::size_t i) {
  const MotionPoint& p = motion.points[i];
  std::size_t lines = 2;                     // $VEL.CP and the motion
  if (p.kind == MoveKind::Home) lines += 8;  // $VEL_AXIS / $VEL_EXTAX
  if (p.pathStart) lines += 3;               // arc on, wait, wire feed
  if (p.arcOn) lines += 2;                   // arc on trigger, wire feed trigger
  if (p.pathEnd) lines += 1;                 // arc off trigger
  if (dwellAfter(motion, cell, i) > 0.0) ++lines;
  return lines;
}

/// The $ANOUT value of the wire feed at point i (fraction of the full scale).
/// @throws InvalidInput if the wire feed exceeds the full scale.
double wireFeedFraction(const Cell& cell, const KrlController& krl, const MotionPoint& p) {
  const double wfs = wireFeedOf(cell, p);
  if (wfs > krl.wireFeedFullScale) {
    throw InvalidInput(
        "KRL export: wire feed beyond the analog output's full scale: " + formatFixed(wfs, 3) +
        " m/min > " + formatFixed(krl.wireFeedFullScale, 3) +
        " m/min; raise /controller/krl/wire_feed_full_scale_m_min in " + cell.controller.source);
  }
  return wfs / krl.wireFeedFullScale;
}

/// Writes one program: the .src moving through `part.points` (positions XP1… from its .dat).
class KrlPartWriter {
 public:
  KrlPartWriter(const MotionPlan& motion, const Cell& cell, const KrlController& krl,
                const PointConfigurations& configurations, ProgramText& src, ProgramText& dat)
      : motion_(motion),
        cell_(cell),
        krl_(krl),
        configurations_(configurations),
        src_(src),
        dat_(dat),
        out_("$OUT[" + std::to_string(krl.arcOnOutput) + "]") {}

  void writePoint(std::size_t i, ExportResult& result);

 private:
  void writeWireFeed(std::size_t i, bool trigger);
  void writeMotion(std::size_t i);

  const MotionPlan& motion_;
  const Cell& cell_;
  const KrlController& krl_;
  const PointConfigurations& configurations_;
  ProgramText& src_;
  ProgramText& dat_;
  std::string out_;
  std::size_t positions_ = 0;
  double lastSpeed_ = -1.0;
  double lastWireFeed_ = -1.0;
};

void KrlPartWriter::writeWireFeed(std::size_t i, bool trigger) {
  if (krl_.wireFeedAnalogOutput <= 0) return;
  const double fraction = wireFeedFraction(cell_, krl_, motion_.points[i]);
  if (fraction == lastWireFeed_) return;
  lastWireFeed_ = fraction;
  std::string& b = src_.buffer();
  if (trigger) b += "TRIGGER WHEN DISTANCE=0 DELAY=0 DO ";
  b += "$ANOUT[";
  appendInt(b, krl_.wireFeedAnalogOutput);
  b += "]=";
  appendFixed(b, fraction, 4);
  src_.endLine();
}

void KrlPartWriter::writeMotion(std::size_t i) {
  const MotionPoint& p = motion_.points[i];
  declarePosition(dat_, motion_, cell_, configurations_, i, ++positions_);
  std::string& b = src_.buffer();
  b += p.kind == MoveKind::Home || i == 0 ? "PTP XP" : "LIN XP";
  appendInt(b, static_cast<std::int64_t>(positions_));
  if (p.kind == MoveKind::Path && !p.pathEnd && !p.pathStart && i > 0) b += " C_DIS";
  src_.endLine();
}

void KrlPartWriter::writePoint(std::size_t i, ExportResult& result) {
  const MotionPoint& p = motion_.points[i];
  const bool waitForArc = krl_.arcEstablishedInput > 0;
  if (p.kind == MoveKind::Home) {
    if (i > 0) writeAxisSpeeds(src_, jointSpeedPercent(motion_, cell_, i));
  } else if (i > 0 && p.speed != lastSpeed_) {
    std::string& v = src_.buffer();
    v += "$VEL.CP=";
    appendSpeed(v, p.speed / 1000.0, 5, speedReduced(p));
    src_.endLine();
    lastSpeed_ = p.speed;
  }
  if (p.arcOn && i > 0) {
    const bool firstWeld = motion_.points[i - 1].pathStart;
    if (firstWeld && !waitForArc) src_.line("TRIGGER WHEN DISTANCE=0 DELAY=0 DO " + out_ + "=TRUE");
    writeWireFeed(i, true);
    if (p.pathEnd) src_.line("TRIGGER WHEN DISTANCE=1 DELAY=0 DO " + out_ + "=FALSE");
  }
  writeMotion(i);
  ++result.motionCount;
  if (p.pathStart) {
    ++result.arcCount;
    lastWireFeed_ = -1.0;  // every weld sets its wire feed
    if (waitForArc) {
      // Stopped on the path start (no approximation there): wire feed, arc on, wait for it.
      if (i + 1 < motion_.points.size()) writeWireFeed(i + 1, false);
      src_.line(out_ + "=TRUE");
      src_.line("WAIT FOR $IN[" + std::to_string(krl_.arcEstablishedInput) + "]");
    }
  }
  const double dwell = dwellAfter(motion_, cell_, i);
  if (dwell > 0.0) {
    std::string& w = src_.buffer();
    w += "WAIT SEC ";
    appendFixed(w, dwell, 2);
    src_.endLine();
  }
}

/// &ACCESS, &REL and DEF of a program.
void beginProgram(ProgramText& src, const std::string& name) {
  src.line("&ACCESS RVP");
  src.line("&REL 1");
  src.line("DEF " + name + "()");
}

/// The initialisation of the program that runs first (the single or the main program).
void writeInitialisation(ProgramText& src, const MotionPlan& motion, const Cell& cell,
                         const KrlController& krl) {
  const bool coordinated = cell.exportOptions.coordinated;
  src.line("; curvedslicer: " + std::to_string(motion.points.size()) + " points, " +
           std::to_string(motion.paths.size()) +
           " paths; E1 = positioner tilt, E2 = rotation (deg)");
  src.line(coordinated ? "; positions: TCP in the positioner table frame (BASE_DATA[" +
                             std::to_string(krl.baseNumber) + "])"
                       : "; positions: TCP in the world frame");
  src.line("GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM()");
  src.line("INTERRUPT ON 3");
  src.line("BAS(#INITMOV,0)");
  src.line("$TOOL=TOOL_DATA[" + std::to_string(cell.tool.number) + "]");
  if (coordinated) {
    src.line("$BASE=EK(MACHINE_DEF[2].ROOT,MACHINE_DEF[2].MECH_TYPE,BASE_DATA[" +
             std::to_string(krl.baseNumber) + "])");
    src.line("$ACT_EX_AX=2");
  } else {
    src.line("$BASE=$NULLFRAME");
  }
  std::string& b = src.buffer();
  b += "$APO.CDIS=";
  appendFixed(b, krl.approximationDistance, 3);
  src.endLine();
}

/// The .dat of program `name` with the declarations written into `declarations`.
ExportFile finishData(const Cell& cell, const std::string& name, ProgramText& declarations) {
  ProgramText dat(cell.exportOptions.lineEnding);
  dat.line("&ACCESS RVP");
  dat.line("&REL 1");
  dat.line("DEFDAT " + name);
  const std::size_t lines = declarations.lineCount();
  dat.buffer() += declarations.take();
  dat.line("ENDDAT");
  ExportFile file;
  file.name = name + ".dat";
  file.lines = lines + kKrlDatLines;
  file.text = dat.take();
  return file;
}

ExportFile finishSource(const std::string& name, ProgramText& src) {
  src.line("END");
  ExportFile file;
  file.name = name + ".src";
  file.lines = src.lineCount();
  file.text = src.take();
  return file;
}

}  // namespace

ExportResult KrlWriter::write(const MotionPlan& motion, const Cell& cell,
                              const ExportOptions& options, const Progress& progress) const {
  requirePoints(motion, "KRL");
  const KrlController& krl = requireKrl(cell);
  checkJointLimits(motion, cell);
  const LineEnding ending = cell.exportOptions.lineEnding;
  const std::string name = makeProgramName(baseProgramName(cell, options), 24, false);
  const std::size_t count = motion.points.size();
  std::vector<std::size_t> costs(count);
  for (std::size_t i = 0; i < count; ++i) costs[i] = pointLines(motion, cell, i);
  const std::size_t limit = static_cast<std::size_t>(
      krl.maxLinesPerFile > 0 ? krl.maxLinesPerFile : cell.exportOptions.maxLinesPerJob);
  const std::vector<ProgramPart> parts =
      splitIntoParts(motion, costs, name, limit, kKrlHeaderLines, 24, "KRL");

  ExportResult result;
  result.format = ExportFormat::Krl;
  const PointConfigurations configurations(motion);
  if (std::string mismatch = describeBranchMismatches(motion); !mismatch.empty()) {
    result.warnings.push_back(std::move(mismatch));
  }
  const bool split = parts.size() > 1;
  if (split) {
    ProgramText src(ending), declarations(ending);
    beginProgram(src, name);
    writeInitialisation(src, motion, cell, krl);
    for (const ProgramPart& part : parts) src.line(part.name + "()");
    result.files.push_back(finishSource(name, src));
    result.files.push_back(finishData(cell, name, declarations));
    result.warnings.push_back("the program is split into " + std::to_string(parts.size()) +
                              " programs of at most " + std::to_string(limit) +
                              " lines, called from " + name);
  }
  for (const ProgramPart& part : parts) {
    ProgramText src(ending), declarations(ending);
    beginProgram(src, part.name);
    if (!split) writeInitialisation(src, motion, cell, krl);
    KrlPartWriter writer(motion, cell, krl, configurations, src, declarations);
    for (std::size_t i = part.points.begin; i < part.points.end; ++i) {
      reportEvery(progress, i, count);
      writer.writePoint(i, result);
    }
    result.files.push_back(finishSource(part.name, src));
    result.files.push_back(finishData(cell, part.name, declarations));
  }
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
