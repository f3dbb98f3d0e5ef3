// Strict readers of the robot programs for the configuration and arc-off tests: each reads every
// motion line of a JBI or LS program (in execution order; JBI through the main job's CALLs; KRL
// and RAPID: program_readers_krl_rapid.hpp), the configuration it states (RCONF, S/T, confdata,
// CONFIG), whether it is a joint or a linear move, its linear speed, and where the arc goes on
// and off. A line a reader does not know is a test failure, so a writer cannot slip in an
// instruction the tests do not see. The readers parse text only and share nothing with the
// writers; the decoding of each format's configuration fields is written out here from the
// controller documentation, independently of the writers.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <sstream>

#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/robot/configuration.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "export_test_support.hpp"

namespace curvedslicer::testing {

/// What a program states about the robot configuration of one move (fields a format does not
/// state stay empty; `branchMask` = the IK branch bits it states).
struct StatedConfiguration {
  std::string text;  ///< the configuration fields as written (for constancy checks)
  int branchMask = 0;
  int branch = 0;
  std::array<std::optional<int>, 6> quadrant, turn;
  std::array<std::optional<bool>, 6> negative, beyond180;
};

struct ProgramMove {
  bool joint = false;        ///< MOVJ, PTP, MoveJ / MoveAbsJ, J
  bool jointTarget = false;  ///< the target is given in joints (E6AXIS, jointtarget, LS joints)
  std::optional<StatedConfiguration> configuration;         ///< absent for joint targets
  double speed = std::numeric_limits<double>::quiet_NaN();  ///< mm/s of a linear move
  std::string line;
  /// The part-frame TCP point the move's target states, through the cell's kinematics (set by
  /// the readers that reconstruct it: JBI, LS, G-code, CSV/JSON).
  std::optional<Vec3> partPoint;
  Vec3 tcpXyz = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());  ///< G-code X Y Z as read
};

/// A program as its reader saw it: the moves in execution order, the welds as [first, last]
/// move indices (the move onto the path start, after which the arc goes on, to the move after
/// which it goes off) and the dwells as (index of the move after which it waits, seconds).
struct ReadProgram {
  std::vector<ProgramMove> moves;
  std::vector<std::pair<std::size_t, std::size_t>> welds;
  std::vector<std::pair<std::size_t, double>> dwells;
};

/// Records "arc on after the last move" / "arc off after the last move".
class WeldTracker {
 public:
  void on(const ReadProgram& program, const std::string& line) {
    EXPECT_FALSE(open_) << "arc on twice without arc off: " << line;
    EXPECT_FALSE(program.moves.empty()) << "arc on before any move: " << line;
    open_ = true;
    first_ = program.moves.empty() ? 0 : program.moves.size() - 1;
  }
  void off(ReadProgram& program, const std::string& line) {
    EXPECT_TRUE(open_) << "arc off without arc on: " << line;
    if (open_ && !program.moves.empty())
      program.welds.emplace_back(first_, program.moves.size() - 1);
    open_ = false;
  }
  void finish() { EXPECT_FALSE(open_) << "the program ends with the arc on"; }
  bool isOpen() const { return open_; }

 private:
  bool open_ = false;
  std::size_t first_ = 0;
};

inline bool startsWith(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

/// Parses an integer that must fill `text`; failure through gtest.
inline int strictInt(const std::string& text, const std::string& line) {
  std::size_t used = 0;
  int value = 0;
  try {
    value = std::stoi(text, &used);
  } catch (...) {
    used = 0;
  }
  EXPECT_TRUE(used == text.size() && !text.empty())
      << "not an integer: '" << text << "' in " << line;
  return value;
}

inline double strictDouble(const std::string& text, const std::string& line) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (...) {
    used = 0;
  }
  EXPECT_TRUE(used == text.size() && !text.empty()) << "not a number: '" << text << "' in " << line;
  return value;
}

/// Records a wait of `seconds` (the text of the number) after the last move.
inline void recordDwell(ReadProgram& program, const std::string& seconds, const std::string& line) {
  EXPECT_FALSE(program.moves.empty()) << "a wait before any move: " << line;
  program.dwells.emplace_back(program.moves.empty() ? 0 : program.moves.size() - 1,
                              strictDouble(seconds, line));
}

// ---- JBI (Yaskawa INFORM) ---------------------------------------------------------------------

/// RCONF l,m,n,o,p,q,…: flip, elbow down, back, R (J4) ≥ 180°, T (J6) ≥ 180°, S (J1) ≥ 180°.
inline StatedConfiguration decodeRconf(const std::vector<int>& f, const std::string& line) {
  StatedConfiguration s;
  EXPECT_TRUE(f.size() == 8 || f.size() == 24) << "RCONF fields: " << f.size() << " in " << line;
  if (f.size() < 6) return s;
  for (std::size_t k = 0; k < f.size(); ++k) {
    EXPECT_TRUE(f[k] == 0 || f[k] == 1) << "RCONF field " << k << " in " << line;
    if (k > 0) s.text += ',';
    s.text += std::to_string(f[k]);
  }
  s.branchMask = 7;
  s.branch = (f[0] ? 4 : 0) | (f[1] ? 2 : 0) | (f[2] ? 1 : 0);
  s.beyond180[3] = f[3] == 1;
  s.beyond180[5] = f[4] == 1;
  s.beyond180[0] = f[5] == 1;
  return s;
}

