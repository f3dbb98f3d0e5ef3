#include "curvedslicer/pipeline/plan_output.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/pipeline/layer_output.hpp"
#include "curvedslicer/pipeline/report_json.hpp"
#include "curvedslicer/plan/plan_io.hpp"

namespace curvedslicer {

namespace fs = std::filesystem;

namespace {

using Json = nlohmann::ordered_json;

Json depositionReport(const DepositionStats& d) {
  return Json{
      {"points", d.points},
      {"towards_surface", d.towardsSurface},
      {"towards_beads", d.towardsBeads},
      {"normal_fallbacks", d.normalFallbacks},
      {"growth_corrections", d.growthCorrections},
      {"normals_overruled", d.normalsOverruled},
      {"min_distance_mm", std::isfinite(d.minDistance) ? Json(d.minDistance) : Json(nullptr)},
      {"max_distance_mm", d.maxDistance}};
}

/// A layer's coverage (null when not measured): shares, arc starts and the largest voids.
Json coverageReport(const LayerCoverage& c) {
  if (!c.measured) return Json(nullptr);
  Json voids = Json::array();
  for (const CoverageVoid& v : c.voids) {
    voids.push_back(Json{{"area_mm2", v.area},
                         {"centre_mm", Json::array({v.centre.x(), v.centre.y(), v.centre.z()})},
                         {"size_mm", v.size}});
  }
  return Json{{"area_mm2", c.area},
              {"void_share", c.voidShare},
              {"overlap_share", c.overlapShare},
              {"bead_width_mm", c.beadWidth},
              {"arc_starts", c.arcStarts},
              {"voids", voids}};
}

Json layerReport(const PlanLayer& layer) {
  double length = 0.0;
  std::size_t points = 0;
  for (const PlanPath& p : layer.paths) {
    length += p.length;
    points += p.points.size();
  }
  return Json{{"index", layer.index},
              {"height_mm", layer.height},
              {"paths", layer.paths.size()},
              {"points", points},
              {"arc_length_mm", length},
              {"warnings", layer.warnings},
              {"coverage", coverageReport(layer.coverage)}};
}

/// The plan's coverage in total (paths/coverage.hpp summarizeCoverage).
Json coverageTotals(const Plan& plan) {
  const PlanCoverageSummary s = summarizeCoverage(plan, 10);
  Json j{{"measured_layers", s.measuredLayers}, {"arc_starts", s.arcStarts}};
  j["area_mm2"] = s.measuredLayers > 0 ? Json(s.area) : Json(nullptr);
  j["void_share"] = s.measuredLayers > 0 ? Json(s.voidShare) : Json(nullptr);
  j["overlap_share"] = s.measuredLayers > 0 ? Json(s.overlapShare) : Json(nullptr);
  j["worst_layers"] = s.worstLayers;
  return j;
}

Json plannerInputs(const PlanParameters& p) {
  Json inputs = Json{{"bead_spacing_mm", p.beadSpacing},
                     {"point_spacing_mm", p.pointSpacing},
                     {"fit_tolerance_mm", p.fitTolerance},
                     {"corner_angle_deg", p.cornerAngle ? Json(*p.cornerAngle) : Json(nullptr)},
                     {"initial_curve", p.initialCurve},
                     {"surface_method", p.surfaceMethod}};
  if (!p.narrowStrips.empty()) inputs["narrow_strips"] = p.narrowStrips;
  if (!p.depositionDirection.empty()) inputs["deposition_direction"] = p.depositionDirection;
  if (p.minFeatureWidth) inputs["min_feature_width_mm"] = *p.minFeatureWidth;
  if (p.beadWidthRange) {
    inputs["bead_width_range"] = Json::array({(*p.beadWidthRange)[0], (*p.beadWidthRange)[1]});
  }
  if (p.connectInsets) inputs["connect_insets"] = *p.connectInsets;
  if (p.fillGaps) inputs["fill_gaps"] = *p.fillGaps;
  if (p.minGapArea) inputs["min_gap_area_mm2"] = *p.minGapArea;
  if (p.cornerOverdeposit) inputs["corner_overdeposit_mm"] = *p.cornerOverdeposit;
  if (p.cornerFillAngle) inputs["corner_fill_angle_deg"] = *p.cornerFillAngle;
  return inputs;
}

/// The report of a thin wall: its inputs and the read time (there is no layer job).
Json thinWallReport(const PlanOutputInputs& inputs, const ThinWallOptions& wall) {
  Json report;
  report["inputs"] = Json{{"model", inputs.modelPath},
                          {"thin_wall_edge", formatThinWallEdge(wall)},
                          {"bead_spacing_mm", wall.beadSpacing},
                          {"point_spacing_mm", wall.pointSpacing},
                          {"fit_tolerance_mm", wall.fitTolerance},
                          {"corner_angle_deg", wall.cornerAngle},
                          {"surface_method", std::string(toString(wall.geodesic.method))},
                          {"version", CURVEDSLICER_VERSION}};
  report["stage_times"] = Json::array({Json{{"stage", "read"}, {"seconds", inputs.readSeconds}}});
  return report;
}

/// Stages the layer surfaces and voxel_sets.ply (volume layers only).
void stageLayerFiles(OutputStaging& staging, const PlanJobOptions& options,
                     const PlanJobResult& result, const Progress& progress) {
  const MeshFormat meshFormat =
      options.layerFormat == LayerFileFormat::Ply ? MeshFormat::Ply : MeshFormat::Obj;
  const auto& surfaces = result.layers.layers.surfaces;
  for (std::size_t k = 0; k < surfaces.size(); ++k) {
    staging.stage(result.layerFiles[k],
                  [&](const fs::path& path) { writeMesh(path, surfaces[k].mesh, meshFormat); });
    progress.report(0.8 * static_cast<double>(k + 1) / surfaces.size(), "write");
  }
  staging.stage(kVoxelSetsFileName, [&](const fs::path& path) {
    writeFileAtomically(
        path,
        [&](std::ostream& out) {
          writeVoxelSetsPly(out, result.layers.layers, result.layers.field.field);
        },
        /*binary=*/true);
  });
}

void stageText(OutputStaging& staging, const std::string& name, const std::string& text) {
  staging.stage(name, [&](const fs::path& path) { writeTextFileAtomically(path, text); });
}

}  // namespace

Json makePlanReportSection(const PlanResult& planned) {
  Json j;
  const PlanStats& s = planned.stats;
  j["paths"] = planned.plan.pathCount();
  j["points"] = planned.plan.pointCount();
  j["arc_length_mm"] = s.arcLength;
  j["travel_mm"] = s.travel;
  j["layers_without_paths"] = s.layersWithoutPaths;
  j["dropped_fragments"] = s.droppedFragments;
  j["seams_too_close"] = s.seamsTooClose;
  j["max_fit_deviation_mm"] = s.maxFitDeviation;
  j["coverage"] = coverageTotals(planned.plan);
  j["deposition"] = depositionReport(s.deposition);
  Json times = Json::array();
  for (const PlanStageTime& t : s.stageTimes) {
    times.push_back(Json{{"stage", t.name}, {"seconds", t.seconds}});
  }
  j["stage_times"] = times;
  Json layers = Json::array();
  for (const PlanLayer& layer : planned.plan.layers) layers.push_back(layerReport(layer));
  j["layers"] = layers;
  j["inputs"] = plannerInputs(planned.plan.parameters);
  j["files"] = Json{{"json", kPlanJsonFileName}, {"csv", kPlanCsvFileName}};
  return j;
}

Json makePlanJobReport(const PlanOutputInputs& inputs, const PlanJobOptions& options,
                       PlanJobResult& result) {
  Json report;
  if (options.thinWall) {
    report = thinWallReport(inputs, *options.thinWall);
  } else {
    LayerJobResult& layers = result.layers;
    layers.stageTimes.insert(layers.stageTimes.begin(), StageTime{"read", inputs.readSeconds});
    layers.totalSeconds += inputs.readSeconds;
    layers.peakMemoryBytes = peakResidentMemoryBytes();
    LayerReportInputs layerInputs;
    layerInputs.modelPath = inputs.modelPath;
    layerInputs.modelFileTriangles = inputs.modelFileTriangles;
    layerInputs.tessellationTolerance = inputs.tessellationTolerance;
    layerInputs.startSpec = options.startSpec;
    layerInputs.layerFormat = options.layerFormat;
    layerInputs.layerFiles = result.layerFiles;
    layerInputs.voxelSetsFile = kVoxelSetsFileName;
    report = makeLayerReport(layerInputs, options.layerJob, layers);
  }
  report["plan"] = makePlanReportSection(result.planned);
  return report;
}

void writePlanOutput(const fs::path& dir, const PlanOutputInputs& inputs,
                     const PlanJobOptions& options, PlanJobResult& result,
                     const Progress& progress) {
  progress.report(0.0, "write");
  OutputStaging staging(dir);
  if (!options.thinWall) stageLayerFiles(staging, options, result, progress);
  const Json report = makePlanJobReport(inputs, options, result);
  stageText(staging, kPlanJsonFileName, formatPlanJson(result.planned.plan));
  stageText(staging, kPlanCsvFileName, formatPlanCsv(result.planned.plan));
  stageText(staging, kReportFileName, formatLayerReport(report));
  progress.report(1.0, "write");  // last chance to cancel: nothing is in place yet
  staging.commit(isLayerFileName);
}

}  // namespace curvedslicer
