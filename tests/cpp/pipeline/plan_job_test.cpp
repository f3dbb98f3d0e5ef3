// The core's one plan job (pipeline/plan_job.hpp) and the option vocabulary every front end uses
// (parse/format next to each enum, pipeline/option_parsing.hpp): runPlanJob equals the layer job
// followed by the planner, with the provenance recorded; validation names the bad option; a zero
// plane normal is rejected by the core; cancellation; names round-trip.
#include <gtest/gtest.h>

#include <string>

#include "common/sanitized_build.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/layers/layer_simplification.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"
#include "curvedslicer/plan/plan_io.hpp"

namespace curvedslicer {
namespace {

/// Grid, layers and beads of the coarse box (twice as coarse under the sanitizers).
constexpr double kScale = testing::coarseningUnderSanitizers();
constexpr double kLayerThickness = 20.0 * kScale;
constexpr double kVoxelSize = 5.0 * kScale;

/// The 200 mm box at a coarse resolution (a few seconds at most).
PlanJobOptions coarseBoxOptions() {
  PlanJobOptions options;
  options.layerJob.layers.layerThickness = kLayerThickness;
  options.layerJob.voxelize.voxelSize = kVoxelSize;
  options.planner.beadSpacing = 12.0 * kScale;
  options.modelName = "box.stl";
  options.startSpec = "plane:bottom";
  return options;
}

TEST(PlanJob, EqualsTheLayerJobFollowedByThePlannerWithProvenance) {
  const TriMesh model = readMesh(testing::modelPath("simple_box_closed_low_res.stl"));
  PlanJobOptions options = coarseBoxOptions();
  options.layerJob.geodesic.method = GeodesicMethod::Paper;
  options.layerFormat = LayerFileFormat::Obj;
  const PlanJobResult job = runPlanJob(model, options);

  const LayerJobResult layers = runLayerJob(model, options.layerJob);
  PlanResult direct = planLayers(layers.layers.surfaces, layers.source, options.planner);
  Plan& plan = direct.plan;
  plan.model = "box.stl";
  plan.start = "plane:bottom";
  plan.parameters.layerThickness = kLayerThickness;
  plan.parameters.voxelSize = kVoxelSize;
  plan.parameters.fieldMethod = "paper";
  if (options.layerJob.layers.simplification.enabled) {
    plan.parameters.layerTolerance = kDefaultLayerToleranceVoxels * kVoxelSize;
  }
  ASSERT_FALSE(plan.layers.empty());
  ASSERT_EQ(job.layerFiles.size(), layers.layers.surfaces.size());
  for (std::size_t k = 0; k < plan.layers.size(); ++k) {
    plan.layers[k].surface = job.layerFiles[k];
  }
  EXPECT_EQ(job.layerFiles.front(), "layer_0001.obj");
  EXPECT_EQ(formatPlanJson(job.planned.plan), formatPlanJson(plan));
  EXPECT_EQ(job.layers.stageTimes.back().name, "plan");
  EXPECT_GE(job.totalSeconds, 0.0);
}

TEST(PlanJob, PlanOnLayersRecordsTheSameProvenanceWithoutFileNames) {
  const TriMesh model = readMesh(testing::modelPath("simple_box_closed_low_res.stl"));
  const PlanJobOptions options = coarseBoxOptions();
  const LayerJobResult layers = runLayerJob(model, options.layerJob);
  const PlanResult planned = planOnLayers(layers.layers.surfaces, layers.source, options);
  EXPECT_EQ(planned.plan.model, "box.stl");
  EXPECT_EQ(planned.plan.start, "plane:bottom");
  EXPECT_EQ(planned.plan.parameters.layerThickness, kLayerThickness);
  EXPECT_EQ(planned.plan.parameters.voxelSize, kVoxelSize);
  EXPECT_EQ(planned.plan.parameters.fieldMethod, "anyangle");
  if (options.layerJob.layers.simplification.enabled) {
    EXPECT_EQ(planned.plan.parameters.layerTolerance, kDefaultLayerToleranceVoxels * kVoxelSize);
  } else {
    EXPECT_FALSE(planned.plan.parameters.layerTolerance.has_value());
  }
  EXPECT_TRUE(planned.plan.layers.front().surface.empty());
}

TEST(PlanJob, FullResolutionLayersRecordNoLayerTolerance) {
  const TriMesh model = readMesh(testing::modelPath("simple_box_closed_low_res.stl"));
  PlanJobOptions options = coarseBoxOptions();
  options.layerJob.layers.simplification.enabled = false;
  const PlanJobResult job = runPlanJob(model, options);
  EXPECT_FALSE(job.planned.plan.parameters.layerTolerance.has_value());
  EXPECT_EQ(job.layers.layers.stats.simplifiedTriangles,
            job.layers.layers.stats.fullResolutionTriangles);
  options.layerJob.layers.simplification.tolerance = 0.5;
  options.layerJob.layers.simplification.enabled = true;
  const PlanJobResult simplified = runPlanJob(model, options);
  EXPECT_EQ(simplified.planned.plan.parameters.layerTolerance, 0.5);
  EXPECT_EQ(simplified.layers.layers.stats.simplificationTolerance, 0.5);
  EXPECT_LT(simplified.layers.layers.stats.simplifiedTriangles,
            simplified.layers.layers.stats.fullResolutionTriangles);
  // A plan on the layers of an earlier layer job records the same tolerance.
  const PlanResult onLayers =
      planOnLayers(simplified.layers.layers.surfaces, simplified.layers.source, options);
  EXPECT_EQ(onLayers.plan.parameters.layerTolerance, 0.5);
}

TEST(PlanJob, ValidationNamesTheBadOption) {
  PlanJobOptions options = coarseBoxOptions();
  options.planner.beadSpacing = -3.0;
  try {
    validatePlanJobOptions(options);
    FAIL() << "no error for a negative bead spacing";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("bead spacing must be a positive number of mm: -3"),
              std::string::npos)
        << e.what();
  }
  options = coarseBoxOptions();
  options.layerJob.layers.layerThickness = 0.0;
  EXPECT_THROW(validatePlanJobOptions(options), InvalidInput);
}

TEST(PlanJob, ZeroPlaneNormalIsRejectedByTheCore) {
  PlanJobOptions options = coarseBoxOptions();
  options.planner.initialCurve = parseInitialCurveSpec("plane:0,0,0,0,0,0").curve;
  try {
    validatePlanJobOptions(options);
    FAIL() << "no error for a zero plane normal";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("non-zero normal"), std::string::npos) << e.what();
  }
}