/// The part-frame point of C<c> + EC<ec> through the cell's kinematics: BASE positions are the TCP
/// in Yaskawa's robot coordinates (x y z mm, Rx Ry Rz deg; origin on the S axis at the height of
/// the L axis, controllerRobotFrame), PULSE positions joint pulses (÷ pulses per
/// degree, forward kinematics); EC pulses are the positioner's tilt and rotation.
inline std::optional<Vec3> jbiPartPoint(const Cell& cell, const JbiJob& job, int c, int ec) {
  const auto ic = job.c.find(c);
  const auto iec = job.ec.find(ec);
  EXPECT_TRUE(ic != job.c.end() && ic->second.size() == 6) << "C" << c << " not declared";
  EXPECT_TRUE(iec != job.ec.end() && iec->second.size() == 2) << "EC" << ec << " not declared";
  if (ic == job.c.end() || iec == job.ec.end() || ic->second.size() != 6 ||
      iec->second.size() != 2) {
    return std::nullopt;
  }
  const std::vector<double>& v = ic->second;
  const double a1 = tiltFromPulses(cell, iec->second[0]);
  const double a2 = rotationFromPulses(cell, iec->second[1]);
  if (job.cPosType == "BASE") {
    return partPointFromControllerFrame(cell, poseFromXyzRpy(v[0], v[1], v[2], v[3], v[4], v[5]),
                                        a1, a2);
  }
  std::vector<double> degrees;
  for (int j = 0; j < 6; ++j) degrees.push_back(v[j] / cell.robot.pulsesPerDegree.at(j));
  return partPointFromJointDegrees(cell, degrees, a1, a2);
}

/// Every job of a JBI export in execution order.
inline ReadProgram readJbiProgram(const ExportResult& result, const Cell& cell) {
  std::map<std::string, JbiJob> jobs;
  for (const ExportFile& f : result.files) {
    JbiJob job = parseJbi(f.text);
    jobs[job.name] = std::move(job);
  }
  const JbiJob& main = jobs[parseJbi(result.files.front().text).name];
  std::vector<std::string> order;
  for (const std::string& line : main.instructions) {
    if (startsWith(line, "CALL JOB:")) order.push_back(line.substr(9));
  }
  if (order.empty()) order.push_back(main.name);
  ReadProgram program;
  WeldTracker welds;
  for (const std::string& name : order) {
    EXPECT_TRUE(jobs.count(name)) << "called job missing: " << name;
    const JbiJob& job = jobs[name];
    for (const std::string& line : job.instructions) {
      if (line == "NOP" || line == "END") continue;
      if (startsWith(line, "TIMER T=")) {
        recordDwell(program, line.substr(8), line);
        continue;
      }
      if (startsWith(line, "ARCON")) {
        welds.on(program, line);
        continue;
      }
      if (startsWith(line, "WAIT IN#(")) {  // the arc-established input, right after ARCON
        int input = 0;
        EXPECT_EQ(std::sscanf(line.c_str(), "WAIT IN#(%d)=ON", &input), 1) << line;
        EXPECT_EQ(line, "WAIT IN#(" + std::to_string(input) + ")=ON") << line;
        EXPECT_TRUE(cell.controller.jbi && cell.controller.jbi->arcWaitInput == input) << line;
        EXPECT_TRUE(welds.isOpen()) << "an arc wait without ARCON: " << line;
        continue;
      }
      if (startsWith(line, "ARCOF")) {
        welds.off(program, line);
        continue;
      }
      ProgramMove move;
      move.line = line;
      char type[8] = {0}, second[16] = {0};
      unsigned c = 0, ec = 0;
      if (std::sscanf(line.c_str(), "MOVJ C%5u VJ=%*f +MOVJ EC%5u VJ=%*f", &c, &ec) == 2) {
        move.joint = true;
      } else if (std::sscanf(line.c_str(), "%7s C%5u V=%15s +MOVJ EC%5u", type, &c, second, &ec) ==
                     4 &&
                 (std::string(type) == "SMOVL" || std::string(type) == "MOVL")) {
        double v = strictDouble(second, line);
        if (cell.process.speedUnit == SpeedUnit::CentimetresPerMinute) v /= 6.0;
        if (cell.process.speedUnit == SpeedUnit::MillimetresPerMinute) v /= 60.0;
        move.speed = v;
      } else {
        ADD_FAILURE() << "unknown JBI instruction in " << name << ": " << line;
        continue;
      }
      EXPECT_EQ(c, ec) << line;
      if (job.cPosType == "BASE") {
        const auto it = job.rconfBefore.find(static_cast<int>(c));
        EXPECT_TRUE(it != job.rconfBefore.end() && !it->second.empty()) << "no RCONF for " << line;
        if (it != job.rconfBefore.end()) move.configuration = decodeRconf(it->second, line);
      } else {
        move.jointTarget = true;  // pulses
      }
      move.partPoint = jbiPartPoint(cell, job, static_cast<int>(c), static_cast<int>(ec));
      program.moves.push_back(std::move(move));
    }
  }
  welds.finish();
  return program;
}

// ---- KRL (KUKA) -------------------------------------------------------------------------------

/// The "KEY value" fields of an aggregate {…} in order.
inline std::vector<std::pair<std::string, std::string>> aggregateFields(const std::string& line) {
  std::vector<std::pair<std::string, std::string>> fields;
  const std::size_t open = line.find('{'), close = line.find('}');
  EXPECT_TRUE(open != std::string::npos && close != std::string::npos && open < close) << line;
  if (open == std::string::npos || close == std::string::npos) return fields;
  std::string item;
  const std::string inner = line.substr(open + 1, close - open - 1) + ",";
  for (char ch : inner) {
    if (ch != ',') {
      item += ch;
      continue;
    }
    const std::size_t space = item.find(' ');
    EXPECT_NE(space, std::string::npos) << "aggregate field without value: " << item;
    if (space != std::string::npos)
      fields.emplace_back(item.substr(0, space), item.substr(space + 1));
    item.clear();
  }
  return fields;
}

