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
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/robot/configuration.hpp"
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

/// S (bit 0 back, bit 1 elbow down, bit 2 J5 < 0) and T (bit k: joint k+1 < 0).
inline StatedConfiguration decodeStatusTurn(int s, int t, const std::string& line) {
  EXPECT_TRUE(s >= 0 && s < 8 && t >= 0 && t < 64) << line;
  StatedConfiguration c;
  c.text = "S " + std::to_string(s) + ",T " + std::to_string(t);
  c.branchMask = 3;
  c.branch = s & 3;
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

inline ReadProgram readLsProgram(const std::string& text) {
  bool endings = false;
  const auto lines = splitLines(text, true, &endings);
  ReadProgram program;
  WeldTracker welds;
  enum { kHead, kMn, kPos } section = kHead;
  std::vector<std::size_t> moveOfPosition;  // P[k] -> move index (k - 1)
  std::size_t position = 0;                 // the P[k] being read
  bool inGp1 = false;
  for (const std::string& line : lines) {
    if (line == "/MN") {
      section = kMn;
      continue;
    }
    if (line == "/POS") {
      section = kPos;
      continue;
    }
    if (line == "/END") break;
    if (section == kHead) continue;
    if (section == kMn) {
      unsigned number = 0;
      int used = 0;
      if (std::sscanf(line.c_str(), "%u:  %n", &number, &used) != 1 || used == 0) {
        ADD_FAILURE() << "unnumbered /MN line: " << line;
        continue;
      }
      const std::string body = line.substr(static_cast<std::size_t>(used));
      unsigned p = 0, percent = 0;
      char unit[16] = {0}, term[16] = {0};
      double v = 0.0;
      ProgramMove move;
      move.line = line;
      if (std::sscanf(body.c_str(), "J P[%u] %u%% FINE ;", &p, &percent) == 2) {
        move.joint = true;
      } else if (std::sscanf(body.c_str(), "L P[%u] %lf %15s %15s", &p, &v, unit, term) == 4) {
        const std::string u = unit, t = term;
        EXPECT_TRUE(u == "mm/sec" || u == "cm/min") << line;
        EXPECT_TRUE(t == "FINE" || t == "CNT100") << line;
        move.speed = u == "cm/min" ? v / 6.0 : v;
      } else if (startsWith(body, "Arc Start[")) {
        welds.on(program, line);
        continue;
      } else if (startsWith(body, "Arc End[")) {
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
      EXPECT_EQ(p, program.moves.size() + 1) << "positions in order: " << line;
      program.moves.push_back(std::move(move));
      continue;
    }
    // /POS
    unsigned k = 0;
    if (std::sscanf(line.c_str(), "P[%u]{", &k) == 1) {
      position = k;
      EXPECT_TRUE(k >= 1 && k <= program.moves.size()) << line;
      continue;
    }
    if (line == "   GP1:") {
      inGp1 = true;
      continue;
    }
    if (line == "   GP2:" || line == "};") {
      inGp1 = false;
      continue;
    }
    if (!inGp1 || position < 1 || position > program.moves.size()) continue;
    ProgramMove& move = program.moves[position - 1];
    const std::size_t config = line.find("CONFIG : '");
    if (config != std::string::npos) {
      const std::size_t begin = config + 10, end = line.find('\'', begin);
      EXPECT_NE(end, std::string::npos) << line;
      move.configuration = decodeFanucConfig(line.substr(begin, end - begin), line);
    } else if (startsWith(line, "\tJ1 = ")) {
      move.jointTarget = true;
    }
  }
  welds.finish();
  for (const ProgramMove& m : program.moves) {
    EXPECT_TRUE(m.configuration.has_value() != m.jointTarget) << "P of " << m.line;
  }
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
