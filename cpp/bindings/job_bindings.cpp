// The jobs of `_curvedslicer`: the layer job (pipeline/layer_pipeline.hpp), the plan job and the
// plan stage alone (pipeline/plan_job.hpp, which records the plan's parameters and provenance).
// Each takes a model as numpy arrays (vertices (n, 3) float64 mm, part frame; triangles (m, 3)
// int; face ids (m,) or None) and one options object (option_bindings.cpp); it runs without the
// GIL and reports to `progress(stage, fraction) -> bool | None` (binding_helpers.hpp).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "binding_helpers.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/pipeline/layer_pipeline.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"
#include "curvedslicer/pipeline/report_json.hpp"
#include "curvedslicer/plan/plan_io.hpp"

namespace curvedslicer::bindings {

namespace {

// ---- results -------------------------------------------------------------------------------

py::dict thicknessDict(const ThicknessStats& t) {
  py::dict d;
  d["samples"] = t.samples;
  if (t.samples == 0) {
    d["min"] = py::none();
    d["mean"] = py::none();
    d["max"] = py::none();
  } else {
    d["min"] = t.min;
    d["mean"] = t.mean;
    d["max"] = t.max;
  }
  return d;
}

py::list layersList(const LayersResult& layers) {
  py::list out;
  for (const LayerSurface& s : layers.surfaces) {
    py::dict l;
    l["index"] = s.index;
    l["height"] = s.level;
    l["vertices"] = verticesArray(s.mesh);
    l["triangles"] = trianglesArray(s.mesh);
    l["area"] = s.area;
    l["components"] = s.components;
    l["thickness"] = thicknessDict(s.thicknessToPrevious);
    out.append(l);
  }
  return out;
}

py::dict gridDict(const LayerJobResult& r) {
  const GridGeometry& g = r.voxelization.grid.geometry;
  py::dict grid;
  grid["dims"] = py::make_tuple(g.dims.x(), g.dims.y(), g.dims.z());
  grid["cells"] = g.cellCount();
  grid["inside_voxels"] = r.voxelization.grid.insideCount;
  grid["voxel_size"] = g.voxelSize;
  grid["reached_voxels"] = r.field.reachedCount;
  grid["unreached_voxels"] = r.field.unreached.count;
  grid["max_distance"] = r.field.maxDistance;
  return grid;
}

py::dict layerResultDict(const LayerJobResult& r, const LayerJobOptions& options,
                         const LayerReportInputs& inputs) {
  py::dict out;
  out["layers"] = layersList(r.layers);
  out["grid"] = gridDict(r);
  py::list times;
  for (const StageTime& t : r.stageTimes) times.append(py::make_tuple(t.name, t.seconds));
  out["stage_times"] = times;
  out["total_seconds"] = r.totalSeconds;
  out["peak_memory_bytes"] = r.peakMemoryBytes;
  out["start_description"] = r.startDescription;
  out["model"] = meshDict(r.clean.mesh);
  out["source"] = meshDict(r.source);
  out["report_json"] = formatLayerReport(makeLayerReport(inputs, options, r));
  return out;
}

py::dict planStatsDict(const PlanResult& result) {
  const PlanStats& s = result.stats;
  py::dict d;
  d["paths"] = result.plan.pathCount();
  d["points"] = result.plan.pointCount();
  d["arc_length_mm"] = s.arcLength;
  d["travel_mm"] = s.travel;
  d["layers_without_paths"] = s.layersWithoutPaths;
  d["dropped_fragments"] = s.droppedFragments;
  d["seams_too_close"] = s.seamsTooClose;
  d["max_fit_deviation_mm"] = s.maxFitDeviation;
  d["deposition_fallbacks"] = s.deposition.normalFallbacks;
  d["deposition_growth_corrections"] = s.deposition.growthCorrections;
  d["deposition_normals_overruled"] = s.deposition.normalsOverruled;
  py::list times;
  for (const PlanStageTime& t : s.stageTimes) times.append(py::make_tuple(t.name, t.seconds));
  d["stage_times"] = times;
  return d;
}

py::dict planResultDict(const PlanResult& result) {
  py::dict d;
  d["plan_json"] = formatPlanJson(result.plan);
  d["stats"] = planStatsDict(result);
  return d;
}

// ---- inputs --------------------------------------------------------------------------------

std::vector<LayerSurface> layerSurfaces(const py::list& layers) {
  std::vector<LayerSurface> surfaces;
  surfaces.reserve(layers.size());
  for (const py::handle& item : layers) {
    const auto layer = py::reinterpret_borrow<py::dict>(item);
    LayerSurface s;
    s.index = layer["index"].cast<int>();
    s.level = layer["height"].cast<double>();
    s.mesh = toTriMesh(layer["vertices"].cast<DoubleArray>(), layer["triangles"].cast<IntArray>(),
                       std::nullopt, "layer");
    surfaces.push_back(std::move(s));
  }
  return surfaces;
}

// ---- jobs ----------------------------------------------------------------------------------
// Options arrive by value: the job runs without the GIL, so it must not share them with Python.

py::dict runLayerJobPy(const DoubleArray& vertices, const IntArray& triangles,
                       const std::optional<IntArray>& faceIds, LayerJobOptions options,
                       const std::string& modelName, const std::string& startSpec,
                       const py::object& progress) {
  validateLayerJobOptions(options);
  const TriMesh model = toTriMesh(vertices, triangles, faceIds, "model");
  const LayerJobResult result = runWithProgress(
      progress, [&](Progress p) { return runLayerJob(model, options, std::move(p)); });
  LayerReportInputs inputs;
  inputs.modelPath = modelName;
  inputs.modelFileTriangles = model.triangleCount();
  inputs.startSpec = startSpec.empty() ? options.start.describe() : startSpec;
  return layerResultDict(result, options, inputs);
}

py::dict runPlanJobPy(const DoubleArray& vertices, const IntArray& triangles,
                      const std::optional<IntArray>& faceIds, PlanJobOptions options,
                      const py::object& progress) {
  validatePlanJobOptions(options);
  const TriMesh model = toTriMesh(vertices, triangles, faceIds, "model");
  const PlanJobResult result = runWithProgress(
      progress, [&](Progress p) { return runPlanJob(model, options, std::move(p)); });
  py::dict d = planResultDict(result.planned);
  d["layer_files"] = result.layerFiles;
  d["total_seconds"] = result.totalSeconds;
  if (options.thinWall) {
    d["layers"] = py::none();
  } else {
    LayerReportInputs inputs;
    inputs.modelPath = options.modelName;
    inputs.modelFileTriangles = model.triangleCount();
    inputs.startSpec = options.startSpec;
    d["layers"] = layerResultDict(result.layers, options.layerJob, inputs);
  }
  return d;
}

py::dict planLayersPy(const py::list& layers, const std::optional<DoubleArray>& startVertices,
                      const std::optional<IntArray>& startTriangles, PlanJobOptions options,
                      const py::object& progress) {
  validatePlanJobOptions(options);
  const std::vector<LayerSurface> surfaces = layerSurfaces(layers);
  TriMesh startSurface;
  if (startVertices && startTriangles) {
    startSurface = toTriMesh(*startVertices, *startTriangles, std::nullopt, "start surface");
  }
  const PlanResult result = runWithProgress(progress, [&](Progress p) {
    return planOnLayers(surfaces, startSurface, options, std::move(p));
  });
  return planResultDict(result);
}

py::dict planThinWallPy(const DoubleArray& vertices, const IntArray& triangles,
                        PlanJobOptions options, const py::object& progress) {
  if (!options.thinWall) {
    throw InvalidInput(
        "plan_thin_wall needs options.thin_wall: None; pass "
        "PlanJobOptions(thin_wall=ThinWallOptions(...)), or call plan_layers");
  }
  validatePlanJobOptions(options);
  const TriMesh surface =
      cleanMesh(toTriMesh(vertices, triangles, std::nullopt, "wall surface")).mesh;
  const PlanResult result = runWithProgress(
      progress, [&](Progress p) { return planOnLayers({}, surface, options, std::move(p)); });
  return planResultDict(result);
}

}  // namespace

void registerJobBindings(py::module_& m) {
  m.def("run_layer_job", &runLayerJobPy,
        "Runs the layer job (paper §2) on a mesh with options: LayerJobOptions; returns a dict "
        "with 'layers' (index, height mm, vertices (n,3) mm, triangles (m,3), area mm², "
        "components, thickness stats), 'grid' (dims, cells, inside/reached/unreached voxels, "
        "voxel_size, max_distance), 'stage_times' [(stage, s)], 'total_seconds', "
        "'peak_memory_bytes', 'start_description', 'model' (the cleaned mesh), 'source' (the "
        "start-surface triangles) and 'report_json' (model_name and start_spec are recorded "
        "there; start_spec '' = the start's description). progress(stage, fraction) -> False "
        "or raise to cancel (raises Cancelled).",
        py::arg("vertices"), py::arg("triangles"), py::arg("face_ids") = py::none(), py::kw_only(),
        py::arg("options"), py::arg("model_name") = "", py::arg("start_spec") = "",
        py::arg("progress") = py::none());

  m.def("run_plan_job", &runPlanJobPy,
        "The whole plan job (pipeline/plan_job.hpp runPlanJob): the layer job, then paths on "
        "the layers; or, with options.thin_wall, the model's surface planned as a thin wall. "
        "Returns {plan_json (parameters and provenance recorded; each plan layer names its "
        "layer file), stats, layer_files, total_seconds, layers (as run_layer_job returns; None "
        "for a thin wall)}.",
        py::arg("vertices"), py::arg("triangles"), py::arg("face_ids") = py::none(), py::kw_only(),
        py::arg("options"), py::arg("progress") = py::none());

  m.def("plan_layers", &planLayersPy,
        "Paths on curved layers of an earlier layer job (planOnLayers, paper §3.1). layers: "
        "list of dicts {index (1-based), height mm, vertices (n,3), triangles (m,3)} bottom to "
        "top; start_vertices/start_triangles: the start surface (deposited material under "
        "layer 1, may be None); options: PlanJobOptions (its layer_job as the layers were run "
        "with: layer thickness, voxel size and field method are recorded in the plan, with "
        "model_name and start_spec). Returns {plan_json, stats}.",
        py::arg("layers"), py::kw_only(), py::arg("start_vertices") = py::none(),
        py::arg("start_triangles") = py::none(), py::arg("options"),
        py::arg("progress") = py::none());

  m.def("plan_thin_wall", &planThinWallPy,
        "Paths of a thin wall (planOnLayers with options.thin_wall, the paper's turbine base) "
        "on its surface (vertices (n,3) mm, triangles (m,3); cleaned first): one bead per plan "
        "layer at geodesic distance k·bead_spacing from the wall's edge. Returns {plan_json, "
        "stats}.",
        py::arg("vertices"), py::arg("triangles"), py::kw_only(), py::arg("options"),
        py::arg("progress") = py::none());
}

}  // namespace curvedslicer::bindings
