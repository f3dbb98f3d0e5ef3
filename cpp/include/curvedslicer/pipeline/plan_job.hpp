// The plan job: from a model to a deposition plan in one call — the layer job (layer_pipeline.hpp,
// paper §2) followed by the path planner (paths/planner.hpp, paper §3.1), or the thin-wall planner
// on the model's surface. The one place where the whole chain is assembled and where the plan's
// parameters and provenance (model, start, layer thickness, voxel size, field method, layer file
// names) are recorded: the command line, the Python module and the workbench only translate their
// inputs into a PlanJobOptions and call it.
//
// Stages (progress stage names, share of the overall progress):
//   layers (0–0.6)     runLayerJob — skipped for a thin wall
//   plan (0.6–0.95)    planLayers / planThinWall (their own stage names)
// The caller writes the outputs (pipeline/plan_output.hpp for the command line's folder).
//
// Preconditions: none on the model (anything readMesh or the CAD tessellation returns).
// Errors: those of validatePlanJobOptions, runLayerJob and the planners; no partial result.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/pipeline/layer_pipeline.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"

namespace curvedslicer {

struct PlanJobOptions {
  /// The layer job (start surface, voxel size, field method, layer thickness, …). Unused for a
  /// thin wall, except its memory budget (voxelize.memoryBudgetBytes), which is the whole job's:
  /// the plan's estimated robot points must fit it too (paths/plan_size.hpp).
  LayerJobOptions layerJob;
  /// Paths on the layers (bead spacing, point spacing, fit, initial curve, narrow strips, …).
  PlannerOptions planner;
  /// Set: plan the model's surface as a thin wall instead of slicing a solid (the paper's turbine
  /// base); `planner`'s initial curve must then be the default (Boundary).
  std::optional<ThinWallOptions> thinWall;
  /// Provenance recorded in the plan: the model's name or file (Plan::model) and the start
  /// specification as the user gave it (Plan::start, e.g. "plane:bottom", "faces:0-9").
  std::string modelName;
  std::string startSpec;
  /// Layer file format, for the file names recorded in PlanLayer::surface.
  LayerFileFormat layerFormat = LayerFileFormat::Ply;
};

struct PlanJobResult {
  /// The layer job's result (empty for a thin wall apart from stageTimes).
  LayerJobResult layers;
  /// The plan with every parameter and provenance field filled in, and the planner's statistics.
  PlanResult planned;
  /// Names of the layer files the plan refers to (layerFileNames(layers.layers, layerFormat));
  /// empty for a thin wall.
  std::vector<std::string> layerFiles;
  /// Wall time of the whole job, s.
  double totalSeconds = 0.0;
};

/// The thin-wall options that share the planner's: bead spacing, point spacing, fit tolerance,
/// corner angle, surface geodesic options, minimum path length, seam separation, 2-opt passes
/// and deposition options, copied from `planner`; the wall's edge is ThinWallOptions{}'s (set it
/// with parseThinWallEdge). Front ends that take one set of planner options use this, so a planner
/// option that also applies to walls is copied in one place.
ThinWallOptions thinWallOptionsFrom(const PlannerOptions& planner);

/// Checks every option without touching geometry: the layer job's (unless thin wall), the
/// planner's or the thin wall's, and their combination.
/// @throws InvalidInput naming the option and its value.
void validatePlanJobOptions(const PlanJobOptions& options);

/// Runs the whole job on `model` (part frame, mm; face ids used by a Faces start surface).
/// @throws as runLayerJob and planLayers / planThinWall; Cancelled when `progress` asks to stop.
PlanJobResult runPlanJob(const TriMesh& model, const PlanJobOptions& options,
                         Progress progress = {});

/// The plan stage alone, on layers of an earlier layer job run with `options.layerJob` (front
/// ends that keep the layers, e.g. the workbench, re-plan without re-slicing). Records the same
/// parameters and provenance as runPlanJob, except PlanLayer::surface (layer file names), which
/// only runPlanJob knows. For a thin wall, `layers` must be empty and `startSurface` is the wall.
/// @param layers        the layer surfaces, bottom to top (extractLayers().surfaces)
/// @param startSurface  the start-surface triangles (deposited material under the first layer;
///                      may be empty); for a thin wall the wall's surface
PlanResult planOnLayers(const std::vector<LayerSurface>& layers, const TriMesh& startSurface,
                        const PlanJobOptions& options, Progress progress = {});

}  // namespace curvedslicer
