#include "plan_command.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "command_errors.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/pipeline/layer_output.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"
#include "curvedslicer/pipeline/plan_output.hpp"
#include "model_input.hpp"
#include "terminal_progress.hpp"

namespace curvedslicer::cli {

namespace fs = std::filesystem;

namespace {

/// The job as the arguments describe it; the files they name are not read yet.
struct PlanCommandJob {
  PlanJobOptions options;
  StartSurfaceSpec start;
  InitialCurveSpec initialCurve;
  double tessellationTolerance = 0.0;
};

/// --thin-wall: the planner's options become the wall's; the layer-job arguments are unused.
void parseThinWall(const PlanArguments& args, PlanCommandJob& job) {
  job.options.thinWall = thinWallOptionsFrom(job.options.planner);
  parseThinWallEdge(args.thinWall, *job.options.thinWall);
  job.options.startSpec = "thin-wall:" + args.thinWall;
  // Any curve but the boundary is an error for a wall (validatePlanJobOptions says so).
  job.options.planner.initialCurve = job.initialCurve.curve;
  job.tessellationTolerance = parseTessellationTolerance(args.layers.tessellationTolerance);
}

/// Parses every argument into the job without touching a file.
PlanCommandJob parseArguments(const PlanArguments& args) {
  const LayersArguments& la = args.layers;
  PlanCommandJob job;
  args.planner.applyTo(job.options.planner);
  job.initialCurve = parseInitialCurveSpec(args.initialCurve);
  job.options.modelName = la.model;
  if (!args.thinWall.empty()) {
    parseThinWall(args, job);
    return job;
  }
  if (la.layerThickness.empty() || la.voxelSize.empty()) {
    throw InvalidInput(std::string("missing ") +
                       (la.layerThickness.empty() ? "--layer-thickness" : "--voxel") +
                       ": required unless --thin-wall; pass e.g. --layer-thickness 1.5 "
                       "--voxel 0.5");
  }
  LayerJobArguments layerJob = parseLayerJobArguments(la);
  job.options.layerJob = std::move(layerJob.options);
  job.options.layerFormat = layerJob.format;
  job.options.startSpec = la.start;
  job.start = std::move(layerJob.start);
  job.tessellationTolerance = layerJob.tessellationTolerance;
  // A surface curve is set once its mesh is read (validation rejects an empty one).
  if (job.initialCurve.meshFile.empty()) job.options.planner.initialCurve = job.initialCurve.curve;
  return job;
}

/// Reads the model and the files the options name (start surface, initial-curve surface).
ModelInput readInputs(const PlanArguments& args, PlanCommandJob& job) {
  const double voxel = job.options.thinWall ? 0.0 : job.options.layerJob.voxelize.voxelSize;
  ModelInput model = readModel(fs::path(args.layers.model), job.tessellationTolerance, voxel);
  if (!job.options.thinWall) {
    job.options.layerJob.start = loadStartSurface(job.start);
    job.options.planner.initialCurve = loadInitialCurve(job.initialCurve);
  }
  return model;
}

/// Total void and overlap share, arc starts and the layers with the largest void share.
void printCoverage(const Plan& plan) {
  const PlanCoverageSummary s = summarizeCoverage(plan, 3);
  if (s.measuredLayers == 0) {
    std::printf("curvedslicer: %zu arc starts; coverage not measured\n", s.arcStarts);
    return;
  }
  std::string worst;
  for (const int index : s.worstLayers) {
    char item[64];
    std::snprintf(item, sizeof(item), "%slayer %d (%.1f %%)", worst.empty() ? "" : ", ", index,
                  100.0 * plan.layers[index].coverage.voidShare);
    worst += item;
  }
  std::printf(
      "curvedslicer: coverage: %.2f %% void, %.2f %% overlap (area-weighted over %zu layers), "
      "%zu arc starts%s%s\n",
      100.0 * s.voidShare, 100.0 * s.overlapShare, s.measuredLayers, s.arcStarts,
      worst.empty() ? "" : "; most void: ", worst.c_str());
}

void printSummary(const PlanJobResult& result, const fs::path& outputDir) {
  const Plan& plan = result.planned.plan;
  for (const PlanLayer& layer : plan.layers) {
    if (!layer.paths.empty() || layer.warnings.empty()) continue;
    std::fprintf(stderr, "curvedslicer: warning: layer %d has no paths: %s\n", layer.index,
                 layer.warnings.front().c_str());
  }
  std::printf(
      "curvedslicer: wrote a plan of %zu paths (%zu points) on %zu layers to %s (%s, %s, %s%s)\n",
      plan.pathCount(), plan.pointCount(), plan.layers.size(), outputDir.string().c_str(),
      kPlanJsonFileName, kPlanCsvFileName, kReportFileName,
      result.layerFiles.empty() ? "" : ", layer files");
  printCoverage(plan);
}

double secondsSince(std::chrono::steady_clock::time_point begin) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

}  // namespace

int runPlanCommand(const PlanArguments& args) {
  installInterruptHandlers();
  TerminalProgress display(!args.layers.quiet);
  const fs::path outputDir(args.layers.output);
  try {
    PlanCommandJob job = parseArguments(args);
    validatePlanJobOptions(job.options);
    checkOutputFolder(outputDir);
    const Progress progress([&display](double fraction, std::string_view stage) {
      return display.update(fraction, stage);
    });
    progress.report(0.0, "read");
    const auto readBegin = std::chrono::steady_clock::now();
    const ModelInput model = readInputs(args, job);
    const PlanOutputInputs outputInputs{args.layers.model, model.mesh.triangleCount(),
                                        model.tessellationTolerance, secondsSince(readBegin)};
    PlanJobResult result = runPlanJob(model.mesh, job.options, progress.sub(0.0, 0.95));
    writePlanOutput(outputDir, outputInputs, job.options, result, progress.sub(0.95, 1.0));
    display.finishLine();
    printWarnings(result.layers.warnings);
    if (!args.layers.quiet) printSummary(result, outputDir);
    return kExitOk;
  } catch (...) {
    return failWithCurrentException(display, outputDir.string(), kJobOutOfMemoryMessage);
  }
}

}  // namespace curvedslicer::cli
