// Configuration bits / turn numbers in the JBI, KRL, RAPID and LS exports: read back by the strict
// readers of program_readers.hpp, they must be constant within every weld (from the move onto the
// path start, after which the arc goes on, to the move after which it goes off) and be the
// weld's configuration (MotionPathSpan::configuration); arc-off points state their own. Synthetic
// motions put joints on the boundaries rounding noise flips (J4 exactly 0 among ±1e-16, J6
// crossing -180°), so a writer that recomputed the configuration per point would fail here.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/robot/configuration.hpp"
#include "export_test_support.hpp"
#include "program_readers.hpp"
#include "synthetic_motion.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

TEST(ConfigurationBits, NoiseOnABoundaryDoesNotFlipThemWithinAWeld) {
  const MotionPlan motion = makeNoisyMotion();
  // The premise: recomputed per point, the configuration would flip inside both welds.
  for (const MotionPathSpan& span : motion.paths) {
    bool flips = false;
    for (std::size_t i = span.begin; i < span.end; ++i) {
      const MotionPoint& p = motion.points[i];
      flips = flips || configurationOf(p.joints, p.configuration) != span.configuration;
    }
    EXPECT_TRUE(flips) << "weld " << span.path << " has no noise on a boundary";
  }
  const Cell cell = defaultCell();
  for (ExportFormat format : kRobotFormats) {
    const std::string name(toString(format));
    const ReadProgram program = exportAndRead(motion, cell, format);
    ASSERT_EQ(program.moves.size(), motion.points.size()) << name;
    ASSERT_EQ(program.welds.size(), motion.paths.size()) << name;
    expectConstantWithinWelds(program, name);
    for (std::size_t w = 0; w < motion.paths.size(); ++w) {
      const MotionPathSpan& span = motion.paths[w];
      EXPECT_EQ(program.welds[w].first, span.begin) << name;
      EXPECT_EQ(program.welds[w].second, span.end - 1) << name;
      for (std::size_t i = span.begin; i < span.end; ++i) {
        ASSERT_TRUE(program.moves[i].configuration) << name << ": " << program.moves[i].line;
        expectStates(*program.moves[i].configuration, span.configuration,
                     name + ": " + program.moves[i].line);
      }
    }
    // Arc-off points state the configuration of their own joints (home is a joint target, or
    // Cartesian with its own configuration in JBI).
    for (std::size_t i = 0; i < motion.points.size(); ++i) {
      const MotionPoint& p = motion.points[i];
      if (p.kind == MoveKind::Path || !program.moves[i].configuration) continue;
      expectStates(*program.moves[i].configuration, configurationOf(p.joints, p.configuration),
                   name + " arc-off: " + program.moves[i].line);
    }
  }
}

TEST(ConfigurationBits, JbiWithTwentyFourRconfFieldsKeepsThemToo) {
  Cell cell = defaultCell();
  cell.exportOptions.maxNameLength = 32;  // DX100 and later: 24 RCONF fields
  const MotionPlan motion = makeNoisyMotion();
  const ReadProgram program = exportAndRead(motion, cell, ExportFormat::Jbi);
  ASSERT_EQ(program.moves.size(), motion.points.size());
  expectConstantWithinWelds(program, "jbi");
  ASSERT_TRUE(program.moves[motion.paths[1].begin].configuration);
  EXPECT_EQ(program.moves[motion.paths[1].begin].configuration->text,
            "1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0");
}

TEST(ConfigurationBits, SplitJbiKeepsThemAcrossSubJobs) {
  Cell cell = defaultCell();
  cell.exportOptions.maxLinesPerJob = 9;  // forces sub-jobs, one weld continues in the next job
  const MotionPlan motion = makeNoisyMotion();
  const ExportResult r = exportProgram(motion, cell, ExportFormat::Jbi);
  ASSERT_GT(r.files.size(), 2u);
  const ReadProgram program = readJbiProgram(r, cell);
  ASSERT_EQ(program.moves.size(), motion.points.size());
  ASSERT_EQ(program.welds.size(), motion.paths.size());
  expectConstantWithinWelds(program, "split jbi");
}

TEST(ConfigurationBits, AWeldPointInAnotherBranchIsWarnedAbout) {
  const Cell cell = defaultCell();
  MotionPlan motion = makeNoisyMotion();
  for (ExportFormat format : kRobotFormats) {
    EXPECT_TRUE(exportProgram(motion, cell, format).warnings.empty()) << toString(format);
  }
  motion.points[motion.paths[0].begin + 3].configuration = 4;  // a wrist flip inside weld 0
  for (ExportFormat format : kRobotFormats) {
    const std::vector<std::string> warnings = exportProgram(motion, cell, format).warnings;
    ASSERT_EQ(warnings.size(), 1u) << toString(format);
    EXPECT_NE(warnings[0].find("1 weld point(s) lie in another IK branch"), std::string::npos)
        << warnings[0];
    EXPECT_NE(warnings[0].find("layer 0 path 0 point 3 has IK branch 4, its weld states 0"),
              std::string::npos)
        << warnings[0];
  }
}

}  // namespace
}  // namespace curvedslicer
