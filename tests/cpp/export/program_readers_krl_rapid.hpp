// Strict readers of whole KRL and RAPID exports (every file of an ExportResult): each follows the
// main program's calls in order, checks the files' structure (KRL: .src/.dat pairs, DEF/DEFDAT
// names equal to the file names, BAS(#INITMOV,0), $APO before approximation, positions declared
// once in the .dat and used by name; RAPID: MODULE names equal to the file names, the tooldata
// and wobjdata used are declared, every called procedure defined once), the line limit per file,
// that every number is finite, and how the arc is switched (the cell's output / signal, the
// arc-established wait when the cell names an input). The moves go into the ReadProgram of
// program_readers.hpp (configuration, speed, welds, dwells) and their positions into
// ReadPositions, which expectRoundTrip takes through the cell's forward kinematics back onto the
// plan's points. A line a reader does not know is a test failure. The readers parse text only
// and share nothing with the writers.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "program_readers.hpp"

namespace curvedslicer::testing {

/// strictDouble that must also be finite (a program must never state nan or inf).
inline double finiteDouble(const std::string& text, const std::string& line) {
  const double value = strictDouble(text, line);
  EXPECT_TRUE(std::isfinite(value)) << "not a finite number: '" << text << "' in " << line;
  return value;
}

/// A target as a program states it: joints (deg) or a TCP pose, and the positioner (deg).
struct ReadPosition {
  bool jointTarget = false;
  std::vector<double> joints;   ///< deg, controller convention
  Pose tcp = Pose::Identity();  ///< in the table (coordinated) or world frame
  double e1 = 0.0, e2 = 0.0;    ///< positioner tilt and rotation, controller degrees
  std::optional<StatedConfiguration> configuration;  ///< KRL: S and T of an E6POS
};

/// A whole export as a reader saw it.
struct ReadExport {
  ReadProgram program;                  ///< moves in execution order
  std::vector<ReadPosition> positions;  ///< one per move
  /// Wire feed (m/min) in force during each move (NaN where the program sets none).
  std::vector<double> wireFeed;
  std::size_t arcWaits = 0;  ///< arc-established waits
  std::size_t programs = 0;  ///< programs / modules with motions
};

/// Lines of `file` with the cell's line ending (a wrong ending is a failure) and at most `limit`.
inline std::vector<std::string> strictLines(const ExportFile& file, const Cell& cell,
                                            std::size_t limit) {
  bool endings = false;
  const auto lines =
      splitLines(file.text, cell.exportOptions.lineEnding == LineEnding::Crlf, &endings);
  EXPECT_TRUE(endings) << file.name << ": line endings";
  EXPECT_EQ(lines.size(), file.lines) << file.name << ": line count stated in ExportFile";
  EXPECT_LE(lines.size(), limit) << file.name << ": more lines than the cell allows";
  return lines;
}

inline std::string fileStem(const std::string& name, const std::string& extension) {
  const bool ok = name.size() > extension.size() &&
                  name.compare(name.size() - extension.size(), extension.size(), extension) == 0;
  EXPECT_TRUE(ok) << name << " should end in " << extension;
  return ok ? name.substr(0, name.size() - extension.size()) : name;
}

/// The part-frame point a read position states, through the cell's forward kinematics (robot FK
/// for joint targets, positioner FK for the table or world frame).
inline Vec3 partPointOfRead(const Cell& cell, const ReadPosition& p) {
  const double a1 = cell.positioner.tilt.sign * p.e1 * kDegT;
  const double a2 = cell.positioner.rotation.sign * p.e2 * kDegT;
  if (p.jointTarget) return partPointFromJointDegrees(cell, p.joints, a1, a2);
  return cell.exportOptions.coordinated ? partPointFromTable(cell, p.tcp, a1, a2)
                                        : partPointFromWorld(cell, p.tcp.translation(), a1, a2);
}

/// Every read position lands on its motion point (part frame) within `tolerance` mm, the
/// positioner angles within 1e-4 deg, and joint targets state the point's joints.
inline void expectRoundTrip(const ReadExport& read, const MotionPlan& motion, const Cell& cell,
                            double tolerance = 0.01) {
  ASSERT_EQ(read.positions.size(), motion.points.size()) << "one move per motion point";
  double worst = 0.0;
  std::size_t worstAt = 0;
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const ReadPosition& r = read.positions[i];
    const MotionPoint& p = motion.points[i];
    EXPECT_NEAR(cell.positioner.tilt.sign * r.e1 * kDegT, p.a1, 1e-4 * kDegT) << i;
    EXPECT_NEAR(cell.positioner.rotation.sign * r.e2 * kDegT, p.a2, 1e-4 * kDegT) << i;
    const double error = (partPointOfRead(cell, r) - p.position).norm();
    if (error > worst) worst = error, worstAt = i;
  }
  EXPECT_LE(worst, tolerance) << "round trip: point " << worstAt << " lands " << worst
                              << " mm from the plan";
}