TEST(PlanJob, ThinWallTakesThePlannerOptionsAndRefusesAnInitialCurve) {
  PlannerOptions planner;
  planner.beadSpacing = 2.5;
  planner.pointSpacing = 1.25;
  planner.fitTolerance = 0.02;
  planner.cornerAngle = 45.0;
  planner.geodesic.method = SurfaceGeodesicMethod::Paper;
  planner.improvementPasses = 2;
  const ThinWallOptions wall = thinWallOptionsFrom(planner);
  EXPECT_EQ(wall.beadSpacing, 2.5);
  EXPECT_EQ(wall.pointSpacing, 1.25);
  EXPECT_EQ(wall.fitTolerance, 0.02);
  EXPECT_EQ(wall.cornerAngle, 45.0);
  EXPECT_EQ(wall.geodesic.method, SurfaceGeodesicMethod::Paper);
  EXPECT_EQ(wall.improvementPasses, 2);
  EXPECT_EQ(wall.edge, ThinWallOptions{}.edge);

  PlanJobOptions options;
  options.thinWall = wall;
  EXPECT_NO_THROW(validatePlanJobOptions(options));
  options.planner.initialCurve = parseInitialCurveSpec("plane:0,0,0,1,0,0").curve;
  EXPECT_THROW(validatePlanJobOptions(options), InvalidInput);
  options.planner.initialCurve = InitialCurve{};
  const TriMesh model = readMesh(testing::modelPath("simple_box_closed_low_res.stl"));
  LayerSurface layer;
  EXPECT_THROW(planOnLayers({layer}, model, options), InvalidInput);
}

TEST(PlanJob, CancelledWhenProgressSaysStop) {
  const TriMesh model = readMesh(testing::modelPath("simple_box_closed_low_res.stl"));
  const Progress stop([](double, std::string_view) { return false; });
  EXPECT_THROW(runPlanJob(model, coarseBoxOptions(), stop), Cancelled);
}