/// KUKA's S and T: S bit 0 = overhead area (wrist centre at negative x of the A1 frame: the
/// "back" branch), bit 1 = A3 ≥ φ, the angle at which the arm is stretched (elbow up; 0 = elbow
/// down), bit 2 = A5 < 0; T bit k = joint k+1 < 0.
inline StatedConfiguration decodeStatusTurn(int s, int t, const std::string& line) {
  EXPECT_TRUE(s >= 0 && s < 8 && t >= 0 && t < 64) << line;
  StatedConfiguration c;
  c.text = "S " + std::to_string(s) + ",T " + std::to_string(t);
  c.branchMask = 3;
  c.branch = (s & 1) | ((s & 2) ? 0 : 2);
  c.negative[4] = (s & 4) != 0;
  for (int j = 0; j < 6; ++j) {
    const bool bit = (t >> j & 1) != 0;
    if (j == 4) {
      EXPECT_EQ(bit, (s & 4) != 0) << "S bit 2 and T bit 4 disagree: " << line;
    }
    c.negative[j] = bit;
  }
  return c;
}

// ---- RAPID (ABB) ------------------------------------------------------------------------------

/// The leaves of a nested [..] literal starting at `text[at]`, grouped by innermost bracket;
/// `at` is left after the closing bracket.
inline std::vector<std::vector<std::string>> bracketGroups(const std::string& text,
                                                           std::size_t& at) {
  std::vector<std::vector<std::string>> groups;
  EXPECT_EQ(text[at], '[') << text;
  int depth = 0;
  std::string item;
  std::vector<std::string> group;
  for (; at < text.size(); ++at) {
    const char ch = text[at];
    if (ch == '[') {
      ++depth;
      group.clear();
      item.clear();
    } else if (ch == ']' || ch == ',') {
      if (!item.empty()) group.push_back(item);
      item.clear();
      if (ch == ']') {
        if (!group.empty()) groups.push_back(group);
        group.clear();
        if (--depth == 0) {
          ++at;
          return groups;
        }
      }
    } else if (ch != ' ') {
      item += ch;
    }
  }
  ADD_FAILURE() << "unclosed bracket: " << text;
  return groups;
}

// ---- LS (Fanuc) -------------------------------------------------------------------------------

/// CONFIG : 'F|N U|D T|B, t1, t4, t6'.
inline StatedConfiguration decodeFanucConfig(const std::string& config, const std::string& line) {
  StatedConfiguration c;
  c.text = config;
  char flip = 0, up = 0, top = 0;
  int t1 = 0, t4 = 0, t6 = 0;
  const int n =
      std::sscanf(config.c_str(), "%c %c %c, %d, %d, %d", &flip, &up, &top, &t1, &t4, &t6);
  EXPECT_EQ(n, 6) << "CONFIG: " << line;
  EXPECT_TRUE((flip == 'F' || flip == 'N') && (up == 'U' || up == 'D') &&
              (top == 'T' || top == 'B'))
      << line;
  c.branchMask = 7;
  c.branch = (flip == 'F' ? 4 : 0) | (up == 'D' ? 2 : 0) | (top == 'B' ? 1 : 0);
  c.turn[0] = t1;
  c.turn[3] = t4;
  c.turn[5] = t6;
  return c;
}

// ---- LS (Fanuc) -------------------------------------------------------------------------------

/// One P[k] of /POS: GP1 Cartesian (X Y Z W P R, CONFIG) or joints (J1..J6), GP2 J1 J2, frames.
struct LsPosition {
  bool joint = false;
  std::map<std::string, double> gp1;  ///< X, Y, Z, W, P, R or J1..J6
  std::string config;                 ///< the CONFIG text, empty for joints
  int uf = -1, ut = -1;
  std::map<std::string, double> gp2;  ///< J1, J2
};

/// One .LS file as read: name, /ATTR fields, the ArcTool equipment of /APPL (0: no /APPL), the
/// /MN bodies (after "n:  ") and the /POS registers.
struct LsFile {
  std::string name;
  std::map<std::string, std::string> attr;
  int equipment = 0;
  std::vector<std::string> mn;
  std::map<unsigned, LsPosition> positions;
};

/// "\tKEY = value unit" items of a /POS line: each must be "<KEY> = <number> <unit>".
inline void readLsValues(const std::string& line, const char* unit,
                         std::map<std::string, double>& out) {
  for (std::string item : splitFields(line, ',')) {
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    EXPECT_NE(eq, std::string::npos) << "no '=' in " << line;
    if (eq == std::string::npos) continue;
    const std::string key = item.substr(0, eq), rest = item.substr(eq + 1);
    EXPECT_TRUE(rest.size() > std::string(unit).size() &&
                rest.compare(rest.size() - std::string(unit).size(), std::string::npos, unit) == 0)
        << "unit " << unit << " expected: " << line;
    const double v = strictDouble(rest.substr(0, rest.size() - std::string(unit).size()), line);
    EXPECT_TRUE(std::isfinite(v)) << line;
    EXPECT_EQ(out.count(key), 0u) << "twice: " << key << " in " << line;
    out[key] = v;
  }
}

/// "\tUF : u, UT : t," (optionally followed by "\t\tCONFIG : '…',").
inline void readLsFrames(const std::string& line, LsPosition& p) {
  char rest[128] = {0};
  const int n = std::sscanf(line.c_str(), "\tUF : %d, UT : %d,%127[^\n]", &p.uf, &p.ut, rest);
  EXPECT_GE(n, 2) << "frames: " << line;
  const std::string tail = rest;
  if (tail.empty()) return;
  EXPECT_TRUE(startsWith(tail, "\t\tCONFIG : '") && tail.size() > 14 &&
              tail.compare(tail.size() - 2, 2, "',") == 0)
      << line;
  if (tail.size() > 14) p.config = tail.substr(12, tail.size() - 14);
}

/// The /ATTR keys a TP program has, in order (TCD is a block of its own).
inline const std::vector<std::string>& lsAttrKeys() {
  static const std::vector<std::string> keys{
      "OWNER",      "COMMENT",     "PROG_SIZE", "CREATE", "MODIFIED",      "FILE_NAME",   "VERSION",
      "LINE_COUNT", "MEMORY_SIZE", "PROTECT",   "TCD",    "DEFAULT_GROUP", "CONTROL_CODE"};
  return keys;
}