/// Every Cartesian position a KRL or RAPID program states turns the torch as planned: RAPID states
/// the cell's tool frame (ABB's tool0 is the cell's flange), KRL states KUKA's tool frame, whose x
/// is the torch axis (the cell tool's z) and whose y is the cell tool's y (KUKA's flange has x out
/// of the flange; resources/cells/README.md). Axes compared within `tolerance` (unit vectors).
inline void expectToolOrientation(const ReadExport& read, const MotionPlan& motion,
                                  const Cell& cell, bool krl, double tolerance = 1e-5) {
  ASSERT_EQ(read.positions.size(), motion.points.size());
  std::size_t off = 0;
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    if (read.positions[i].jointTarget) continue;
    const MotionPoint& p = motion.points[i];
    const Mat3 planned = (cell.exportOptions.coordinated ? p.toolInTable : p.toolInWorld).linear();
    const Mat3 stated = read.positions[i].tcp.linear();
    const Vec3 torch = planned.col(2);
    const double error =
        krl ? std::max((stated.col(0) - torch).norm(), (stated.col(1) - planned.col(1)).norm())
            : (stated - planned).norm();
    if (error > tolerance && off++ < 3) {
      ADD_FAILURE() << (krl ? "KRL" : "RAPID") << " position " << i << " turns the tool " << error
                    << " off the plan: " << read.program.moves[i].line;
    }
  }
  EXPECT_EQ(off, 0u);
}

// ---- KRL --------------------------------------------------------------------------------------

