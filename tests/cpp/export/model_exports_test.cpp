// The acceptance models of the motion planner, planned end to end (runPlanJob, planMotion with the
// default cell) and exported to JBI, KRL, RAPID and LS: read back by the strict readers, the stated
// robot configuration (RCONF, S/T, confdata, CONFIG) is constant within every weld and is the
// planned solution's, up to joints within kBoundaryBand of a boundary. The plans are coarser than
// the measurement (voxel 2 mm and 5 mm point spacing for the curved example, 3 mm layers,
// 4 mm voxels, 10 mm bead and point spacing for the cylinder) to keep the run time at seconds;
// the configuration rules do not depend on the resolution.
// The same motions exported to CSV are read back as a process engineer would check them: every
// robot joint's and both positioner axes' speed, recomputed from the exported per-point angles and
// times, stays within the cell's max_speed_deg_s.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "axis_speeds.hpp"
#include "common/sanitized_build.hpp"
#include "common/small_part.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"
#include "export_test_support.hpp"
#include "model_plans.hpp"
#include "program_readers.hpp"
#include "program_readers_krl_rapid.hpp"
#include "synthetic_motion.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

/// rad (15°): a stated configuration field may be that of any angle this close to the joint
/// (hysteresis keeps a weld's configuration while a joint moves a little past a boundary).
constexpr double kBoundaryBand = 15.0 * kDegT;

/// The motion of a model's plan, and how many connected-inset links the plan has (each joins two
/// rings into one weld; paths/connected_insets.hpp).
struct ModelMotion {
  MotionPlan motion;
  std::size_t insetLinks = 0;
};

ModelMotion planModelMotion(const ModelCase& c, const Cell& cell) {
  const PlanJobResult job = planModelCase(c);
  return {planMotion(job.planned.plan, cell), job.planned.stats.insetLinks};
}

/// True once planMotion fills MotionPathSpan::configuration (one configuration per weld).
bool plannerSetsConfigurations(const MotionPlan& motion) {
  for (const MotionPathSpan& span : motion.paths) {
    if (span.configuration != RobotConfiguration{}) return true;
  }
  return false;
}

/// Every robot format of `motion`: welds where the spans are, one configuration per weld, and
/// that configuration the solution's at every weld point (failures counted, the first shown).
void expectConfigurationsPerWeld(const MotionPlan& motion, const Cell& cell) {
  for (ExportFormat format : kRobotFormats) {
    const std::string name(toString(format));
    const ReadProgram program = exportAndRead(motion, cell, format);
    ASSERT_EQ(program.moves.size(), motion.points.size()) << name;
    ASSERT_EQ(program.welds.size(), motion.paths.size()) << name;
    std::size_t changes = 0, inconsistent = 0;
    std::string firstChange, firstInconsistent;
    for (std::size_t w = 0; w < motion.paths.size(); ++w) {
      const MotionPathSpan& span = motion.paths[w];
      ASSERT_EQ(program.welds[w].first, span.begin) << name;
      ASSERT_EQ(program.welds[w].second, span.end - 1) << name;
      const auto& start = program.moves[span.begin].configuration;
      ASSERT_TRUE(start.has_value()) << name << ": " << program.moves[span.begin].line;
      for (std::size_t i = span.begin; i < span.end; ++i) {
        const auto& stated = program.moves[i].configuration;
        ASSERT_TRUE(stated.has_value()) << name << ": " << program.moves[i].line;
        if (stated->text != start->text && changes++ == 0) {
          firstChange = "layer " + std::to_string(span.layer) + " path " +
                        std::to_string(span.path) + ": " + start->text + " -> " + stated->text +
                        " at " + program.moves[i].line;
        }
        const std::string why = inconsistencyWithJoints(*stated, motion.points[i], kBoundaryBand);
        if (!why.empty() && inconsistent++ == 0) {
          firstInconsistent = "layer " + std::to_string(span.layer) + " path " +
                              std::to_string(span.path) + " point " +
                              std::to_string(motion.points[i].index) + ": " + why;
        }
      }
    }
    EXPECT_EQ(changes, 0u) << name
                           << ": configuration changes within welds, first: " << firstChange;
    EXPECT_EQ(inconsistent, 0u) << name << ": weld points whose stated configuration is not "
                                << "their solution's, first: " << firstInconsistent;
  }
}

TEST(ModelExports, CurvedExampleStatesOneConfigurationPerWeldAndKeepsAxisSpeeds) {
  CURVEDSLICER_SKIP_IF_SANITIZED(
      "ModelExports.SmallPartStatesOneConfigurationPerWeldAndKeepsAxisSpeeds");
  const Cell cell = defaultCell();
  const ModelMotion planned = planModelMotion(curvedExampleCase(), cell);
  const MotionPlan& motion = planned.motion;
  // Over 100 rings and pieces, some rings joined into one weld (open welds over several rings).
  ASSERT_GT(motion.paths.size() + planned.insetLinks, 100u);
  ASSERT_GT(planned.insetLinks, 0u);
  ASSERT_TRUE(plannerSetsConfigurations(motion));
  expectConfigurationsPerWeld(motion, cell);
  expectAxisSpeedsFromCsv(motion, cell);
  expectKrlAndRapidReadBack(motion, cell);
}

TEST(ModelExports, CylinderStatesOneConfigurationPerWeldAndKeepsAxisSpeeds) {
  CURVEDSLICER_SKIP_IF_SANITIZED(
      "ModelExports.SmallPartStatesOneConfigurationPerWeldAndKeepsAxisSpeeds");
  const Cell cell = defaultCell();
  const ModelMotion planned = planModelMotion(cylinderCase(), cell);
  const MotionPlan& motion = planned.motion;
  // Over 100 rings and pieces, some rings joined into one weld (open welds over several rings).
  ASSERT_GT(motion.paths.size() + planned.insetLinks, 100u);
  ASSERT_GT(planned.insetLinks, 0u);
  ASSERT_TRUE(plannerSetsConfigurations(motion));
  expectConfigurationsPerWeld(motion, cell);
  expectAxisSpeedsFromCsv(motion, cell);
  expectKrlAndRapidReadBack(motion, cell);
}

/// The same on the small part of common/small_part.hpp (the sanitizer build runs this one).
TEST(ModelExports, SmallPartStatesOneConfigurationPerWeldAndKeepsAxisSpeeds) {
  const Cell cell = defaultCell();
  const PlanJobResult job = planSmallPart();
  const MotionPlan motion = planMotion(job.planned.plan, cell);
  // Rings joined into open welds over several layers.
  ASSERT_GT(job.planned.plan.layers.size(), 5u);
  ASSERT_GT(job.planned.stats.insetLinks, 0u);
  ASSERT_TRUE(plannerSetsConfigurations(motion));
  expectConfigurationsPerWeld(motion, cell);
  expectAxisSpeedsFromCsv(motion, cell);
  expectKrlAndRapidReadBack(motion, cell);
}

}  // namespace
}  // namespace curvedslicer