/// Reads one .LS file strictly: sections in order, every /ATTR key once, LINE_COUNT = the /MN
/// lines, /MN numbered 1, 2, …, every P[k] of /POS complete, the file ends with /END.
inline LsFile parseLsFile(const ExportFile& file, bool crlf) {
  LsFile ls;
  bool endingsOk = false;
  const auto lines = splitLines(file.text, crlf, &endingsOk);
  EXPECT_TRUE(endingsOk) << file.name << ": line endings";
  enum { kProg, kAttr, kTcd, kAppl, kMn, kPos, kEnd } section = kProg;
  std::vector<std::string> keys;
  unsigned current = 0;
  int group = 0, rows = 0;
  for (const std::string& line : lines) {
    if (section == kProg) {
      EXPECT_TRUE(startsWith(line, "/PROG  ")) << file.name << ": " << line;
      ls.name = line.size() > 7 ? line.substr(7) : "";
      section = kAttr;
      continue;
    }
    if (line == "/ATTR" && keys.empty() && section == kAttr) continue;
    if (line == "/APPL" && section == kAttr) {
      section = kAppl;
      continue;
    }
    if (line == "/MN" && (section == kAttr || section == kAppl)) {
      section = kMn;
      continue;
    }
    if (line == "/POS" && section == kMn) {
      section = kPos;
      continue;
    }
    if (line == "/END" && section == kPos) {
      section = kEnd;
      continue;
    }
    switch (section) {
      case kAttr: {
        if (startsWith(line, "TCD:")) {
          keys.push_back("TCD");
          section = kTcd;
          break;
        }
        const std::size_t eq = line.find('=');
        EXPECT_TRUE(eq != std::string::npos && !line.empty() && line.back() == ';')
            << file.name << ": /ATTR line " << line;
        if (eq == std::string::npos) break;
        std::string key = line.substr(0, eq);
        key.erase(key.find_last_not_of(" \t") + 1);
        const std::size_t v = line.find_first_not_of(' ', eq + 1);
        ls.attr[key] = line.substr(v, line.size() - 1 - v);
        keys.push_back(key);
        break;
      }
      case kTcd:
        EXPECT_TRUE(startsWith(line, "      ")) << file.name << ": TCD line " << line;
        if (!line.empty() && line.back() == ';') section = kAttr;
        break;
      case kAppl: {
        int n = 0;
        EXPECT_EQ(std::sscanf(line.c_str(), "  ARC Welding Equipment : %d,*,*,*,*;", &n), 1)
            << file.name << ": /APPL line " << line;
        EXPECT_EQ(ls.equipment, 0) << file.name << ": two ARC sections";
        ls.equipment = n;
        break;
      }
      case kMn: {
        unsigned number = 0;
        int used = 0;
        if (std::sscanf(line.c_str(), "%u:  %n", &number, &used) != 1 || used == 0) {
          ADD_FAILURE() << file.name << ": unnumbered /MN line: " << line;
          break;
        }
        EXPECT_EQ(number, ls.mn.size() + 1) << file.name << ": " << line;
        ls.mn.push_back(line.substr(static_cast<std::size_t>(used)));
        break;
      }
      case kPos: {
        unsigned k = 0;
        if (std::sscanf(line.c_str(), "P[%u]{", &k) == 1 &&
            line == "P[" + std::to_string(k) + "]{") {
          EXPECT_EQ(ls.positions.count(k), 0u) << file.name << ": P[" << k << "] declared twice";
          current = k;
          ls.positions[k];
          group = 0;
          continue;
        }
        EXPECT_NE(current, 0u) << file.name << ": /POS line outside P[k]: " << line;
        LsPosition& p = ls.positions[current];
        if (line == "   GP1:" || line == "   GP2:") {
          group = line == "   GP1:" ? 1 : 2;
          rows = 0;
        } else if (line == "};") {
          EXPECT_EQ(p.gp2.size(), 2u) << file.name << ": P[" << current << "] GP2";
          EXPECT_EQ(p.gp1.size(), 6u) << file.name << ": P[" << current << "] GP1";
          current = 0;
        } else if (group != 0 && rows++ == 0) {
          if (group == 1) {
            readLsFrames(line, p);
          } else {
            LsPosition frames;
            readLsFrames(line, frames);
            EXPECT_TRUE(frames.uf == p.uf && frames.ut == p.ut && frames.config.empty()) << line;
          }
        } else if (group == 1) {
          const bool joint = startsWith(line, "\tJ");
          if (rows == 2) p.joint = joint;
          EXPECT_EQ(p.joint, joint) << file.name << ": mixed GP1 " << line;
          EXPECT_EQ(p.joint, p.config.empty()) << file.name << ": CONFIG for Cartesian only";
          readLsValues(line, joint ? "deg" : (startsWith(line, "\tX") ? "mm" : "deg"), p.gp1);
        } else if (group == 2) {
          readLsValues(line, "deg", p.gp2);
        } else {
          ADD_FAILURE() << file.name << ": unknown /POS line " << line;
        }
        break;
      }
      default:
        ADD_FAILURE() << file.name << ": line after /END or out of order: " << line;
    }
  }
  EXPECT_EQ(section, kEnd) << file.name << ": no /END";
  EXPECT_EQ(keys, lsAttrKeys()) << file.name << ": /ATTR keys";
  EXPECT_EQ(ls.attr["LINE_COUNT"], std::to_string(ls.mn.size())) << file.name;
  EXPECT_EQ(file.name, ls.name + ".LS") << "file and program name disagree";
  EXPECT_TRUE(!ls.name.empty() && ls.name.size() <= 36 &&
              std::isupper(static_cast<unsigned char>(ls.name[0])))
      << "program name " << ls.name;
  for (char ch : ls.name) {
    EXPECT_TRUE(std::isupper(static_cast<unsigned char>(ch)) ||
                std::isdigit(static_cast<unsigned char>(ch)) || ch == '_')
        << "program name " << ls.name;
  }
  return ls;
}

