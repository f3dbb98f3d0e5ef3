// Golden files: the exports of a small, hand-made motion plan (welds and the arc-off points a
// planned motion has: home, retract, travel, approach) compared byte for byte with
// tests/cpp/export/golden/*. The motion plan is written out by hand (not planned), so these files
// change only when a writer changes.
//
// To regenerate deliberately after an intended format change, run the test binary with
//   CURVEDSLICER_UPDATE_GOLDEN=1 build/tests/cpp/test_export --gtest_filter='Golden.*'
// and review the diff of tests/cpp/export/golden/ before committing it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "curvedslicer/export/exporter.hpp"
#include "export_test_support.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using namespace testing;

/// A hand-made point at `position` (part frame) with joints from `seed`; poses follow the
/// position (TCP 1100 mm in front of the robot, torch down, yaw `yaw`).
MotionPoint makeGoldenPoint(MoveKind kind, int layer, int path, int index, const Vec3& position,
                            double seed, double yaw) {
  MotionPoint p;
  p.kind = kind;
  p.layer = layer;
  p.path = path;
  p.index = index;
  p.position = position;
  p.normal = Vec3::UnitZ();
  p.deposition = p.usedDeposition = Vec3(0.1 * seed, 0.05 * path, -1.0).normalized();
  p.a1 = 0.05 * seed + 0.01 * layer;
  p.a2 = 0.3 * path - 0.1 * (seed + 1.0);
  for (int j = 0; j < 6; ++j) p.joints[j] = 0.1 * (j + 1) - 0.02 * (seed + 1.0) + 0.01 * layer;
  const Vec3 rpy(kPiT, 0.02 * (seed + 1.0), yaw);
  p.toolInRobotBase =
      makePose(Vec3(1100.0 + position.x(), position.y(), 530.0 + position.z()), rpy);
  p.toolInWorld = p.toolInRobotBase;
  p.toolInTable = makePose(position, rpy);
  p.toolInPart = p.toolInTable;
  return p;
}

/// The cell's home pose as a hand-made point (joints of a folded arm, positioner at zero).
MotionPoint makeGoldenHome(int layer, int path) {
  MotionPoint p = makeGoldenPoint(MoveKind::Home, layer, path, -1, Vec3(-20.0, -5.0, 200.0), 0, 0);
  p.joints = {0.0, 0.0, 0.0, 0.0, -1.5707963267948966, 0.0};
  p.a1 = 0.0;
  p.a2 = 0.0;
  return p;
}

