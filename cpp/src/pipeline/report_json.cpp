#include "curvedslicer/pipeline/report_json.hpp"

#include <cmath>
#include <map>
#include <string>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace {

using Json = nlohmann::ordered_json;

/// A finite number, or null.
Json number(double value) {
  return std::isfinite(value) ? Json(value) : Json(nullptr);
}

Json vec3(const Vec3& v) {
  return Json::array({number(v.x()), number(v.y()), number(v.z())});
}

Json box(const Aabb& b) {
  if (b.empty()) return Json{{"min_mm", nullptr}, {"max_mm", nullptr}};
  return Json{{"min_mm", vec3(b.min)}, {"max_mm", vec3(b.max)}};
}

Json inputsJson(const LayerReportInputs& inputs, const LayerJobOptions& options,
                const LayerJobResult& result) {
  Json j;
  j["model"] = inputs.modelPath;
  if (inputs.tessellationTolerance > 0.0) {
    j["tessellation_tolerance_mm"] = number(inputs.tessellationTolerance);
  }
  j["start_surface"] = Json{{"spec", inputs.startSpec}, {"description", result.startDescription}};
  j["layer_thickness_mm"] = number(options.layers.layerThickness);
  j["voxel_size_mm"] = number(options.voxelize.voxelSize);
  j["method"] = std::string(toString(result.field.method));
  j["grid_alignment"] = std::string(toString(options.voxelize.alignment));
  j["cap_holes"] = options.capHoles;
  j["memory_budget_bytes"] = number(options.voxelize.memoryBudgetBytes);
  j["full_resolution_layers"] = !options.layers.simplification.enabled;
  j["layer_tolerance_mm"] = options.layers.simplification.enabled
                                ? number(result.layers.stats.simplificationTolerance)
                                : Json(nullptr);
  j["layer_format"] = std::string(toString(inputs.layerFormat));
  j["version"] = CURVEDSLICER_VERSION;
  return j;
}

Json meshJson(const LayerReportInputs& inputs, const LayerJobResult& result) {
  const MeshReport& r = result.meshReport;
  const CleanResult& c = result.clean;
  Json j;
  j["file_triangles"] = inputs.modelFileTriangles;
  j["vertices"] = r.vertices;
  j["triangles"] = r.triangles;
  j["closed"] = r.closed();
  j["consistently_oriented"] = r.consistentlyOriented();
  j["open_edges"] = r.openEdges;
  j["non_manifold_edges"] = r.nonManifoldEdges;
  j["degenerate_triangles"] = r.degenerateTriangles;
  j["inconsistent_edges"] = r.inconsistentEdges;
  j["components"] = r.components;
  j["area_mm2"] = number(r.area);
  j["volume_mm3"] = number(r.volume);
  j["bounds"] = box(r.bounds);
  j["repair"] = Json{{"merged_vertices", c.mergedVertices},
                     {"degenerate_triangles", c.degenerateTriangles},
                     {"duplicate_triangles", c.duplicateTriangles},
                     {"opposite_duplicate_triangles", c.oppositeDuplicateTriangles},
                     {"weld_tolerance_mm", number(c.weldTolerance)},
                     {"holes", result.capping.loops},
                     {"capped_holes", result.capping.cappedLoops},
                     {"holes_capped_on_start_surface", result.capping.loopsOnStartSurface},
                     {"cap_triangles", result.capping.capTriangles},
                     {"uncapped_boundary_edges", result.capping.openBoundaryEdges}};
  return j;
}

Json gridJson(const LayerJobResult& result) {
  const VoxelGrid& grid = result.voxelization.grid;
  const GridGeometry& g = grid.geometry;
  const VoxelizeStats& s = result.voxelization.stats;
  Json j;
  j["frame"] =
      Json{{"origin_mm", vec3(g.frame.origin)},
           {"axes", Json::array({vec3(g.frame.rotation.col(0)), vec3(g.frame.rotation.col(1)),
                                 vec3(g.frame.rotation.col(2))})}};
  j["corner_mm"] = vec3(g.corner);
  j["voxel_size_mm"] = number(g.voxelSize);
  j["dims"] = Json::array({g.dims.x(), g.dims.y(), g.dims.z()});
  j["cells"] = g.cellCount();
  j["inside_voxels"] = grid.insideCount;
  j["inside_volume_mm3"] = number(grid.insideVolume());
  j["columns"] = s.columns;
  j["odd_columns"] = s.oddColumns;
  j["resolved_voxels"] = s.resolvedVoxels;
  j["unresolved_voxels"] = s.unresolvedVoxels;
  j["fill_rule"] = std::string(toString(s.fillRule));
  j["overlap_voxels"] = s.overlapVoxels;
  j["overlap_bounds"] = box(s.overlapBounds);
  return j;
}

Json fieldJson(const LayerJobResult& result) {
  const GeodesicResult& f = result.field;
  Json j;
  j["method"] = std::string(toString(f.method));
  j["seeds"] = f.seedCount;
  j["reached"] = f.reachedCount;
  Json unreached;
  unreached["count"] = f.unreached.count;
  unreached["components"] = f.unreached.components;
  unreached["bounds"] = box(f.unreached.bounds);
  unreached["example_mm"] = f.unreached.count > 0 ? vec3(f.unreached.example) : Json(nullptr);
  j["unreached"] = unreached;
  j["max_distance_mm"] = number(f.maxDistance);
  j["diagnostics"] = Json{{"line_of_sight_tests", f.lineOfSightTests},
                          {"line_of_sight_failures", f.lineOfSightFailures},
                          {"paper_outer_iterations", f.paperOuterIterations},
                          {"paper_correction_rounds", f.paperCorrectionRounds}};
  return j;
}