/// Reads a KRL .dat: DEFDAT <stem>, declarations "DECL E6POS|E6AXIS XP<k>={…}", ENDDAT.
inline std::map<std::string, ReadPosition> readKrlData(const ExportFile& file, const Cell& cell,
                                                       std::size_t limit, const std::string& stem) {
  std::map<std::string, ReadPosition> positions;
  const auto lines = strictLines(file, cell, limit);
  EXPECT_GE(lines.size(), 4u) << file.name;
  if (lines.size() < 4) return positions;
  EXPECT_EQ(lines[0], "&ACCESS RVP") << file.name;
  EXPECT_EQ(lines[1], "&REL 1") << file.name;
  EXPECT_EQ(lines[2], "DEFDAT " + stem) << file.name << ": DEFDAT name = file name";
  EXPECT_EQ(lines.back(), "ENDDAT") << file.name;
  const std::vector<std::string> e6pos{"X", "Y",  "Z",  "A",  "B",  "C",  "S",
                                       "T", "E1", "E2", "E3", "E4", "E5", "E6"};
  const std::vector<std::string> e6axis{"A1", "A2", "A3", "A4", "A5", "A6",
                                        "E1", "E2", "E3", "E4", "E5", "E6"};
  for (std::size_t k = 3; k + 1 < lines.size(); ++k) {
    const std::string& line = lines[k];
    const bool axis = startsWith(line, "DECL E6AXIS XP"), pos = startsWith(line, "DECL E6POS XP");
    if (!axis && !pos) {
      ADD_FAILURE() << file.name << ": unknown .dat line: " << line;
      continue;
    }
    const std::size_t nameAt = line.find("XP"), eq = line.find('=');
    const std::string name = line.substr(nameAt, eq - nameAt);
    strictInt(name.substr(2), line);
    EXPECT_EQ(positions.count(name), 0u) << file.name << ": " << name << " declared twice";
    const auto fields = aggregateFields(line);
    std::vector<std::string> keys;
    std::vector<double> values;
    for (const auto& [key, value] : fields) {
      keys.push_back(key);
      values.push_back(finiteDouble(value, line));
    }
    ReadPosition p;
    p.jointTarget = axis;
    if (axis) {
      EXPECT_EQ(keys, e6axis) << line;
      if (keys != e6axis) continue;
      p.joints.assign(values.begin(), values.begin() + 6);
      p.e1 = values[6], p.e2 = values[7];
    } else {
      EXPECT_EQ(keys, e6pos) << line;
      if (keys != e6pos) continue;
      // A about z (yaw), B about y (pitch), C about x (roll).
      p.tcp = poseFromXyzRpy(values[0], values[1], values[2], values[5], values[4], values[3]);
      p.e1 = values[8], p.e2 = values[9];
      p.configuration = decodeStatusTurn(strictInt(fields[6].second, line),
                                         strictInt(fields[7].second, line), line);
    }
    for (std::size_t e = keys.size() - 4; e < keys.size(); ++e) {
      EXPECT_EQ(values[e], 0.0) << "unused external axis set: " << line;
    }
    positions[name] = p;
  }
  return positions;
}

/// State of a KRL reading across programs (system variables are global).
struct KrlState {
  bool initialised = false, apoSet = false, onPending = false, offPending = false;
  bool waitPending = false;  ///< $OUT=TRUE seen, WAIT FOR $IN expected next
  double velCp = std::numeric_limits<double>::quiet_NaN();
  double wireFeed = std::numeric_limits<double>::quiet_NaN();
  double pendingWireFeed = std::numeric_limits<double>::quiet_NaN();
  WeldTracker welds;
};