/// 2 layers × 2 paths × 3 points with fixed, arbitrary but plausible numbers, and the arc-off
/// points a planned motion has: home at the start and end, a retract along the normal after
/// every path, a travel point at clearance height between layers, an approach above every path
/// start. Times are nominal (distance / speed, dwells, 1 s per home move); the second weld point
/// of layer 1, path 1 has a reduced weld speed (6.66 mm/s).
MotionPlan makeGoldenMotion(const Cell& cell) {
  constexpr double kClearance = 10.0;
  MotionPlan motion;
  const auto add = [&](MotionPoint p) {
    if (!motion.points.empty()) {
      const MotionPoint& q = motion.points.back();
      double dwell = q.pathEnd ? cell.process.pathDwell : 0.0;
      const double move =
          p.kind == MoveKind::Home ? 1.0 : (p.position - q.position).norm() / p.speed;
      p.time = q.time + dwell + move;
    }
    motion.points.push_back(p);
  };
  MotionPoint home = makeGoldenHome(0, 0);
  home.speed = cell.process.travelSpeed;
  add(home);
  for (int layer = 0; layer < 2; ++layer) {
    for (int path = 0; path < 2; ++path) {
      const double z = 1.5 * (layer + 1);
      const Vec3 start(-20.0, -5.0 + 10.0 * path, z);
      if (layer == 1 && path == 0) {
        MotionPoint travel = makeGoldenPoint(MoveKind::Travel, layer, path, -1,
                                             start + Vec3(0, 0, kClearance + 1.5), -1, 0.1 * path);
        travel.speed = cell.process.travelSpeed;
        add(travel);
      }
      MotionPoint approach = makeGoldenPoint(MoveKind::Approach, layer, path, -1,
                                             start + Vec3(0, 0, kClearance), -1, 0.1 * path);
      approach.speed = cell.process.travelSpeed;
      add(approach);
      MotionPathSpan span{layer, path, motion.points.size(), 0, {}};
      for (int i = 0; i < 3; ++i) {
        MotionPoint p = makeGoldenPoint(MoveKind::Path, layer, path, i,
                                        start + Vec3(10.0 * i, 0, 0), i - 1, 0.1 * path);
        p.configuration = path == 1 ? 4 : 0;
        p.pathStart = i == 0;
        p.pathEnd = i == 2;
        p.arcOn = i > 0;
        p.speed = i == 0 ? cell.process.travelSpeed : cell.process.weldSpeed;
        if (layer == 1 && path == 1 && i == 1) {
          p.speed = 6.66;
          p.flags |= kMotionSpeedReduced;
        }
        p.residual = 1e-12 * i;
        add(p);
      }
      span.end = motion.points.size();
      span.configuration = configurationOf(motion.points[span.begin].joints,
                                           motion.points[span.begin].configuration);
      motion.paths.push_back(span);
      MotionPoint retract = makeGoldenPoint(MoveKind::Retract, layer, path, -1,
                                            start + Vec3(20.0, 0, kClearance), 1, 0.1 * path);
      retract.speed = cell.process.travelSpeed;
      add(retract);
    }
  }
  home = makeGoldenHome(1, 1);
  home.speed = cell.process.travelSpeed;
  add(home);
  return motion;
}

void compareWithGolden(const std::string& fileName, const std::string& text) {
  const fs::path path = fs::path(CURVEDSLICER_SOURCE_DIR) / "tests/cpp/export/golden" / fileName;
  const char* update = std::getenv("CURVEDSLICER_UPDATE_GOLDEN");
  if (update != nullptr && std::string(update) == "1") {
    std::ofstream out(path, std::ios::binary);
    out << text;
    ASSERT_TRUE(out.good()) << "cannot write " << path;
    return;
  }
  ASSERT_TRUE(fs::exists(path)) << path << " is missing; see the file comment to create it";
  const std::string golden = readFile(path.string());
  EXPECT_EQ(text.size(), golden.size()) << fileName;
  EXPECT_TRUE(text == golden) << fileName
                              << " differs from the golden file; if the change is "
                                 "intended, regenerate (see golden_test.cpp)";
}

TEST(Golden, EveryFormatMatchesItsGoldenFile) {
  Cell cell = defaultCell();
  cell.process.pathDwell = 1.5;
  const MotionPlan motion = makeGoldenMotion(cell);
  for (ExportFormat f : {ExportFormat::Jbi, ExportFormat::Ls, ExportFormat::Gcode,
                         ExportFormat::Csv, ExportFormat::Json}) {
    const ExportResult r = exportProgram(motion, cell, f);
    ASSERT_EQ(r.files.size(), 1u);
    compareWithGolden("small_" + std::string(toString(f)) + std::string(fileExtension(f)),
                      r.files[0].text);
  }
  ExportOptions machine;
  machine.gcodeMode = GcodeMode::Machine;
  compareWithGolden("small_gcode_machine.ngc",
                    exportProgram(motion, cell, ExportFormat::Gcode, machine).files[0].text);
  ExportOptions linuxcnc;
  linuxcnc.gcodeDialect = GcodeDialect::LinuxCnc;
  compareWithGolden("small_gcode_linuxcnc.ngc",
                    exportProgram(motion, cell, ExportFormat::Gcode, linuxcnc).files[0].text);
  linuxcnc.gcodeMode = GcodeMode::Machine;
  compareWithGolden("small_gcode_linuxcnc_machine.ngc",
                    exportProgram(motion, cell, ExportFormat::Gcode, linuxcnc).files[0].text);
}

