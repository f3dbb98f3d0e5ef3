// Thin features on the bundled branches model (h 1.5, L 1, s 3.7, fixed width): every
// layer with area gets paths (before: 150 of 152 had none, each branch's cross-section reaching
// about 1.3 mm from its rim, less than s/2), and the total void share, measured by the plan's own
// coverage numbers (paths/coverage.hpp, area-weighted over the layers), is at most 10 %; with
// adaptive width (0.7·s–1.3·s) at most 3 %.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "common/sanitized_build.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"

namespace curvedslicer {
namespace {

TEST(ThinFeatures, BranchesEveryLayerWithAreaGetsPathsAndAtMostTenPercentVoid) {
  CURVEDSLICER_SKIP_IF_SANITIZED("ThinRegions.* (tests/cpp/paths/thin_regions_test.cpp)");
  const TriMesh model = readMesh(testing::modelPath("branches_70_closed_low_res.stl"));
  PlanJobOptions options;
  options.layerJob.layers.layerThickness = 1.5;
  options.layerJob.voxelize.voxelSize = 1.0;
  options.planner.beadSpacing = 3.7;
  const PlanJobResult job = runPlanJob(model, options);
  const Plan& plan = job.planned.plan;
  ASSERT_GT(plan.layers.size(), 100u);
  double area = 0.0, voidArea = 0.0;
  std::size_t spots = 0;
  for (const PlanLayer& layer : plan.layers) {
    ASSERT_TRUE(layer.coverage.measured);
    if (layer.coverage.area > 0.0) {
      EXPECT_FALSE(layer.paths.empty())
          << "layer " << layer.index << " has area " << layer.coverage.area << " mm² and no path";
    }
    area += layer.coverage.area;
    voidArea += layer.coverage.voidShare * layer.coverage.area;
    for (const PlanPath& path : layer.paths) {
      if (path.dwell <= 0.0) continue;
      ++spots;
      // A spot: 2 points at least 0.05 mm apart, width s, dwell w / spotWeldSpeed.
      ASSERT_EQ(path.points.size(), 2u);
      EXPECT_GE((path.points[1].position - path.points[0].position).norm(), 0.05);
      EXPECT_DOUBLE_EQ(path.dwell, 3.7 / options.planner.spotWeldSpeed);
      for (const PathPoint& p : path.points) EXPECT_EQ(p.width, 3.7);
    }
  }
  EXPECT_EQ(job.planned.stats.layersWithoutPaths, 0u);
  EXPECT_GT(spots, 0u);
  ASSERT_GT(area, 0.0);
  EXPECT_LE(voidArea / area, 0.10) << "total void share " << voidArea / area;
}

TEST(ThinFeatures, BranchesAdaptiveWidthAtMostThreePercentVoid) {
  CURVEDSLICER_SKIP_IF_SANITIZED(
      "ThinRegions.AdaptiveCentreBeadIsCentredOnACoarseMesh and ThinRegions.AdaptiveWidth*");
  const TriMesh model = readMesh(testing::modelPath("branches_70_closed_low_res.stl"));
  PlanJobOptions options;
  options.layerJob.layers.layerThickness = 1.5;
  options.layerJob.voxelize.voxelSize = 1.0;
  options.planner.beadSpacing = 3.7;
  options.planner.widthMin = 0.7;
  options.planner.widthMax = 1.3;
  const PlanJobResult job = runPlanJob(model, options);
  const PlanCoverageSummary c = summarizeCoverage(job.planned.plan);
  std::printf("branches adaptive 0.7,1.3: void %.4f %%, overlap %.4f %%, arc starts %zu\n",
              100.0 * c.voidShare, 100.0 * c.overlapShare, c.arcStarts);
  EXPECT_EQ(c.measuredLayers, job.planned.plan.layers.size());
  EXPECT_EQ(job.planned.stats.layersWithoutPaths, 0u);
  EXPECT_LE(c.voidShare, 0.03);
}

}  // namespace
}  // namespace curvedslicer