/// The part-frame point a /POS register states, through the cell's kinematics: GP1 joints by
/// the robot's forward kinematics, GP1 Cartesian in the table frame (UF = the cell's user frame,
/// coordinated) or Fanuc's world frame (UF 0: the controller's robot frame on J1's axis at the
/// height of J2, controllerRobotFrame), GP2 J1 J2 as the positioner's tilt and rotation.
inline Vec3 lsPartPoint(const Cell& cell, const LsPosition& p) {
  const double a1 = cell.positioner.tilt.sign * p.gp2.at("J1") * kDegT;
  const double a2 = cell.positioner.rotation.sign * p.gp2.at("J2") * kDegT;
  if (p.joint) {
    std::vector<double> q;
    for (const char* k : {"J1", "J2", "J3", "J4", "J5", "J6"}) q.push_back(p.gp1.at(k));
    return partPointFromJointDegrees(cell, q, a1, a2);
  }
  const Pose tcp = poseFromXyzRpy(p.gp1.at("X"), p.gp1.at("Y"), p.gp1.at("Z"), p.gp1.at("W"),
                                  p.gp1.at("P"), p.gp1.at("R"));
  if (p.uf == 0) return partPointFromControllerFrame(cell, tcp, a1, a2);
  EXPECT_EQ(p.uf, cell.exportOptions.userFrame) << "user frame";
  return partPointFromTable(cell, tcp, a1, a2);
}

/// Reads one program's /MN lines into `program` (moves, welds, dwells, part points).
inline void readLsBody(const LsFile& ls, const Cell& cell, ReadProgram& program,
                       WeldTracker& welds) {
  std::map<unsigned, int> used;
  const bool moves = !ls.positions.empty();
  EXPECT_EQ(ls.attr.at("DEFAULT_GROUP"), moves ? "1,1,*,*,*" : "*,*,*,*,*") << ls.name;
  if (moves && cell.controller.ls) {
    EXPECT_EQ(ls.equipment, cell.controller.ls->weldEquipment) << ls.name << ": /APPL";
  }
  for (const std::string& body : ls.mn) {
    const std::string line = ls.name + ": " + body;
    unsigned p = 0, percent = 0;
    char unit[16] = {0}, term[32] = {0};
    double v = 0.0;
    int n = 0;
    ProgramMove move;
    move.line = line;
    if (std::sscanf(body.c_str(), "J P[%u] %u%% FINE ;", &p, &percent) == 2) {
      move.joint = true;
      EXPECT_TRUE(percent >= 1 && percent <= 100) << line;
    } else if (std::sscanf(body.c_str(), "L P[%u] %lf%15s %31[^;];", &p, &v, unit, term) == 4) {
      const std::string u = unit, t = term;
      EXPECT_TRUE(u == "mm/sec" || u == "cm/min") << line;
      const std::string coord = cell.exportOptions.coordinated ? " COORD " : " ";
      EXPECT_TRUE(t == "FINE" + coord || t == "CNT100" + coord) << line;
      EXPECT_TRUE(v >= 1.0 && v == std::floor(v)) << line;
      move.speed = u == "cm/min" ? v / 6.0 : v;
    } else if (std::sscanf(body.c_str(), "Arc Start[%d] ;", &n) == 1) {
      EXPECT_TRUE(n >= 1 && n <= 99) << line;
      if (!welds.isOpen()) welds.on(program, line);  // else a schedule change within the weld
      continue;
    } else if (std::sscanf(body.c_str(), "Arc End[%d] ;", &n) == 1) {
      EXPECT_TRUE(n >= 1 && n <= 99) << line;
      welds.off(program, line);
      continue;
    } else if (startsWith(body, "WAIT ") && body.size() > 12 &&
               body.compare(body.size() - 7, 7, "(sec) ;") == 0) {
      recordDwell(program, body.substr(5, body.size() - 12), line);
      continue;
    } else {
      ADD_FAILURE() << "unknown /MN line: " << line;
      continue;
    }
    EXPECT_EQ(body,
              (move.joint ? "J P[" : "L P[") + std::to_string(p) + body.substr(body.find(']')))
        << "register number form: " << line;
    ++used[p];
    const auto it = ls.positions.find(p);
    EXPECT_TRUE(it != ls.positions.end()) << "P[" << p << "] used but not declared: " << line;
    if (it != ls.positions.end()) {
      const LsPosition& pos = it->second;
      EXPECT_EQ(pos.ut, cell.tool.number) << line;
      move.jointTarget = pos.joint;
      if (!pos.joint) move.configuration = decodeFanucConfig(pos.config, line);
      move.partPoint = lsPartPoint(cell, pos);
    }
    program.moves.push_back(std::move(move));
  }
  for (const auto& [k, pos] : ls.positions) {
    EXPECT_EQ(used[k], 1) << ls.name << ": P[" << k << "] declared, used " << used[k] << " times";
  }
}

