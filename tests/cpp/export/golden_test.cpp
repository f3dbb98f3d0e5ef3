// Golden files: the exports of a small, hand-made motion plan compared byte for byte with
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

/// 2 layers × 2 paths × 3 points with fixed, arbitrary but plausible numbers.
MotionPlan makeGoldenMotion() {
  MotionPlan motion;
  for (int layer = 0; layer < 2; ++layer) {
    for (int path = 0; path < 2; ++path) {
      MotionPathSpan span{layer, path, motion.points.size(), 0};
      for (int i = 0; i < 3; ++i) {
        MotionPoint p;
        p.layer = layer;
        p.path = path;
        p.index = i;
        p.position = Vec3(-20.0 + 10.0 * i, -5.0 + 10.0 * path, 1.5 * (layer + 1));
        p.normal = Vec3::UnitZ();
        p.deposition = p.usedDeposition = Vec3(0.1 * (i - 1), 0.05 * path, -1.0).normalized();
        p.a1 = (0.05 * (i - 1) + 0.01 * layer);
        p.a2 = 0.3 * path - 0.1 * i;
        for (int j = 0; j < 6; ++j) p.joints[j] = 0.1 * (j + 1) - 0.02 * i + 0.01 * layer;
        p.configuration = path == 1 ? 4 : 0;
        const Vec3 rpy(kPiT, 0.02 * i, 0.1 * path);
        p.toolInRobotBase =
            makePose(Vec3(1100.0 + p.position.x(), p.position.y(), 530.0 + p.position.z()), rpy);
        p.toolInWorld = p.toolInRobotBase;
        p.toolInTable = makePose(p.position, rpy);
        p.toolInPart = p.toolInTable;
        p.pathStart = i == 0;
        p.pathEnd = i == 2;
        p.arcOn = i > 0;
        p.speed = i == 0 ? 50.0 : 8.0;
        p.residual = 1e-12 * i;
        motion.points.push_back(p);
      }
      span.end = motion.points.size();
      motion.paths.push_back(span);
    }
  }
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
  const MotionPlan motion = makeGoldenMotion();
  for (ExportFormat f :
       {ExportFormat::Jbi, ExportFormat::Krl, ExportFormat::Rapid, ExportFormat::Ls,
        ExportFormat::Gcode, ExportFormat::Csv, ExportFormat::Json}) {
    const ExportResult r = exportProgram(motion, cell, f);
    ASSERT_EQ(r.files.size(), 1u);
    compareWithGolden("small_" + std::string(toString(f)) + std::string(fileExtension(f)),
                      r.files[0].text);
  }
  ExportOptions machine;
  machine.gcodeMode = GcodeMode::Machine;
  compareWithGolden("small_gcode_machine.ngc",
                    exportProgram(motion, cell, ExportFormat::Gcode, machine).files[0].text);
}

TEST(Golden, SplitJbiMatchesItsGoldenFiles) {
  Cell cell = defaultCell();
  cell.exportOptions.maxLinesPerJob = 12;
  cell.exportOptions.positionType = PositionType::Pulse;
  cell.robot.pulsesPerDegree = {1000.0, 1000.0, 1000.0, 800.0, 800.0, 500.0};
  const ExportResult r = exportProgram(makeGoldenMotion(), cell, ExportFormat::Jbi);
  ASSERT_GT(r.files.size(), 2u);
  for (const ExportFile& f : r.files) compareWithGolden("split_" + f.name, f.text);
}

}  // namespace
}  // namespace curvedslicer
