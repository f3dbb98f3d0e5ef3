// Bead coverage of the turbine example's blades (resources/examples/turbine.py): planned at
// the example's settings (h 1.5, L 1, s 3.7, narrow strips Overlap, minimum feature width 1 mm,
// minimum gap area 1 mm², corner fill up to 150° corners; gap fill on, the default) from the
// tessellations in tests/data/turbine/, the total void share is at most 1.5 %, by the plan's own
// coverage numbers (paths/coverage.hpp, area-weighted over the layers) and by an independent
// recomputation from the layer meshes and plan points (common/independent_coverage.hpp, bead widths
// honoured).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "common/independent_coverage.hpp"
#include "common/sanitized_build.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"

namespace curvedslicer {
namespace {

std::filesystem::path turbineData(const char* name) {
  return std::filesystem::path(CURVEDSLICER_SOURCE_DIR) / "tests" / "data" / "turbine" / name;
}

TEST(TurbineCoverage, BladesAtTheExamplesSettingsAtMostOneAndAHalfPercentVoid) {
  CURVEDSLICER_SKIP_IF_SANITIZED("CornerFill.* and GapFill.* (tests/cpp/paths)");
  const TriMesh blades = readMesh(turbineData("blades.stl"));
  PlanJobOptions options;
  options.layerJob.layers.layerThickness = 1.5;
  options.layerJob.voxelize.voxelSize = 1.0;
  options.layerJob.start.kind = StartSurface::Kind::Mesh;
  options.layerJob.start.mesh = readMesh(turbineData("base_surface.stl"));
  options.planner.beadSpacing = 3.7;
  options.planner.narrowStrips = NarrowStripMode::Overlap;
  options.planner.minFeatureWidth = 1.0;    // turbine.py BLADE_MIN_FEATURE_WIDTH
  options.planner.minGapArea = 1.0;         // turbine.py BLADE_MIN_GAP_AREA
  options.planner.cornerFillAngle = 150.0;  // turbine.py BLADE_CORNER_FILL_ANGLE
  const PlanJobResult job = runPlanJob(blades, options);
  const Plan& plan = job.planned.plan;
  ASSERT_GE(plan.layers.size(), 19u);
  const PlanCoverageSummary summary = summarizeCoverage(plan);
  EXPECT_EQ(summary.measuredLayers, plan.layers.size());
  EXPECT_LE(summary.voidShare, 0.015) << "plan's void share " << summary.voidShare;
  testing::Coverage independent;
  ASSERT_EQ(job.layers.layers.surfaces.size(), plan.layers.size());
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    testing::addLayerCoverage(job.layers.layers.surfaces[l].mesh, plan.layers[l].paths, 3.7,
                              independent, /*useWidths=*/true);
  }
  std::printf("turbine blades: plan void %.3f %%, overlap %.2f %%; recomputed void %.3f %%\n",
              100.0 * summary.voidShare, 100.0 * summary.overlapShare,
              100.0 * independent.voidShare());
  EXPECT_NEAR(independent.area, summary.area, 1e-6 * summary.area);
  EXPECT_LE(independent.voidShare(), 0.015) << "recomputed void share " << independent.voidShare();
}

}  // namespace
}  // namespace curvedslicer