/// Every program of an LS export in execution order (the main program's CALLs, or the only
/// program): names agree with files, every program is called once, /MN lines within
/// `maxLines` (0: not checked), every P[k] declared once and used once.
inline ReadProgram readLsProgram(const ExportResult& result, const Cell& cell,
                                 std::size_t maxLines = 0) {
  const bool crlf = cell.exportOptions.lineEnding == LineEnding::Crlf;
  std::map<std::string, LsFile> files;
  std::vector<std::string> fileOrder;
  for (const ExportFile& f : result.files) {
    LsFile ls = parseLsFile(f, crlf);
    EXPECT_EQ(files.count(ls.name), 0u) << "two programs named " << ls.name;
    if (maxLines > 0) {
      EXPECT_LE(ls.mn.size(), maxLines) << ls.name << ": /MN lines over the limit";
    }
    fileOrder.push_back(ls.name);
    files[ls.name] = std::move(ls);
  }
  ReadProgram program;
  WeldTracker welds;
  if (fileOrder.empty()) return program;
  const LsFile& main = files[fileOrder.front()];
  std::vector<std::string> order;
  if (main.positions.empty()) {
    for (const std::string& body : main.mn) {
      EXPECT_TRUE(startsWith(body, "CALL ") && body.size() > 7 &&
                  body.compare(body.size() - 2, 2, " ;") == 0)
          << main.name << ": a main program only calls: " << body;
      if (body.size() > 7) order.push_back(body.substr(5, body.size() - 7));
    }
  } else {
    order.push_back(main.name);
  }
  EXPECT_EQ(order.size() + (main.positions.empty() ? 1 : 0), files.size())
      << "every program is called once";
  for (const std::string& name : order) {
    EXPECT_TRUE(files.count(name)) << "called program missing: " << name;
    if (files.count(name)) readLsBody(files[name], cell, program, welds);
  }
  welds.finish();
  for (const ProgramMove& m : program.moves) {
    EXPECT_TRUE(m.configuration.has_value() != m.jointTarget) << "P of " << m.line;
  }
  return program;
}

// ---- G-code (tilt-rotate table) ---------------------------------------------------------------

/// The words of a G-code line "G1 X1 Y2 …" as (letter, number text), strictly one space apart.
inline std::vector<std::pair<char, std::string>> gcodeWords(const std::string& line) {
  std::vector<std::pair<char, std::string>> words;
  std::istringstream in(line);
  std::string word;
  while (in >> word) {
    EXPECT_TRUE(word.size() >= 2 && std::isupper(static_cast<unsigned char>(word[0])))
        << "word " << word << " in " << line;
    if (!word.empty()) words.emplace_back(word[0], word.substr(1));
  }
  return words;
}

/// A G-code export read back: header mode and dialect, the start and end codes they require,
/// every move (G0 first / home, G1 with F), M3 / M5 around welds, dwells in the dialect's unit
/// (generic: G4 P whole milliseconds; linuxcnc: G4 P seconds). Part points: X Y Z are the part
/// point (tcp) or the point in the positioner base frame, taken back through the table's
/// kinematics (machine); A, C the table angles with the cell's signs. Speeds: tcp F mm/min
/// (none for a move with unchanged X Y Z: F in deg/min); machine inverse time (G93): the
/// part-frame length of the move · F / 60.
/// The lines of a G-code sub-program file, checked and stripped of its frame: linuxcnc
/// `o<name> sub` … `o<name> endsub` `M2` in name.ngc; generic `O<n>` … `M99` in O<n>.ngc.
inline std::vector<std::string> gcodeSubProgram(const ExportResult& result, const std::string& name,
                                                bool linuxcnc, bool crlf,
                                                std::map<std::string, int>& calls) {
  ++calls[name];
  std::vector<std::string> body;
  for (std::size_t k = 1; k < result.files.size(); ++k) {
    if (result.files[k].name != name + ".ngc") continue;
    bool endings = false;
    body = splitLines(result.files[k].text, crlf, &endings);
    EXPECT_TRUE(endings) << name;
  }
  const std::vector<std::string> head{linuxcnc ? "o<" + name + "> sub" : name};
  const std::vector<std::string> tail =
      linuxcnc ? std::vector<std::string>{"o<" + name + "> endsub", "M2"}
               : std::vector<std::string>{"M99"};
  EXPECT_GE(body.size(), head.size() + tail.size()) << "called file missing or empty: " << name;
  if (body.size() < head.size() + tail.size()) return {};
  EXPECT_EQ(body.front(), head.front()) << name;
  for (std::size_t k = 0; k < tail.size(); ++k) {
    EXPECT_EQ(body[body.size() - tail.size() + k], tail[k]) << name;
  }
  return std::vector<std::string>(body.begin() + 1, body.end() - static_cast<long>(tail.size()));
}

