// Arc-off points in every format: the moves to the home pose are joint moves (MOVJ, PTP to an
// E6AXIS, MoveAbsJ, J in joint representation, G0), retract / travel / approach are linear moves
// at their (travel) speed with the arc off, every weld point a linear move at its weld speed (a
// reduced one written as reduced, never rounded up), and the neutral files name each point's kind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "export_test_support.hpp"
#include "program_readers.hpp"
#include "synthetic_motion.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

/// The noisy motion with one weld point of the second weld slowed to 6.667 mm/s (reduced).
MotionPlan makeMotionWithReducedSpeed() {
  MotionPlan motion = makeNoisyMotion();
  MotionPoint& p = motion.points[motion.paths[1].begin + 2];
  p.speed = 6.667;
  p.flags |= kMotionSpeedReduced;
  EXPECT_EQ(p.kind, MoveKind::Path);
  return motion;
}

/// Speed resolution of a format's linear moves in mm/s (default cell: mm/s).
double speedResolution(ExportFormat format) {
  switch (format) {
    case ExportFormat::Jbi:
      return 0.1;
    case ExportFormat::Krl:
      return 1e-5 * 1000.0;  // $VEL.CP in m/s, 5 decimals
    case ExportFormat::Rapid:
      return 0.01;
    default:
      return 1.0;  // LS: whole mm/sec
  }
}

/// True if move m is welded (the arc is on while moving to it).
bool welded(const ReadProgram& program, std::size_t m) {
  for (const auto& [first, last] : program.welds) {
    if (m > first && m <= last) return true;
  }
  return false;
}

TEST(ArcOffMoves, HomeIsAJointMoveAndTravelIsLinearInEveryRobotFormat) {
  const MotionPlan motion = makeMotionWithReducedSpeed();
  ASSERT_FALSE(motion.points.empty());
  const Cell cell = defaultCell();
  for (ExportFormat format : kRobotFormats) {
    const std::string name(toString(format));
    const ReadProgram program = exportAndRead(motion, cell, format);
    ASSERT_EQ(program.moves.size(), motion.points.size()) << name;
    ASSERT_EQ(program.welds.size(), motion.paths.size()) << name;
    const double resolution = speedResolution(format);
    for (std::size_t i = 0; i < motion.points.size(); ++i) {
      const MotionPoint& p = motion.points[i];
      const ProgramMove& m = program.moves[i];
      const std::string where = name + " point " + std::to_string(i) + ": " + m.line;
      EXPECT_EQ(welded(program, i), p.arcOn) << where;
      if (p.kind == MoveKind::Home) {
        EXPECT_TRUE(m.joint) << where;
        // JBI states positions as the cell's position type (base: Cartesian + RCONF).
        EXPECT_EQ(m.jointTarget, format != ExportFormat::Jbi) << where;
        continue;
      }
      EXPECT_FALSE(m.joint) << where;
      EXPECT_FALSE(m.jointTarget) << where;
      ASSERT_TRUE(std::isfinite(m.speed)) << where;
      if ((p.flags & kMotionSpeedReduced) != 0u) {
        EXPECT_LE(m.speed, p.speed) << "a reduced speed must not be rounded up: " << where;
        EXPECT_GT(m.speed, p.speed - resolution) << where;
      } else {
        EXPECT_NEAR(m.speed, p.speed, 0.5 * resolution + 1e-9) << where;
      }
      if (p.kind != MoveKind::Path) {
        EXPECT_EQ(m.speed, cell.process.travelSpeed) << where;
      }
    }
  }
}