/// The per-layer summaries of the result; derived from its surfaces and voxel sets when the
/// result was put together without them.
std::vector<LayerSummary> layerSummaries(const LayersResult& layers) {
  if (!layers.summaries.empty() || layers.surfaces.empty()) return layers.summaries;
  std::map<int, std::size_t> setSizes;
  for (const VoxelLayerSet& set : layers.voxelSets) setSizes[set.index] = set.cells.size();
  std::vector<LayerSummary> summaries;
  summaries.reserve(layers.surfaces.size());
  for (const LayerSurface& s : layers.surfaces) {
    LayerSummary m;
    m.index = s.index;
    m.level = s.level;
    m.vertices = s.mesh.vertexCount();
    m.triangles = s.mesh.triangleCount();
    m.fullResolutionTriangles = m.triangles;  // unknown here; the surfaces are all there is
    m.area = s.area;
    m.components = s.components;
    m.thicknessToPrevious = s.thicknessToPrevious;
    const auto it = setSizes.find(s.index);
    m.voxelSetSize = it == setSizes.end() ? std::size_t{0} : it->second;
    summaries.push_back(m);
  }
  return summaries;
}

Json layersJson(const LayerReportInputs& inputs, const std::vector<LayerSummary>& summaries) {
  Json layers = Json::array();
  for (std::size_t k = 0; k < summaries.size(); ++k) {
    const LayerSummary& s = summaries[k];
    const ThicknessStats& t = s.thicknessToPrevious;
    const bool measured = t.samples > 0;
    Json j;
    j["index"] = s.index;
    j["level_mm"] = number(s.level);
    j["file"] = inputs.layerFiles.empty() ? Json(nullptr) : Json(inputs.layerFiles[k]);
    j["vertices"] = s.vertices;
    j["triangles"] = s.triangles;
    j["full_resolution_triangles"] = s.fullResolutionTriangles;
    j["area_mm2"] = number(s.area);
    j["components"] = s.components;
    j["thickness_mm"] = Json{{"min", measured ? number(t.min) : Json(nullptr)},
                             {"mean", measured ? number(t.mean) : Json(nullptr)},
                             {"max", measured ? number(t.max) : Json(nullptr)},
                             {"samples", t.samples}};
    j["voxel_set_size"] = s.voxelSetSize;
    layers.push_back(std::move(j));
  }
  return layers;
}

}  // namespace

Json makeLayerReport(const LayerReportInputs& inputs, const LayerJobOptions& options,
                     const LayerJobResult& result) {
  const std::vector<LayerSummary> summaries = layerSummaries(result.layers);
  if (!inputs.layerFiles.empty() && inputs.layerFiles.size() != summaries.size()) {
    throw InvalidInput(
        "layer file names do not match the layers: " + std::to_string(inputs.layerFiles.size()) +
        " names for " + std::to_string(summaries.size()) +
        " layers; pass one name per layer surface");
  }
  Json report;
  report["report"] = "curvedslicer layers";
  report["format_version"] = kLayerReportFormatVersion;
  report["inputs"] = inputsJson(inputs, options, result);
  report["mesh"] = meshJson(inputs, result);
  report["start_surface"] = Json{{"triangles", result.source.triangleCount()},
                                 {"area_mm2", number(surfaceArea(result.source))}};
  report["grid"] = gridJson(result);
  report["field"] = fieldJson(result);
  report["warnings"] = result.warnings;
  Json stages = Json::object();
  for (const StageTime& st : result.stageTimes) stages[st.name] = number(st.seconds);
  Json stagePeaks = Json::object();
  for (const StageTime& st : result.stageTimes) stagePeaks[st.name] = st.peakMemoryBytes;
  report["timing"] = Json{{"stage_seconds", stages},
                          {"total_seconds", number(result.totalSeconds)},
                          {"stage_peak_memory_bytes", stagePeaks}};
  report["peak_memory_bytes"] = result.peakMemoryBytes;
  const std::size_t cells = result.voxelization.grid.geometry.cellCount();
  report["peak_memory_bytes_per_cell"] =
      cells > 0 ? number(static_cast<double>(result.peakMemoryBytes) / static_cast<double>(cells))
                : Json(nullptr);
  std::size_t voxelSetPoints = 0;
  for (const LayerSummary& s : summaries) voxelSetPoints += s.voxelSetSize;
  report["outputs"] =
      Json{{"layer_count", summaries.size()},
           {"voxel_sets_file",
            inputs.voxelSetsFile.empty() ? Json(nullptr) : Json(inputs.voxelSetsFile)},
           {"voxel_set_points", voxelSetPoints},
           {"layer_batches", result.layers.batches},
           {"largest_layer_batch_crossed_cubes", result.layers.largestBatchCrossings}};
  const LayerExtractionStats& ls = result.layers.stats;
  report["layer_simplification"] = Json{
      {"enabled", options.layers.simplification.enabled},
      {"tolerance_mm",
       options.layers.simplification.enabled ? number(ls.simplificationTolerance) : Json(nullptr)},
      {"full_resolution_triangles", ls.fullResolutionTriangles},
      {"triangles", ls.simplifiedTriangles},
      {"layers_kept_full_resolution", ls.layersKeptFull},
      {"seconds", number(ls.simplificationSeconds)}};
  report["layers"] = layersJson(inputs, summaries);
  return report;
}

std::string formatLayerReport(const nlohmann::ordered_json& report) {
  return report.dump(2) + "\n";
}

}  // namespace curvedslicer