/// Reads every program of a KRL export in execution order (main program first, its calls).
inline ReadExport readKrlExport(const ExportResult& result, const Cell& cell) {
  ReadExport read;
  const KrlController& krl = *cell.controller.krl;
  const std::size_t limit = static_cast<std::size_t>(
      krl.maxLinesPerFile > 0 ? krl.maxLinesPerFile : cell.exportOptions.maxLinesPerJob);
  const std::string out = "$OUT[" + std::to_string(krl.arcOnOutput) + "]";
  const std::string anout = "$ANOUT[" + std::to_string(krl.wireFeedAnalogOutput) + "]=";
  std::map<std::string, std::pair<const ExportFile*, const ExportFile*>> programs;
  EXPECT_EQ(result.files.size() % 2, 0u) << "KRL files come in .src/.dat pairs";
  for (std::size_t f = 0; f + 1 < result.files.size(); f += 2) {
    const std::string stem = fileStem(result.files[f].name, ".src");
    EXPECT_EQ(fileStem(result.files[f + 1].name, ".dat"), stem) << "the .dat follows its .src";
    EXPECT_EQ(programs.count(stem), 0u) << stem << " twice";
    programs[stem] = {&result.files[f], &result.files[f + 1]};
  }
  if (result.files.empty()) return read;
  std::set<std::string> called;
  KrlState state;
  // Reads one program; `main` = the program that runs first.
  std::function<void(const std::string&, bool)> readProgram = [&](const std::string& stem,
                                                                  bool main) {
    const auto [src, dat] = programs.at(stem);
    auto positions = readKrlData(*dat, cell, limit, stem);
    std::set<std::string> used;
    const auto lines = strictLines(*src, cell, limit);
    ASSERT_GE(lines.size(), 4u) << src->name;
    EXPECT_EQ(lines[0], "&ACCESS RVP") << src->name;
    EXPECT_EQ(lines[1], "&REL 1") << src->name;
    EXPECT_EQ(lines[2], "DEF " + stem + "()") << src->name << ": DEF name = file name";
    EXPECT_EQ(lines.back(), "END") << src->name;
    bool moved = false;
    for (std::size_t k = 3; k + 1 < lines.size(); ++k) {
      const std::string& line = lines[k];
      EXPECT_FALSE(state.waitPending && !startsWith(line, "WAIT FOR $IN["))
          << "the arc-established wait must follow the arc output: " << line;
      if (startsWith(line, ";")) continue;
      if (main && !moved && !state.initialised &&
          (line == "GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM()" ||
           line == "INTERRUPT ON 3")) {
        continue;
      }
      if (line == "BAS(#INITMOV,0)") {
        EXPECT_TRUE(main && !state.initialised) << src->name << ": BAS once, in the main program";
        state.initialised = true;
        continue;
      }
      if (startsWith(line, "$TOOL=TOOL_DATA[") || startsWith(line, "$BASE=") ||
          line == "$ACT_EX_AX=2") {
        EXPECT_TRUE(main && state.initialised && !moved) << "after BAS, before motion: " << line;
        continue;
      }
      if (startsWith(line, "$APO.CDIS=")) {
        EXPECT_GT(finiteDouble(line.substr(10), line), 0.0) << line;
        state.apoSet = true;
        continue;
      }
      if (startsWith(line, "$VEL_AXIS[") || startsWith(line, "$VEL_EXTAX[")) {
        const double percent = finiteDouble(line.substr(line.find('=') + 1), line);
        EXPECT_TRUE(percent >= 1.0 && percent <= 100.0) << line;
        continue;
      }
      if (startsWith(line, "WAIT SEC ")) {
        recordDwell(read.program, line.substr(9), line);
        continue;
      }
      if (startsWith(line, "$VEL.CP=")) {
        state.velCp = finiteDouble(line.substr(8), line) * 1000.0;
        EXPECT_GT(state.velCp, 0.0) << line;
        continue;
      }
      if (line == "TRIGGER WHEN DISTANCE=0 DELAY=0 DO " + out + "=TRUE") {
        EXPECT_EQ(krl.arcEstablishedInput, 0) << "with an arc-established input the program "
                                                 "must stop and wait: "
                                              << line;
        state.welds.on(read.program, line);
        state.onPending = true;
        continue;
      }
      if (line == "TRIGGER WHEN DISTANCE=1 DELAY=0 DO " + out + "=FALSE") {
        state.offPending = true;
        continue;
      }
      if (line == out + "=TRUE") {
        EXPECT_GT(krl.arcEstablishedInput, 0) << "a plain output stops the advance run: " << line;
        state.welds.on(read.program, line);
        state.waitPending = true;
        continue;
      }
      if (startsWith(line, "WAIT FOR $IN[")) {
        EXPECT_TRUE(state.waitPending) << line;
        EXPECT_EQ(line, "WAIT FOR $IN[" + std::to_string(krl.arcEstablishedInput) + "]");
        state.waitPending = false;
        ++read.arcWaits;
        continue;
      }
      const bool anTrigger = startsWith(line, "TRIGGER WHEN DISTANCE=0 DELAY=0 DO " + anout);
      if (krl.wireFeedAnalogOutput > 0 && (anTrigger || startsWith(line, anout))) {
        const double v = finiteDouble(line.substr(line.rfind('=') + 1), line);
        EXPECT_TRUE(v >= 0.0 && v <= 1.0) << line;
        (anTrigger ? state.pendingWireFeed : state.wireFeed) = v * krl.wireFeedFullScale;
        continue;
      }
      const bool ptp = startsWith(line, "PTP XP"), lin = startsWith(line, "LIN XP");
      if (!ptp && !lin) {
        if (main && line.size() > 2 && line.compare(line.size() - 2, 2, "()") == 0) {
          const std::string callee = line.substr(0, line.size() - 2);
          EXPECT_TRUE(programs.count(callee) && callee != stem) << "call of no program: " << line;
          EXPECT_TRUE(called.insert(callee).second) << callee << " called twice";
          EXPECT_TRUE(state.initialised) << "call before BAS: " << line;
          if (programs.count(callee) && callee != stem) readProgram(callee, false);
          continue;
        }
        ADD_FAILURE() << src->name << ": unknown KRL line: " << line;
        continue;
      }
      EXPECT_TRUE(state.initialised) << "motion before BAS(#INITMOV,0): " << line;
      std::string name = line.substr(4);
      const bool cdis = name.size() > 6 && name.compare(name.size() - 6, 6, " C_DIS") == 0;
      if (cdis) name.resize(name.size() - 6);
      EXPECT_TRUE(!cdis || (lin && state.apoSet)) << "C_DIS needs LIN and $APO.CDIS: " << line;
      const auto it = positions.find(name);
      if (it == positions.end()) {
        ADD_FAILURE() << src->name << ": " << name << " used but not declared in " << dat->name;
        continue;
      }
      used.insert(name);
      ProgramMove move;
      move.line = line;
      move.joint = ptp;
      move.jointTarget = it->second.jointTarget;
      EXPECT_TRUE(ptp || !move.jointTarget) << "an E6AXIS needs PTP: " << line;
      move.configuration = it->second.configuration;
      if (lin) move.speed = state.velCp;
      moved = true;
      read.program.moves.push_back(std::move(move));
      read.positions.push_back(it->second);
      if (!std::isnan(state.pendingWireFeed)) {
        state.wireFeed = state.pendingWireFeed;
        state.pendingWireFeed = std::numeric_limits<double>::quiet_NaN();
      }
      read.wireFeed.push_back(state.wireFeed);
      if (state.onPending) {
        EXPECT_TRUE(lin) << "the arc must go on with a LIN: " << line;
        state.onPending = false;
      }
      if (state.offPending) {
        state.welds.off(read.program, line);
        state.offPending = false;
      }
    }
    for (const auto& [name, p] : positions) {
      EXPECT_TRUE(used.count(name)) << dat->name << ": " << name << " declared but not used";
    }
    if (moved) ++read.programs;
  };
  readProgram(fileStem(result.files[0].name, ".src"), true);
  EXPECT_EQ(called.size() + 1, programs.size()) << "every program is called once";
  state.welds.finish();
  return read;
}