TEST(ArcOffMoves, GcodeRapidsHomeAndFeedsTheRest) {
  const MotionPlan motion = makeMotionWithReducedSpeed();
  const Cell cell = defaultCell();
  const std::string text = exportProgram(motion, cell, ExportFormat::Gcode).files[0].text;
  bool lf = false;
  std::size_t move = 0;
  bool arc = false;
  for (const std::string& line : splitLines(text, true, &lf)) {
    if (line == "M3" || line == "M5") {
      EXPECT_NE(arc, line == "M3") << line;
      arc = line == "M3";
      continue;
    }
    if (!startsWith(line, "G0 ") && !startsWith(line, "G1 ")) continue;
    ASSERT_LT(move, motion.points.size());
    const MotionPoint& p = motion.points[move];
    EXPECT_EQ(startsWith(line, "G0 "), move == 0 || p.kind == MoveKind::Home) << line;
    EXPECT_EQ(arc, p.arcOn) << line;
    const std::size_t f = line.find(" F");
    if (startsWith(line, "G1 ")) {
      ASSERT_NE(f, std::string::npos) << line;
      const double feed = strictDouble(line.substr(f + 2), line);
      if ((p.flags & kMotionSpeedReduced) != 0u) {
        EXPECT_LE(feed, p.speed * 60.0) << line;
        EXPECT_GT(feed, p.speed * 60.0 - 0.1) << line;
      } else {
        EXPECT_NEAR(feed, p.speed * 60.0, 0.05) << line;
      }
    } else {
      EXPECT_EQ(f, std::string::npos) << line;
    }
    ++move;
  }
  EXPECT_EQ(move, motion.points.size());
  EXPECT_FALSE(arc);
}

/// The G-code waits (G4 P, P in `unit` seconds: 1 on LinuxCNC, 0.001 on generic / Fanuc-style
/// controllers) as (index of the G0/G1 move after which it waits, seconds).
std::vector<std::pair<std::size_t, double>> gcodeDwells(const std::string& text, double unit) {
  bool lf = false;
  std::vector<std::pair<std::size_t, double>> dwells;
  std::size_t moves = 0;
  for (const std::string& line : splitLines(text, true, &lf)) {
    if (startsWith(line, "G0 ") || startsWith(line, "G1 ")) ++moves;
    if (!startsWith(line, "G4 P")) continue;
    EXPECT_GT(moves, 0u) << "a wait before any move: " << line;
    dwells.emplace_back(moves == 0 ? 0 : moves - 1, unit * strictDouble(line.substr(4), line));
  }
  return dwells;
}

TEST(ArcOffMoves, DwellsWaitAfterTheRetractWithTheTorchOffThePartInEveryFormat) {
  Cell cell = defaultCell();
  cell.process.pathDwell = 2.0;
  ASSERT_GT(cell.process.layerDwell, 0.0);
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);  // 2 layers of 2 paths
  // Each path's dwell after the retract that follows its end; the layer dwell added after a
  // layer's last path (the next weld lies in the next layer, or none follows).
  std::vector<std::pair<std::size_t, double>> expected;
  for (std::size_t s = 0; s < motion.paths.size(); ++s) {
    const MotionPathSpan& span = motion.paths[s];
    ASSERT_LT(span.end, motion.points.size());
    ASSERT_EQ(motion.points[span.end].kind, MoveKind::Retract) << "path " << s;
    const bool lastOfLayer =
        s + 1 == motion.paths.size() || motion.paths[s + 1].layer != span.layer;
    expected.emplace_back(span.end,
                          cell.process.pathDwell + (lastOfLayer ? cell.process.layerDwell : 0.0));
  }
  ASSERT_EQ(expected.size(), 4u);
  const auto expectDwells = [&](const std::vector<std::pair<std::size_t, double>>& dwells,
                                const std::string& format) {
    ASSERT_EQ(dwells.size(), expected.size()) << format;
    for (std::size_t k = 0; k < expected.size(); ++k) {
      EXPECT_EQ(dwells[k].first, expected[k].first) << format << " dwell " << k;
      EXPECT_NEAR(dwells[k].second, expected[k].second, 1e-9) << format << " dwell " << k;
    }
  };
  for (ExportFormat format : kRobotFormats) {
    expectDwells(exportAndRead(motion, cell, format).dwells, std::string(toString(format)));
  }
  expectDwells(gcodeDwells(exportProgram(motion, cell, ExportFormat::Gcode).files[0].text, 0.001),
               "gcode generic");
  ExportOptions linuxcnc;
  linuxcnc.gcodeDialect = GcodeDialect::LinuxCnc;
  expectDwells(
      gcodeDwells(exportProgram(motion, cell, ExportFormat::Gcode, linuxcnc).files[0].text, 1.0),
      "gcode linuxcnc");
}