inline ReadProgram readGcodeProgram(const ExportResult& result, const Cell& cell) {
  EXPECT_FALSE(result.files.empty());
  if (result.files.empty()) return {};
  const std::string& text = result.files.front().text;
  const bool crlf = cell.exportOptions.lineEnding == LineEnding::Crlf;
  bool endings = false;
  const auto lines = splitLines(text, crlf, &endings);
  EXPECT_TRUE(endings) << "line endings";
  std::string mode, dialect;
  std::vector<std::string> codes;  // the non-comment lines, calls expanded
  std::map<std::string, int> calls;
  for (const std::string& line : lines) {
    if (startsWith(line, "; mode: ")) mode = line.substr(8, line.find(' ', 8) - 8);
    if (startsWith(line, "; dialect: ")) dialect = line.substr(11);
    if (startsWith(line, ";")) continue;
    if (startsWith(line, "o<") && line.size() > 8 &&
        line.compare(line.size() - 6, 6, "> call") == 0) {
      EXPECT_EQ(dialect, "linuxcnc") << line;
      const auto sub = gcodeSubProgram(result, line.substr(2, line.size() - 8), true, crlf, calls);
      codes.insert(codes.end(), sub.begin(), sub.end());
    } else if (startsWith(line, "M98 P")) {
      EXPECT_EQ(dialect, "generic") << line;
      strictInt(line.substr(5), line);
      const auto sub = gcodeSubProgram(result, "O" + line.substr(5), false, crlf, calls);
      codes.insert(codes.end(), sub.begin(), sub.end());
    } else {
      codes.push_back(line);
    }
  }
  EXPECT_EQ(calls.size() + 1, result.files.size()) << "every sub-program file is called";
  for (const auto& [name, n] : calls) EXPECT_EQ(n, 1) << name << " called " << n << " times";
  EXPECT_TRUE(mode == "tcp" || mode == "machine") << "mode " << mode;
  EXPECT_TRUE(dialect == "generic" || dialect == "linuxcnc") << "dialect " << dialect;
  const bool machine = mode == "machine", linuxcnc = dialect == "linuxcnc";
  std::vector<std::string> head{machine ? "G21 G90 G93" : "G21 G90 G94"};
  std::vector<std::string> tail;
  if (!machine) {
    head.push_back(linuxcnc ? "M429" : "G43.4 H" + std::to_string(cell.tool.number));
    tail.push_back(linuxcnc ? "M428" : "G49");
  } else {
    tail.push_back("G94");
  }
  tail.push_back(linuxcnc ? "M2" : "M30");
  ReadProgram program;
  EXPECT_GE(codes.size(), head.size() + tail.size());
  if (codes.size() < head.size() + tail.size()) return program;
  for (std::size_t k = 0; k < head.size(); ++k) EXPECT_EQ(codes[k], head[k]);
  for (std::size_t k = 0; k < tail.size(); ++k) {
    EXPECT_EQ(codes[codes.size() - tail.size() + k], tail[k]);
  }
  WeldTracker welds;
  const PositionerDescription& pos = cell.positioner;
  for (std::size_t k = head.size(); k + tail.size() < codes.size(); ++k) {
    const std::string& line = codes[k];
    if (line == "M3") {
      welds.on(program, line);
      continue;
    }
    if (line == "M5") {
      welds.off(program, line);
      continue;
    }
    const auto words = gcodeWords(line);
    if (words.size() == 2 && words[0].first == 'G' && words[0].second == "4" &&
        words[1].first == 'P') {
      const double p = strictDouble(words[1].second, line);
      if (!linuxcnc) {
        EXPECT_EQ(words[1].second.find('.'), std::string::npos) << "P in whole ms: " << line;
      }
      recordDwell(program, std::to_string(linuxcnc ? p : p / 1000.0), line);
      continue;
    }
    const bool g0 = !words.empty() && words[0].first == 'G' && words[0].second == "0";
    const bool g1 = !words.empty() && words[0].first == 'G' && words[0].second == "1";
    const std::string letters = g0 ? "GXYZAC" : "GXYZACF";
    std::string got;
    for (const auto& w : words) got += w.first;
    if (!(g0 || g1) || got != letters) {
      ADD_FAILURE() << "unknown G-code line: " << line;
      continue;
    }
    double v[6];
    for (int i = 0; i < (g0 ? 5 : 6); ++i) {
      v[i] = strictDouble(words[static_cast<std::size_t>(i) + 1].second, line);
      EXPECT_TRUE(std::isfinite(v[i])) << line;
    }
    const double a1 = pos.tilt.sign * v[3] * kDegT, a2 = pos.rotation.sign * v[4] * kDegT;
    const Vec3 xyz(v[0], v[1], v[2]);
    ProgramMove move;
    move.line = line;
    move.joint = g0;
    move.partPoint = machine ? Vec3(computePartInPositionerBase(pos, a1, a2).inverse() * xyz) : xyz;
    move.tcpXyz = xyz;
    if (g1) {
      EXPECT_GT(v[5], 0.0) << line;
      const bool rotaryOnly = !program.moves.empty() && program.moves.back().tcpXyz == xyz;
      if (machine) {
        if (!program.moves.empty() && program.moves.back().partPoint) {
          const double length = (*move.partPoint - *program.moves.back().partPoint).norm();
          // X Y Z have 4 decimals: over 0.1 mm the length is known to 0.2 %
          if (length > 0.1) move.speed = length * v[5] / 60.0;
        }
      } else if (!rotaryOnly) {
        move.speed = v[5] / 60.0;  // mm/min (a rotary-only move's F is deg/min)
      }
    }
    program.moves.push_back(std::move(move));
  }
  welds.finish();
  return program;
}

// ---- CSV / JSON (neutral) -----------------------------------------------------------------------

/// The neutral file's rows read back: every row as many fields as columns, every number finite,
/// kind one of path | retract | travel | approach | home, welds from path_start / path_end, the
/// speed column, the torch angle against its travel and work shares, and as part point the TCP of
/// the row's robot joints (forward kinematics, controller degrees) in the part frame of its
/// positioner angles — so a round trip against the x/y/z columns checks the joints, not only the
/// copied position.
inline ReadProgram readNeutralProgram(
    const ExportResult& result, const Cell& cell,
    std::vector<std::map<std::string, double>>* rowsOut = nullptr) {
  EXPECT_EQ(result.files.size(), 1u);
  const std::string& text = result.files.front().text;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  if (result.format == ExportFormat::Json) {
    const auto doc = nlohmann::json::parse(text);
    EXPECT_EQ(doc.at("format"), "curvedslicer-motion");
    EXPECT_EQ(doc.at("version"), 4);
    for (const auto& c : doc.at("columns")) columns.push_back(c.get<std::string>());
    for (const auto& r : doc.at("points")) {
      std::vector<std::string> fields;
      for (const auto& f : r) fields.push_back(f.is_string() ? f.get<std::string>() : f.dump());
      rows.push_back(fields);
    }
  } else {
    bool endings = false;
    const auto lines = splitLines(text, false, &endings);
    EXPECT_TRUE(endings);
    if (lines.empty()) return {};
    columns = splitFields(lines[0], ',');
    for (std::size_t k = 1; k < lines.size(); ++k) rows.push_back(splitFields(lines[k], ','));
  }
  EXPECT_TRUE(!columns.empty() && columns.back() == "kind");
  ReadProgram program;
  WeldTracker welds;
  for (const auto& fields : rows) {
    EXPECT_EQ(fields.size(), columns.size());
    if (fields.size() != columns.size()) continue;
    std::map<std::string, double> row;
    const std::string line = fields.back() + " row " + std::to_string(program.moves.size());
    for (std::size_t k = 0; k + 1 < fields.size(); ++k) {
      row[columns[k]] = strictDouble(fields[k], line);
      EXPECT_TRUE(std::isfinite(row[columns[k]])) << columns[k] << " in " << line;
    }
    // the torch angle off gravity of a path point splits into its travel and work shares
    // (projections onto the planes along and across the travel): tan² travel + tan² work =
    // tan² torch
    const double torch = row.at("torch_angle_deg") * kDegT;
    EXPECT_TRUE(torch >= 0.0 && torch <= 45.0 * kDegT) << line;
    if (fields.back() == "path") {
      EXPECT_NEAR(std::hypot(std::tan(row.at("travel_angle_deg") * kDegT),
                             std::tan(row.at("work_angle_deg") * kDegT)),
                  std::tan(torch), 1e-9)
          << line;
    }
    EXPECT_GE(row.at("gravity_deviation_deg"), 0.0) << line;
    const std::string& kind = fields.back();
    EXPECT_TRUE(kind == "path" || kind == "retract" || kind == "travel" || kind == "approach" ||
                kind == "home")
        << line;
    ProgramMove move;
    move.line = line;
    move.joint = kind == "home" || program.moves.empty();
    move.speed = row.at("speed_mm_s");
    const double a1 = row.at("a1_deg") * kDegT, a2 = row.at("a2_deg") * kDegT;  // model angles
    move.partPoint =
        partPointFromJointDegrees(cell,
                                  {row.at("j1_deg"), row.at("j2_deg"), row.at("j3_deg"),
                                   row.at("j4_deg"), row.at("j5_deg"), row.at("j6_deg")},
                                  a1, a2);
    program.moves.push_back(std::move(move));
    if (row.at("path_start") == 1.0) welds.on(program, line);
    if (row.at("path_end") == 1.0) welds.off(program, line);
    if (rowsOut) rowsOut->push_back(std::move(row));
  }
  welds.finish();
  return program;
}

