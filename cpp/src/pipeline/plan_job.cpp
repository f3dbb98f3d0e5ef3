#include "curvedslicer/pipeline/plan_job.hpp"

#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/layers/layer_simplification.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/paths/plan_size.hpp"
#include "curvedslicer/pipeline/layer_output.hpp"

namespace curvedslicer {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point begin) {
  return std::chrono::duration<double>(Clock::now() - begin).count();
}

/// What the plan records of the job besides the planner's own parameters; the layer
/// simplification's tolerance as the layer job resolves it (absent at full resolution), so a plan
/// on the layers of an earlier layer job records what `runPlanJob` would.
void recordProvenance(Plan& plan, const PlanJobOptions& options) {
  plan.model = options.modelName;
  plan.start = options.startSpec;
  if (options.thinWall) return;  // a wall has no volume layers: thickness, voxel, field unset
  const LayerJobOptions& job = options.layerJob;
  plan.parameters.layerThickness = job.layers.layerThickness;
  plan.parameters.voxelSize = job.voxelize.voxelSize;
  plan.parameters.fieldMethod = std::string(toString(job.geodesic.method));
  if (job.layers.simplification.enabled) {
    plan.parameters.layerTolerance =
        resolveLayerTolerance(job.layers.simplification, job.voxelize.voxelSize);
  }
}

/// Refuses a plan whose robot points would not fit the job's memory budget
/// (layerJob.voxelize.memoryBudgetBytes, also for a thin wall), before anything is fitted.
/// @param area  mm², of the layer surfaces (or of the wall's surface)
void checkPlanSizeFor(double area, const PlanJobOptions& options) {
  const double budget = options.layerJob.voxelize.memoryBudgetBytes;
  if (options.thinWall) {
    checkPlanSize(area, options.thinWall->beadSpacing, options.thinWall->pointSpacing, budget);
  } else {
    checkPlanSize(area, options.planner.beadSpacing, options.planner.pointSpacing, budget);
  }
}

/// The same before slicing, in O(triangles): a solid of volume V in layers h apart has layer
/// surfaces of about V / h in all; a wall is its own surface.
void checkPlanSizeBeforeSlicing(const TriMesh& model, const PlanJobOptions& options) {
  const auto n = static_cast<int>(model.vertices.size());
  for (const Vec3i& t : model.triangles) {
    if ((t.array() < 0).any() || (t.array() >= n).any()) return;  // the mesh checks report it
  }
  const double area = options.thinWall
                          ? surfaceArea(model)
                          : std::abs(signedVolume(model)) / options.layerJob.layers.layerThickness;
  checkPlanSizeFor(area, options);
}

}  // namespace

ThinWallOptions thinWallOptionsFrom(const PlannerOptions& planner) {
  ThinWallOptions wall;
  wall.beadSpacing = planner.beadSpacing;
  wall.pointSpacing = planner.pointSpacing;
  wall.fitTolerance = planner.fitTolerance;
  wall.cornerAngle = planner.cornerAngle;
  wall.geodesic = planner.geodesic;
  wall.minPathLength = planner.minPathLength;
  wall.seamSeparation = planner.seamSeparation;
  wall.improvementPasses = planner.improvementPasses;
  wall.deposition = planner.deposition;
  return wall;
}

void validatePlanJobOptions(const PlanJobOptions& options) {
  if (options.thinWall) {
    validateThinWallOptions(*options.thinWall);
    if (options.planner.initialCurve.kind != InitialCurveKind::Boundary) {
      throw InvalidInput("an initial curve does not apply to a thin wall: '" +
                         options.planner.initialCurve.describe() +
                         "'; the wall's edge is the initial curve (leave the initial curve at "
                         "boundary)");
    }
    return;
  }
  validateLayerJobOptions(options.layerJob);
  validatePlannerOptions(options.planner);
}

PlanResult planOnLayers(const std::vector<LayerSurface>& layers, const TriMesh& startSurface,
                        const PlanJobOptions& options, Progress progress) {
  validatePlanJobOptions(options);
  PlanResult planned;
  if (options.thinWall) {
    if (!layers.empty()) {
      throw InvalidInput(
          "a thin wall is planned on its surface, not on layers: " + std::to_string(layers.size()) +
          " layers given; pass the wall as the surface and no layers");
    }
    checkPlanSizeFor(surfaceArea(startSurface), options);
    planned = planThinWall(startSurface, *options.thinWall, std::move(progress));
  } else {
    double area = 0.0;
    for (const LayerSurface& layer : layers) area += surfaceArea(layer.mesh);
    checkPlanSizeFor(area, options);
    planned = planLayers(layers, startSurface, options.planner, std::move(progress));
  }
  recordProvenance(planned.plan, options);
  return planned;
}

PlanJobResult runPlanJob(const TriMesh& model, const PlanJobOptions& options, Progress progress) {
  validatePlanJobOptions(options);
  checkPlanSizeBeforeSlicing(model, options);
  const auto begin = Clock::now();
  PlanJobResult result;
  if (options.thinWall) {
    const TriMesh surface = cleanMesh(model).mesh;
    result.planned = planOnLayers({}, surface, options, progress.sub(0.0, 0.95));
    result.totalSeconds = secondsSince(begin);
    return result;
  }
  result.layers = runLayerJob(model, options.layerJob, progress.sub(0.0, 0.6));
  const auto planBegin = Clock::now();
  result.planned = planOnLayers(result.layers.layers.surfaces, result.layers.source, options,
                                progress.sub(0.6, 0.95));
  const double planSeconds = secondsSince(planBegin);
  result.layers.stageTimes.push_back(StageTime{"plan", planSeconds});
  result.layers.totalSeconds += planSeconds;
  result.layerFiles = layerFileNames(result.layers.layers, options.layerFormat);
  Plan& plan = result.planned.plan;
  for (std::size_t k = 0; k < plan.layers.size() && k < result.layerFiles.size(); ++k) {
    plan.layers[k].surface = result.layerFiles[k];
  }
  result.totalSeconds = secondsSince(begin);
  return result;
}

}  // namespace curvedslicer