TEST(ArcOffMoves, ALayerShorterThanTheMinimumLayerTimeWaitsTheRestInEveryFormat) {
  Cell cell = defaultCell();
  cell.process.pathDwell = 0.0;
  cell.process.layerDwell = 0.0;
  cell.process.minLayerTime = 30.0;
  const Plan plan = makeSmallPlan();  // 2 layers of 2 short paths: seconds each
  const MotionPlan motion = planMotion(plan, cell);
  ASSERT_EQ(motion.paths.size(), 4u);
  ASSERT_EQ(motion.paths[1].layer, 0);
  ASSERT_EQ(motion.paths[2].layer, 1);
  // Layer 0 runs from the arrival at its first weld point to its last path end; it waits the
  // rest of the 30 s after that path's retract. Layer 1 is the last: nothing is welded onto it,
  // so it does not wait.
  const double layerTime =
      motion.points[motion.paths[1].end - 1].time - motion.points[motion.paths[0].begin].time;
  ASSERT_GT(layerTime, 0.0);
  ASSERT_LT(layerTime, 30.0);
  const double wait = 30.0 - layerTime;
  EXPECT_NEAR(motion.layers[0].coolingWait, wait, 1e-9);
  EXPECT_EQ(motion.layers[1].coolingWait, 0.0);
  EXPECT_EQ(motion.total.cooledLayers, 1u);
  EXPECT_NEAR(motion.total.coolingWait, wait, 1e-9);
  // the next layer's first weld is at least the minimum layer time after the first one's start
  EXPECT_GE(motion.points[motion.paths[2].begin].time - motion.points[motion.paths[0].begin].time,
            30.0);
  // the wait is in the total time: the same motion without it is that much shorter
  Cell off = cell;
  off.process.minLayerTime = 0.0;
  const MotionPlan plain = planMotion(plan, off);
  EXPECT_NEAR(motion.total.totalTime - plain.total.totalTime, wait, 1e-9);
  EXPECT_NEAR(motion.total.dwellTime - plain.total.dwellTime, wait, 1e-9);
  EXPECT_NEAR(motion.total.totalTime, motion.points.back().time, 1e-9);
  EXPECT_NE(std::find_if(motion.notes.begin(), motion.notes.end(),
                         [](const std::string& n) {
                           return n.find("minimum layer time 30.0 s: 1 layer(s)") !=
                                  std::string::npos;
                         }),
            motion.notes.end());
  // every language waits exactly there, and nowhere else; without the minimum, none waits
  const std::size_t at = motion.paths[1].end;  // the retract after layer 0's last path
  ASSERT_EQ(motion.points[at].kind, MoveKind::Retract);
  const auto expectOneWait = [&](const std::vector<std::pair<std::size_t, double>>& dwells,
                                 const std::string& format) {
    ASSERT_EQ(dwells.size(), 1u) << format;
    EXPECT_EQ(dwells[0].first, at) << format;
    EXPECT_NEAR(dwells[0].second, wait, 0.01) << format;  // programs give 0.01 s or finer
  };
  for (ExportFormat format : kRobotFormats) {
    const std::string name(toString(format));
    expectOneWait(exportAndRead(motion, cell, format).dwells, name);
    EXPECT_TRUE(exportAndRead(plain, off, format).dwells.empty()) << name;
  }
  expectOneWait(gcodeDwells(exportProgram(motion, cell, ExportFormat::Gcode).files[0].text, 0.001),
                "gcode generic");
  EXPECT_TRUE(
      gcodeDwells(exportProgram(plain, off, ExportFormat::Gcode).files[0].text, 0.001).empty());
  ExportOptions linuxcnc;
  linuxcnc.gcodeDialect = GcodeDialect::LinuxCnc;
  expectOneWait(
      gcodeDwells(exportProgram(motion, cell, ExportFormat::Gcode, linuxcnc).files[0].text, 1.0),
      "gcode linuxcnc");
}