// ---- checks -----------------------------------------------------------------------------------

/// Every weld states one configuration from its first move (the path start) to its last.
inline void expectConstantWithinWelds(const ReadProgram& program, const std::string& format) {
  for (const auto& [first, last] : program.welds) {
    ASSERT_LT(last, program.moves.size());
    const auto& start = program.moves[first].configuration;
    ASSERT_TRUE(start.has_value())
        << format << ": no configuration at " << program.moves[first].line;
    for (std::size_t m = first; m <= last; ++m) {
      const auto& c = program.moves[m].configuration;
      ASSERT_TRUE(c.has_value()) << format << ": " << program.moves[m].line;
      EXPECT_EQ(c->text, start->text)
          << format << ": the configuration changes within the weld of moves " << first << ".."
          << last << " at " << program.moves[m].line;
    }
  }
}

/// `stated` says exactly what `expected` is, field by field (for the fields the format states).
inline void expectStates(const StatedConfiguration& stated, const RobotConfiguration& expected,
                         const std::string& where) {
  EXPECT_EQ(stated.branch & stated.branchMask, expected.branch & stated.branchMask) << where;
  for (int j = 0; j < 6; ++j) {
    const std::string joint = where + " J" + std::to_string(j + 1);
    if (stated.quadrant[j]) {
      EXPECT_EQ(*stated.quadrant[j], expected.quadrant[j]) << joint;
    }
    if (stated.turn[j]) {
      EXPECT_EQ(*stated.turn[j], expected.turn[j]) << joint;
    }
    if (stated.negative[j]) {
      EXPECT_EQ(*stated.negative[j], expected.negative[j]) << joint;
    }
    if (stated.beyond180[j]) {
      EXPECT_EQ(*stated.beyond180[j], expected.beyond180[j]) << joint;
    }
  }
}

/// Empty if `stated` is the configuration of `p`'s solution (IK branch exactly) up to joints
/// lying within `band` (rad) of a boundary: each stated field of joints 1, 4, 5 (sign) and 6 must
/// be the value of that field for some angle within ±band of the point's joint. Else what
/// differs.
inline std::string inconsistencyWithJoints(const StatedConfiguration& stated, const MotionPoint& p,
                                           double band) {
  if ((stated.branch & stated.branchMask) != (p.configuration & stated.branchMask)) {
    return "IK branch " + std::to_string(stated.branch) + " stated, the solution's is " +
           std::to_string(p.configuration);
  }
  for (int j = 0; j < 6; ++j) {
    const double deg = p.joints[j] / kDegT, bandDeg = band / kDegT;
    const double lo = deg - bandDeg, hi = deg + bandDeg;
    bool ok = true;
    if (stated.quadrant[j]) {
      ok = ok && *stated.quadrant[j] >= static_cast<int>(std::floor(lo / 90.0)) &&
           *stated.quadrant[j] <= static_cast<int>(std::floor(hi / 90.0));
    }
    if (stated.turn[j]) {
      ok = ok && *stated.turn[j] >= static_cast<int>(std::floor((lo + 180.0) / 360.0)) &&
           *stated.turn[j] <= static_cast<int>(std::floor((hi + 180.0) / 360.0));
    }
    // The signs of joints 2 and 3 (KUKA T bits 1, 2) follow from the pose and the branch; they
    // change along a weld as the arm reaches and are no configuration choice.
    if (stated.negative[j] && j != 1 && j != 2) {
      ok = ok && (*stated.negative[j] ? lo < 0.0 : hi >= 0.0);
    }
    if (stated.beyond180[j]) {
      ok = ok && (*stated.beyond180[j] ? std::abs(deg) + bandDeg >= 180.0
                                       : std::abs(deg) - bandDeg < 180.0);
    }
    if (!ok) {
      return "joint " + std::to_string(j + 1) + " at " + std::to_string(deg) +
             " deg does not have the stated configuration " + stated.text;
    }
  }
  return {};
}

}  // namespace curvedslicer::testing