TEST(Golden, SplitLsMatchesItsGoldenFiles) {
  Cell cell = defaultCell();
  cell.controller.ls = LsControllerSettings{1, 3, 4, 20};
  const ExportResult r = exportProgram(makeGoldenMotion(cell), cell, ExportFormat::Ls);
  ASSERT_GT(r.files.size(), 2u);
  for (const ExportFile& f : r.files) compareWithGolden("split_" + f.name, f.text);
}

TEST(Golden, SplitGcodeMatchesItsGoldenFiles) {
  const Cell cell = defaultCell();
  for (GcodeDialect d : {GcodeDialect::Generic, GcodeDialect::LinuxCnc}) {
    ExportOptions o;
    o.gcodeDialect = d;
    o.gcodeMaxLinesPerFile = 20;
    const ExportResult r = exportProgram(makeGoldenMotion(cell), cell, ExportFormat::Gcode, o);
    ASSERT_GT(r.files.size(), 2u);
    for (const ExportFile& f : r.files) {
      compareWithGolden("split_" + std::string(toString(d)) + "_" + f.name, f.text);
    }
  }
}

TEST(Golden, JbiWithArcWaitMatchesItsGoldenFile) {
  Cell cell = defaultCell();
  cell.controller.jbi->arcWaitInput = 12;
  const ExportResult r = exportProgram(makeGoldenMotion(cell), cell, ExportFormat::Jbi);
  ASSERT_EQ(r.files.size(), 1u);
  compareWithGolden("small_jbi_arc_wait.JBI", r.files[0].text);
}

TEST(Golden, SplitJbiMatchesItsGoldenFiles) {
  Cell cell = defaultCell();
  cell.exportOptions.maxLinesPerJob = 12;
  cell.exportOptions.positionType = PositionType::Pulse;
  cell.robot.pulsesPerDegree = {1000.0, 1000.0, 1000.0, 800.0, 800.0, 500.0};
  const ExportResult r = exportProgram(makeGoldenMotion(cell), cell, ExportFormat::Jbi);
  ASSERT_GT(r.files.size(), 2u);
  for (const ExportFile& f : r.files) compareWithGolden("split_" + f.name, f.text);
}

/// KRL and RAPID (several files each): every file as golden_<format>_<file name>; the motion
/// with a per-point wire feed on layer 1 (as a bead model sets it), KRL with the wire feed on an
/// analog output; then split at a small line limit (split_<format>_<file name>).
TEST(Golden, KrlAndRapidMatchTheirGoldenFiles) {
  Cell cell = defaultCell();
  cell.process.pathDwell = 1.5;
  cell.controller.krl->wireFeedAnalogOutput = 2;
  cell.controller.krl->wireFeedFullScale = 20.0;
  MotionPlan motion = makeGoldenMotion(cell);
  for (MotionPoint& p : motion.points) {
    if (p.arcOn && p.layer == 1) p.wireFeed = 4.0 + 0.5 * p.index;
  }
  for (ExportFormat f : {ExportFormat::Krl, ExportFormat::Rapid}) {
    const ExportResult r = exportProgram(motion, cell, f);
    for (const ExportFile& file : r.files) {
      compareWithGolden("small_" + std::string(toString(f)) + "_" + file.name, file.text);
    }
  }
  cell.controller.krl->maxLinesPerFile = 30;
  cell.controller.rapid->maxLinesPerModule = 24;
  for (ExportFormat f : {ExportFormat::Krl, ExportFormat::Rapid}) {
    const ExportResult r = exportProgram(motion, cell, f);
    ASSERT_GT(r.files.size(), 2u);
    for (const ExportFile& file : r.files) {
      compareWithGolden("split_" + std::string(toString(f)) + "_" + file.name, file.text);
    }
  }
}

}  // namespace
}  // namespace curvedslicer