TEST(ArcOffMoves, NeutralFilesNameEveryPointsKindAndTime) {
  const MotionPlan motion = makeMotionWithReducedSpeed();
  const Cell cell = defaultCell();
  bool lf = false;
  const auto lines =
      splitLines(exportProgram(motion, cell, ExportFormat::Csv).files[0].text, false, &lf);
  ASSERT_EQ(lines.size(), motion.points.size() + 1);
  const std::vector<std::string> header = splitFields(lines[0], ',');
  std::size_t kind = header.size(), time = header.size();
  for (std::size_t k = 0; k < header.size(); ++k) {
    if (header[k] == "kind") kind = k;
    if (header[k] == "time_s") time = k;
  }
  ASSERT_LT(kind, header.size());
  ASSERT_LT(time, header.size());
  const auto doc =
      nlohmann::json::parse(exportProgram(motion, cell, ExportFormat::Json).files[0].text);
  ASSERT_EQ(doc.at("points").size(), motion.points.size());
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const std::vector<std::string> row = splitFields(lines[i + 1], ',');
    ASSERT_EQ(row.size(), header.size());
    EXPECT_EQ(row[kind], toString(motion.points[i].kind));
    EXPECT_EQ(strictDouble(row[time], lines[i + 1]), motion.points[i].time);
    EXPECT_EQ(doc["points"][i][kind].get<std::string>(), toString(motion.points[i].kind));
    EXPECT_EQ(doc["points"][i][time].get<double>(), motion.points[i].time);
  }
}

TEST(ArcOffMoves, HomeJointSpeedKeepsThePlannedDuration) {
  const Cell cell = defaultCell();
  const MotionPlan motion = makeNoisyMotion();
  const MotionPoint& from = motion.points[motion.points.size() - 2];
  const MotionPoint& home = motion.points.back();
  ASSERT_EQ(home.kind, MoveKind::Home);
  // The slowest joint speed (percent of every axis's maximum) that still ends on time.
  const double duration = home.time - from.time;
  double fraction = 0.0;
  for (int j = 0; j < 6; ++j) {
    fraction = std::max(fraction, std::abs(home.joints[j] - from.joints[j]) / duration /
                                      cell.robot.joints[j].maxSpeed);
  }
  fraction = std::max(fraction,
                      std::abs(home.a1 - from.a1) / duration / cell.positioner.tilt.limit.maxSpeed);
  fraction = std::max(
      fraction, std::abs(home.a2 - from.a2) / duration / cell.positioner.rotation.limit.maxSpeed);
  ASSERT_GT(fraction, 0.01);
  ASSERT_LT(fraction, 1.0);
  char percent[32];
  std::snprintf(percent, sizeof percent, "%.2f", std::ceil(fraction * 1e4 - 1e-9) / 100.0);
  const std::string jbi = exportProgram(motion, cell, ExportFormat::Jbi).files[0].text;
  EXPECT_NE(jbi.find("MOVJ C00000 VJ=10.00 +MOVJ EC00000 VJ=10.00"), std::string::npos)
      << "the first move starts from an unknown pose: 10 %";
  const std::string last = "VJ=" + std::string(percent) + " +MOVJ EC";
  EXPECT_NE(jbi.find(last), std::string::npos) << last << " in\n" << jbi;
  const std::string krl = exportProgram(motion, cell, ExportFormat::Krl).files[0].text;
  EXPECT_NE(krl.find("$VEL_AXIS[5]=" + std::string(percent)), std::string::npos) << krl;
  const std::string ls = exportProgram(motion, cell, ExportFormat::Ls).files[0].text;
  const std::string j = "J P[" + std::to_string(motion.points.size()) + "] " +
                        std::to_string(static_cast<int>(std::round(std::stod(percent)))) +
                        "% FINE ;";
  EXPECT_NE(ls.find(j), std::string::npos) << j;
}

TEST(ArcOffMoves, AnArcOffPointBeyondAJointLimitIsNamedByItsKind) {
  const Cell cell = defaultCell();
  MotionPlan motion = makeNoisyMotion();
  motion.points.back().joints[4] = cell.robot.joints[4].max + 0.1;  // the final home pose
  for (ExportFormat format : {ExportFormat::Jbi, ExportFormat::Krl, ExportFormat::Rapid,
                              ExportFormat::Ls, ExportFormat::Gcode}) {
    try {
      exportProgram(motion, cell, format);
      ADD_FAILURE() << toString(format) << ": a home pose beyond joint 5's limit was exported";
    } catch (const InvalidInput& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("motion point " + std::to_string(motion.points.size() - 1) +
                             " (layer 0, path 1, home move) crosses the limit of robot joint 5"),
                std::string::npos)
          << message;
    }
  }
}

}  // namespace
}  // namespace curvedslicer