// ---- RAPID ------------------------------------------------------------------------------------

/// A robtarget / jointtarget literal's groups as numbers (9E9 allowed), every value finite.
inline std::vector<std::vector<double>> numericGroups(
    const std::vector<std::vector<std::string>>& g, const std::string& line) {
  std::vector<std::vector<double>> out;
  for (const auto& group : g) {
    std::vector<double> values;
    for (const auto& v : group) values.push_back(finiteDouble(v, line));
    out.push_back(values);
  }
  return out;
}

/// A tooldata literal [TRUE,[[x,y,z],[q1..q4]],[mass,[cx,cy,cz],[1,0,0,0],0,0,0]]; (robot-held,
/// the cell's TCP, the cell's load).
inline void expectToolData(const std::string& literal, const Cell& cell,
                           const RapidController& rapid) {
  std::string skeleton, flat;
  for (char ch : literal) {
    if (ch == '[' || ch == ']') skeleton += ch;
    flat += (ch == '[' || ch == ']') ? ',' : ch;
  }
  EXPECT_EQ(skeleton, "[[[][]][[][]]]") << literal;
  EXPECT_EQ(literal.back(), ';') << literal;
  std::vector<std::string> tokens;
  for (const std::string& t : splitFields(flat.substr(0, flat.size() - 1), ',')) {
    if (!t.empty()) tokens.push_back(t);
  }
  ASSERT_EQ(tokens.size(), 19u) << literal;
  EXPECT_EQ(tokens[0], "TRUE") << literal;
  std::vector<double> v;
  for (std::size_t k = 1; k < tokens.size(); ++k) v.push_back(finiteDouble(tokens[k], literal));
  EXPECT_NEAR((Vec3(v[0], v[1], v[2]) - cell.tool.tcp.translation()).norm(), 0.0, 1e-3) << literal;
  const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
  EXPECT_NEAR(q.norm(), 1.0, 1e-6) << literal;
  EXPECT_LT((q.normalized().toRotationMatrix() - cell.tool.tcp.rotation()).norm(), 1e-6) << literal;
  EXPECT_NEAR(v[7], rapid.toolMass, 1e-3) << literal;
  EXPECT_NEAR((Vec3(v[8], v[9], v[10]) - rapid.toolCog).norm(), 0.0, 1e-3) << literal;
  EXPECT_GT(v[7], 0.0) << "a tool load needs a mass: " << literal;
}