TEST(OptionVocabulary, EnumNamesRoundTrip) {
  for (auto m : {SurfaceGeodesicMethod::Accurate, SurfaceGeodesicMethod::Paper}) {
    EXPECT_EQ(parseSurfaceGeodesicMethod(toString(m)), m);
  }
  for (auto m : {GeodesicMethod::AnyAngle, GeodesicMethod::Paper}) {
    EXPECT_EQ(parseGeodesicMethod(toString(m)), m);
  }
  for (auto a : {GridAlignment::Pca, GridAlignment::Model}) {
    EXPECT_EQ(parseGridAlignment(toString(a)), a);
  }
  for (auto f : {LayerFileFormat::Ply, LayerFileFormat::Obj}) {
    EXPECT_EQ(parseLayerFileFormat(toString(f)), f);
  }
  for (auto g : {GcodeMode::Tcp, GcodeMode::Machine}) EXPECT_EQ(parseGcodeMode(toString(g)), g);
  for (auto k : {WallEdgeKind::LowestAlongAxis, WallEdgeKind::NearestToPoint}) {
    EXPECT_EQ(parseWallEdgeKind(toString(k)), k);
  }
  EXPECT_THROW(parseWallEdgeKind("highest"), InvalidInput);
  for (auto f : {ExportFormat::Jbi, ExportFormat::Krl, ExportFormat::Rapid, ExportFormat::Ls,
                 ExportFormat::Gcode, ExportFormat::Csv, ExportFormat::Json}) {
    EXPECT_EQ(parseExportFormat(toString(f)), f);
  }
  EXPECT_EQ(toString(SurfaceGeodesicMethod::Accurate), "accurate");
  EXPECT_EQ(toString(GcodeMode::Machine), "machine");
  EXPECT_EQ(parseGridAlignment(" PCA "), GridAlignment::Pca);
  EXPECT_THROW(parseSurfaceGeodesicMethod("exact"), InvalidInput);
  EXPECT_THROW(parseGcodeMode("joint"), InvalidInput);
  EXPECT_THROW(parseGridAlignment("p ca"), InvalidInput);
}

TEST(OptionVocabulary, ThinWallEdgeSpecs) {
  ThinWallOptions wall;
  parseThinWallEdge("nearest:1,2.5,-3", wall);
  EXPECT_EQ(wall.edge, WallEdgeKind::NearestToPoint);
  EXPECT_EQ(wall.point, Vec3(1, 2.5, -3));
  EXPECT_EQ(formatThinWallEdge(wall), "nearest:1,2.5,-3");
  parseThinWallEdge("lowest:1,0,0", wall);
  EXPECT_EQ(wall.edge, WallEdgeKind::LowestAlongAxis);
  EXPECT_EQ(wall.axis, Vec3::UnitX());
  EXPECT_EQ(formatThinWallEdge(wall), "lowest:1,0,0");
  parseThinWallEdge("lowest", wall);
  EXPECT_EQ(wall.axis, Vec3::UnitZ());
  EXPECT_EQ(formatThinWallEdge(wall), "lowest");
  EXPECT_THROW(parseThinWallEdge("upwards", wall), InvalidInput);
  EXPECT_THROW(parseThinWallEdge("lowest:0,1", wall), InvalidInput);
  EXPECT_THROW(parseThinWallEdge("nearest:0,0,nan", wall), InvalidInput);
}

TEST(OptionVocabulary, InitialCurveSpecs) {
  EXPECT_EQ(parseInitialCurveSpec("boundary").curve.kind, InitialCurveKind::Boundary);
  const InitialCurveSpec plane = parseInitialCurveSpec("plane:1,2,3,0,0,2");
  EXPECT_EQ(plane.curve.kind, InitialCurveKind::Plane);
  EXPECT_EQ(plane.curve.planePoint, Vec3(1, 2, 3));
  EXPECT_EQ(plane.curve.planeNormal, Vec3(0, 0, 2));
  const InitialCurveSpec mesh = parseInitialCurveSpec("mesh:missing_surface.obj");
  EXPECT_EQ(mesh.curve.kind, InitialCurveKind::Surface);
  EXPECT_EQ(mesh.meshFile, std::filesystem::path("missing_surface.obj"));
  EXPECT_TRUE(mesh.curve.surface.empty());  // nothing read while parsing
  EXPECT_THROW(loadInitialCurve(mesh), InvalidInput);
  const InitialCurve loaded = loadInitialCurve(
      parseInitialCurveSpec("mesh:" + testing::modelPath("custom_base_surface.obj").string()));
  EXPECT_GT(loaded.surface.triangleCount(), 0u);
  EXPECT_THROW(parseInitialCurveSpec("plane:1,2,3"), InvalidInput);
  EXPECT_THROW(parseInitialCurveSpec("spiral"), InvalidInput);
  EXPECT_THROW(parseInitialCurveSpec("mesh:"), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