/// Reads every module of a RAPID export in execution order (main() first, its calls).
inline ReadExport readRapidExport(const ExportResult& result, const Cell& cell) {
  ReadExport read;
  const RapidController& rapid = *cell.controller.rapid;
  const std::size_t limit = static_cast<std::size_t>(
      rapid.maxLinesPerModule > 0 ? rapid.maxLinesPerModule : cell.exportOptions.maxLinesPerJob);
  const bool coordinated = cell.exportOptions.coordinated;
  std::map<std::string, std::vector<std::string>> procedures;  // name -> body lines
  std::set<std::string> declared;                              // tooldata / wobjdata names
  std::string mainStem;
  for (std::size_t f = 0; f < result.files.size(); ++f) {
    const ExportFile& file = result.files[f];
    const std::string stem = fileStem(file.name, ".mod");
    if (f == 0) mainStem = stem;
    const auto lines = strictLines(file, cell, limit);
    EXPECT_GE(lines.size(), 4u) << file.name;
    if (lines.size() < 4) continue;
    EXPECT_EQ(lines[0], "MODULE " + stem) << file.name << ": MODULE name = file name";
    EXPECT_EQ(lines.back(), "ENDMODULE") << file.name;
    std::string proc;
    for (std::size_t k = 1; k + 1 < lines.size(); ++k) {
      const std::string& raw = lines[k];
      const std::string line = raw.substr(std::min(raw.find_first_not_of(' '), raw.size()));
      if (startsWith(line, "!")) continue;
      if (proc.empty()) {
        if (startsWith(line, "PROC ")) {
          proc = line.substr(5, line.find('(') - 5);
          EXPECT_EQ(line, "PROC " + proc + "()") << file.name;
          EXPECT_EQ(proc, f == 0 ? std::string("main") : "p" + stem)
              << file.name << ": procedure name";
          EXPECT_EQ(procedures.count(proc), 0u) << proc << " defined twice";
          procedures[proc];
          continue;
        }
        EXPECT_EQ(f, 0u) << "declarations only in the main module: " << line;
        if (startsWith(line, "PERS tooldata ")) {
          declared.insert(line.substr(14, line.find(' ', 14) - 14));
          expectToolData(line.substr(line.find(" := ") + 4), cell, rapid);
        } else if (startsWith(line, "TASK PERS wobjdata ")) {
          const std::string name = line.substr(19, line.find(' ', 19) - 19);
          const std::string unit =
              coordinated ? "[FALSE, FALSE, \"" + rapid.mechUnit + "\", " : "[FALSE, TRUE, \"\", ";
          EXPECT_NE(line.find(" := " + unit + "[[0,0,0],[1,0,0,0]], [[0,0,0],[1,0,0,0]]];"),
                    std::string::npos)
              << line;
          declared.insert(name);
        } else {
          ADD_FAILURE() << file.name << ": unknown declaration: " << line;
        }
        continue;
      }
      if (line == "ENDPROC") {
        proc.clear();
        continue;
      }
      procedures[proc].push_back(line);
    }
    EXPECT_TRUE(proc.empty()) << file.name << ": PROC without ENDPROC";
  }
  EXPECT_TRUE(procedures.count("main")) << "no PROC main()";
  std::set<std::string> called;
  WeldTracker welds;
  bool waitPending = false, activated = false;
  double wireFeed = std::numeric_limits<double>::quiet_NaN();
  const std::string setOn = "SetDO " + rapid.arcSignal + ", 1;",
                    setOff = "SetDO " + rapid.arcSignal + ", 0;";
  std::function<void(const std::string&)> run = [&](const std::string& proc) {
    bool moved = false;
    for (const std::string& line : procedures[proc]) {
      EXPECT_FALSE(waitPending && !startsWith(line, "WaitDI "))
          << "the arc-established wait must follow SetDO: " << line;
      if (proc == "main" && !moved && (line == "ConfJ \\On;" || line == "ConfL \\Off;")) continue;
      if (coordinated && line == "ActUnit " + rapid.mechUnit + ";") {
        activated = true;
        continue;
      }
      if (coordinated && line == "DeactUnit " + rapid.mechUnit + ";") {
        activated = false;
        continue;
      }
      if (startsWith(line, "WaitTime ") && line.back() == ';') {
        recordDwell(read.program, line.substr(9, line.size() - 10), line);
        continue;
      }
      if (line == setOn) {
        welds.on(read.program, line);
        waitPending = !rapid.arcEstablishedSignal.empty();
        continue;
      }
      if (line == setOff) {
        welds.off(read.program, line);
        continue;
      }
      if (startsWith(line, "WaitDI ")) {
        EXPECT_TRUE(waitPending) << line;
        EXPECT_EQ(line, "WaitDI " + rapid.arcEstablishedSignal + ", 1;");
        waitPending = false;
        ++read.arcWaits;
        continue;
      }
      if (!rapid.wireFeedSignal.empty() &&
          startsWith(line, "SetAO " + rapid.wireFeedSignal + ", ")) {
        const std::size_t at = rapid.wireFeedSignal.size() + 8;
        wireFeed = finiteDouble(line.substr(at, line.size() - at - 1), line);
        EXPECT_GT(wireFeed, 0.0) << line;
        continue;
      }
      const bool absJ = startsWith(line, "MoveAbsJ ["), moveJ = startsWith(line, "MoveJ ["),
                 moveL = startsWith(line, "MoveL [");
      if (!absJ && !moveJ && !moveL) {
        if (line.back() == ';' && procedures.count(line.substr(0, line.size() - 1)) &&
            proc == "main") {
          const std::string callee = line.substr(0, line.size() - 1);
          EXPECT_TRUE(called.insert(callee).second) << callee << " called twice";
          run(callee);
          continue;
        }
        ADD_FAILURE() << "unknown RAPID line in " << proc << ": " << line;
        continue;
      }
      EXPECT_TRUE(!coordinated || activated) << "motion outside ActUnit: " << line;
      ProgramMove move;
      move.line = line;
      move.joint = absJ || moveJ;
      std::size_t at = line.find('[');
      const auto target = numericGroups(bracketGroups(line, at), line);
      EXPECT_EQ(line.compare(at, 2, ", "), 0) << line;
      at += 2;
      const auto speed = numericGroups(bracketGroups(line, at), line);
      EXPECT_TRUE(speed.size() == 1 && speed[0].size() == 4 && speed[0][0] > 0.0) << line;
      if (speed.size() == 1 && !speed[0].empty()) move.speed = speed[0][0];
      ReadPosition p;
      const std::string rest = line.substr(at);
      if (absJ) {
        move.jointTarget = p.jointTarget = true;
        ASSERT_TRUE(target.size() == 2 && target[0].size() == 6 && target[1].size() == 6) << line;
        p.joints = target[0];
        EXPECT_TRUE(startsWith(rest, ", fine, ")) << line;
      } else {
        ASSERT_TRUE(target.size() == 4 && target[0].size() == 3 && target[1].size() == 4 &&
                    target[2].size() == 4 && target[3].size() == 6)
            << line;
        const Eigen::Quaterniond q(target[1][0], target[1][1], target[1][2], target[1][3]);
        EXPECT_NEAR(q.norm(), 1.0, 1e-6) << "unit quaternion: " << line;
        p.tcp = Pose::Identity();
        p.tcp.linear() = q.normalized().toRotationMatrix();
        p.tcp.translation() = Vec3(target[0][0], target[0][1], target[0][2]);
        StatedConfiguration c;
        const auto& cf = target[2];
        c.text = std::to_string(cf[0]) + "," + std::to_string(cf[1]) + "," + std::to_string(cf[2]) +
                 "," + std::to_string(cf[3]);
        c.quadrant[0] = static_cast<int>(cf[0]);
        c.quadrant[3] = static_cast<int>(cf[1]);
        c.quadrant[5] = static_cast<int>(cf[2]);
        c.branchMask = 7;
        c.branch = static_cast<int>(cf[3]);
        move.configuration = c;
        EXPECT_TRUE(startsWith(rest, ", fine, ") || startsWith(rest, ", z1, ")) << line;
        const std::string wobj = rest.substr(rest.find("\\WObj:=") + 7);
        EXPECT_TRUE(declared.count(wobj.substr(0, wobj.size() - 1))) << "undeclared wobj: " << line;
      }
      const std::vector<double>& ext = target.back();
      for (std::size_t e = 2; e < 6 && e < ext.size(); ++e) EXPECT_EQ(ext[e], 9e9) << line;
      p.e1 = ext.size() > 0 ? ext[0] : 0.0;
      p.e2 = ext.size() > 1 ? ext[1] : 0.0;
      const std::size_t toolAt = rest.find(", ", 2) + 2;
      const std::string tool = rest.substr(toolAt, rest.find_first_of(" ;", toolAt) - toolAt);
      EXPECT_TRUE(declared.count(tool)) << "undeclared tool " << tool << ": " << line;
      moved = true;
      read.program.moves.push_back(std::move(move));
      read.positions.push_back(p);
      read.wireFeed.push_back(wireFeed);
    }
    if (moved) ++read.programs;
  };
  run("main");
  EXPECT_EQ(called.size() + 1, procedures.size()) << "every procedure is called once";
  EXPECT_EQ(procedures.size(), result.files.size()) << "one procedure per module";
  welds.finish();
  return read;
}

// ---- whole exports ----------------------------------------------------------------------------

/// KRL and RAPID exports of `motion` read back by the strict readers: one move per point, one
/// weld per motion path, the round trip within 0.01 mm, every file at most `maxBytes`.
inline void expectKrlAndRapidReadBack(const MotionPlan& motion, const Cell& cell,
                                      std::size_t maxBytes = std::size_t{4} << 20) {
  for (ExportFormat format : {ExportFormat::Krl, ExportFormat::Rapid}) {
    SCOPED_TRACE(std::string(toString(format)));
    const ExportResult result = exportProgram(motion, cell, format);
    for (const ExportFile& file : result.files) {
      EXPECT_LE(file.text.size(), maxBytes) << file.name;
    }
    const ReadExport read =
        format == ExportFormat::Krl ? readKrlExport(result, cell) : readRapidExport(result, cell);
    EXPECT_EQ(read.program.welds.size(), motion.paths.size());
    expectRoundTrip(read, motion, placedCell(cell, motion));
    expectToolOrientation(read, motion, cell, format == ExportFormat::Krl);
  }
}

}  // namespace curvedslicer::testing
