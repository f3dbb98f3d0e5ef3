// Python module `_curvedslicer`: the core for the FreeCAD workbench and for scripts.
//
// Thin conversions only: meshes in and out as numpy arrays (vertices float64 (n, 3) in mm, part
// frame; triangles int32 (m, 3); face ids int32 (m,)), the layer job with every option as a named
// argument, OpenCASCADE tessellation of BREP text and CAD files, mesh files, and the grid/memory
// estimate of the task panel. Long calls release the GIL; the progress callback
// `progress(stage: str, fraction: float) -> bool | None` runs on the calling thread with the GIL
// re-acquired; returning False or raising cancels the job, which then raises `Cancelled`. Core
// errors arrive as Python exceptions derived from `CurvedSlicerError` with the core's message.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "binding_helpers.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/mesh/mesh_report.hpp"
#include "curvedslicer/occ/shape_tessellation.hpp"
#include "curvedslicer/pipeline/layer_pipeline.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/report_json.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace py = pybind11;
using namespace curvedslicer;
using namespace curvedslicer::bindings;

namespace {

// ---- layer job -----------------------------------------------------------------------------

StartSurface makeStart(const std::string& kind,
                       const std::optional<std::vector<double>>& planePoint,
                       const std::optional<std::vector<double>>& planeNormal,
                       const std::optional<std::vector<int>>& faceIds,
                       const std::optional<DoubleArray>& startVertices,
                       const std::optional<IntArray>& startTriangles) {
  if (kind == "build_plate") return StartSurface::buildPlate();
  if (kind == "plane") {
    if (!planePoint || !planeNormal || planePoint->size() != 3 || planeNormal->size() != 3) {
      throw InvalidInput(
          "start plane needs plane_point and plane_normal as 3 numbers each: "
          "missing or wrong length; pass e.g. plane_point=(0, 0, 0), "
          "plane_normal=(0, 0, 1)");
    }
    const auto& p = *planePoint;
    const auto& n = *planeNormal;
    return StartSurface::plane(Vec3(p[0], p[1], p[2]), Vec3(n[0], n[1], n[2]));
  }
  if (kind == "faces") {
    if (!faceIds || faceIds->empty()) {
      throw InvalidInput("start faces missing: none given; pass start_face_ids=[1, 2] (FaceN)");
    }
    return StartSurface::faces(*faceIds);
  }
  if (kind == "mesh") {
    if (!startVertices || !startTriangles) {
      throw InvalidInput(
          "start surface mesh missing: start_vertices/start_triangles not given; "
          "pass the surface as numpy arrays");
    }
    return StartSurface::surface(
        toTriMesh(*startVertices, *startTriangles, std::nullopt, "start surface"));
  }
  throw InvalidInput("unknown start kind: '" + kind +
                     "'; use 'build_plate', 'plane', 'faces' or 'mesh'");
}

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

py::dict resultDict(const LayerJobResult& r, const LayerJobOptions& options,
                    const std::string& modelName, const std::string& startSpec,
                    std::size_t inputTriangles) {
  py::dict out;
  py::list layers;
  for (const LayerSurface& s : r.layers.surfaces) {
    py::dict l;
    l["index"] = s.index;
    l["height"] = s.level;
    l["vertices"] = verticesArray(s.mesh);
    l["triangles"] = trianglesArray(s.mesh);
    l["area"] = s.area;
    l["components"] = s.components;
    l["thickness"] = thicknessDict(s.thicknessToPrevious);
    layers.append(l);
  }
  out["layers"] = layers;
  const GridGeometry& g = r.voxelization.grid.geometry;
  py::dict grid;
  grid["dims"] = py::make_tuple(g.dims.x(), g.dims.y(), g.dims.z());
  grid["cells"] = g.cellCount();
  grid["inside_voxels"] = r.voxelization.grid.insideCount;
  grid["voxel_size"] = g.voxelSize;
  grid["reached_voxels"] = r.field.reachedCount;
  grid["unreached_voxels"] = r.field.unreached.count;
  grid["max_distance"] = r.field.maxDistance;
  out["grid"] = grid;
  py::list times;
  for (const StageTime& t : r.stageTimes) times.append(py::make_tuple(t.name, t.seconds));
  out["stage_times"] = times;
  out["total_seconds"] = r.totalSeconds;
  out["peak_memory_bytes"] = r.peakMemoryBytes;
  out["start_description"] = r.startDescription;
  out["model"] = meshDict(r.clean.mesh);
  out["source"] = meshDict(r.source);
  LayerReportInputs inputs;
  inputs.modelPath = modelName;
  inputs.modelFileTriangles = inputTriangles;
  inputs.startSpec = startSpec;
  out["report_json"] = formatLayerReport(makeLayerReport(inputs, options, r));
  return out;
}

py::dict runLayerJobPy(const DoubleArray& vertices, const IntArray& triangles,
                       const std::optional<IntArray>& faceIds, double layerThickness,
                       double voxelSize, const std::string& start,
                       const std::optional<std::vector<double>>& planePoint,
                       const std::optional<std::vector<double>>& planeNormal,
                       const std::optional<std::vector<int>>& startFaceIds,
                       const std::optional<DoubleArray>& startVertices,
                       const std::optional<IntArray>& startTriangles, const std::string& method,
                       const std::string& alignment, bool capHoles, double memoryBudgetMb,
                       double seedBand, bool clipToSolid, int thicknessSamples, int maxLayers,
                       const std::string& modelName, const std::string& startSpec,
                       const py::object& progress) {
  LayerJobOptions options;
  options.start =
      makeStart(start, planePoint, planeNormal, startFaceIds, startVertices, startTriangles);
  options.voxelize.voxelSize = voxelSize;
  options.voxelize.alignment = parseGridAlignment(alignment);
  options.voxelize.memoryBudgetBytes = memoryBudgetMb * 1024.0 * 1024.0;
  options.geodesic.method = parseGeodesicMethod(method);
  options.geodesic.seedBand = seedBand;
  options.layers.layerThickness = layerThickness;
  options.layers.clipToSolid = clipToSolid;
  options.layers.thicknessSamples = thicknessSamples;
  options.layers.maxLayers = maxLayers;
  options.capHoles = capHoles;
  validateLayerJobOptions(options);
  const TriMesh model = toTriMesh(vertices, triangles, faceIds, "model");
  LayerJobResult result = runWithProgress(
      progress, [&](Progress p) { return runLayerJob(model, options, std::move(p)); });
  return resultDict(result, options, modelName, startSpec.empty() ? start : startSpec,
                    model.triangleCount());
}

// ---- estimates -----------------------------------------------------------------------------

py::dict estimateGridPy(const DoubleArray& vertices, const IntArray& triangles, double voxelSize,
                        const std::string& alignment, double memoryBudgetMb, double bytesPerCell) {
  const TriMesh model = toTriMesh(vertices, triangles, std::nullopt, "model");
  VoxelizeOptions options;
  options.voxelSize = voxelSize;
  options.alignment = parseGridAlignment(alignment);
  options.bytesPerCell = bytesPerCell;
  options.memoryBudgetBytes = memoryBudgetMb * 1024.0 * 1024.0;
  const double budget =
      options.memoryBudgetBytes > 0.0 ? options.memoryBudgetBytes : 0.8 * physicalMemoryBytes();
  VoxelizeOptions unlimited = options;
  unlimited.memoryBudgetBytes = std::numeric_limits<double>::max();
  GridGeometry geometry;
  {
    py::gil_scoped_release release;
    geometry = planGrid(model, unlimited);
  }
  py::dict d;
  d["dims"] = py::make_tuple(geometry.dims.x(), geometry.dims.y(), geometry.dims.z());
  d["cells"] = geometry.cellCount();
  d["bytes"] = static_cast<double>(geometry.cellCount()) * bytesPerCell;
  d["budget_bytes"] = budget;
  d["fits"] = true;
  d["message"] = "";
  try {
    py::gil_scoped_release release;
    (void)planGrid(model, options);
  } catch (const ResourceLimit& e) {
    d["fits"] = false;
    d["message"] = std::string(e.what());
  }
  return d;
}

py::dict analyzeMeshPy(const DoubleArray& vertices, const IntArray& triangles) {
  const MeshReport r = analyzeMesh(toTriMesh(vertices, triangles, std::nullopt, "mesh"));
  py::dict d;
  d["vertices"] = r.vertices;
  d["triangles"] = r.triangles;
  d["open_edges"] = r.openEdges;
  d["non_manifold_edges"] = r.nonManifoldEdges;
  d["degenerate_triangles"] = r.degenerateTriangles;
  d["inconsistent_edges"] = r.inconsistentEdges;
  d["components"] = r.components;
  d["area"] = r.area;
  d["volume"] = r.volume;
  d["closed"] = r.closed();
  d["bounds_min"] = r.bounds.empty() ? py::object(py::none()) : py::object(vec3List(r.bounds.min));
  d["bounds_max"] = r.bounds.empty() ? py::object(py::none()) : py::object(vec3List(r.bounds.max));
  return d;
}

CadFormat parseCadFormat(const std::string& name) {
  if (name == "auto") return CadFormat::Auto;
  if (name == "step") return CadFormat::Step;
  if (name == "iges") return CadFormat::Iges;
  if (name == "brep") return CadFormat::Brep;
  throw InvalidInput("unknown CAD format: '" + name + "'; use 'auto', 'step', 'iges' or 'brep'");
}

}  // namespace

PYBIND11_MODULE(_curvedslicer, m) {
  m.doc() = "CurvedSlicer core: curved layers for wire-arc additive manufacturing";
  m.attr("__version__") = CURVEDSLICER_VERSION;

  // Base first: pybind11 tries translators newest first, so the derived classes win.
  static py::exception<Error> errorBase(m, "CurvedSlicerError");
  py::register_exception<InvalidInput>(m, "InvalidInput", errorBase.ptr());
  py::register_exception<IoError>(m, "IoError", errorBase.ptr());
  py::register_exception<ResourceLimit>(m, "ResourceLimit", errorBase.ptr());
  py::register_exception<NumericalFailure>(m, "NumericalFailure", errorBase.ptr());
  py::register_exception<Cancelled>(m, "Cancelled", errorBase.ptr());

  m.def("run_layer_job", &runLayerJobPy,
        "Runs the layer job (paper §2) on a mesh; returns a dict with 'layers' (index, height "
        "mm, vertices (n,3) mm, triangles (m,3), area mm², components, thickness stats), 'grid' "
        "(dims, cells, inside/reached/unreached voxels, voxel_size, max_distance), "
        "'stage_times' [(stage, s)], 'total_seconds', 'peak_memory_bytes', 'start_description', "
        "'model' (the cleaned mesh), 'source' (the start-surface triangles) and 'report_json'. "
        "start: 'build_plate' | 'plane' "
        "(plane_point, plane_normal) | 'faces' (start_face_ids: the model's face ids) | 'mesh' "
        "(start_vertices, start_triangles). memory_budget_mb 0 = 80 % of physical memory. "
        "progress(stage, fraction) -> False or raise to cancel (raises Cancelled).",
        py::arg("vertices"), py::arg("triangles"), py::arg("face_ids") = py::none(), py::kw_only(),
        py::arg("layer_thickness"), py::arg("voxel_size"), py::arg("start") = "build_plate",
        py::arg("plane_point") = py::none(), py::arg("plane_normal") = py::none(),
        py::arg("start_face_ids") = py::none(), py::arg("start_vertices") = py::none(),
        py::arg("start_triangles") = py::none(), py::arg("method") = "anyangle",
        py::arg("alignment") = "pca", py::arg("cap_holes") = false,
        py::arg("memory_budget_mb") = 0.0, py::arg("seed_band") = 0.0,
        py::arg("clip_to_solid") = true, py::arg("thickness_samples") = 4096,
        py::arg("max_layers") = 100000, py::arg("model_name") = "", py::arg("start_spec") = "",
        py::arg("progress") = py::none());

  m.def("estimate_grid", &estimateGridPy,
        "Voxel grid a job would use (planGrid, no allocation): dict with dims, cells, bytes "
        "(cells × bytes_per_cell), budget_bytes, fits and message (the core's ResourceLimit text "
        "with a voxel size that fits, when it does not).",
        py::arg("vertices"), py::arg("triangles"), py::kw_only(), py::arg("voxel_size"),
        py::arg("alignment") = "pca", py::arg("memory_budget_mb") = 0.0,
        py::arg("bytes_per_cell") = VoxelizeOptions{}.bytesPerCell);

  m.def("analyze_mesh", &analyzeMeshPy,
        "Mesh diagnostics: open/non-manifold/inconsistent edges, components, area mm², volume "
        "mm³, bounds.",
        py::arg("vertices"), py::arg("triangles"));

  m.def(
      "tessellate_brep",
      [](const std::string& brep, double deflection, double angularDeflection) {
        TessellationOptions options{deflection, angularDeflection};
        TriMesh mesh;
        {
          py::gil_scoped_release release;
          mesh = tessellateBrepText(brep, options);
        }
        return meshDict(mesh);
      },
      "Tessellates BREP text (shape.exportBrepToString()); dict with vertices, triangles and "
      "face_ids (FreeCAD FaceN, 1-based). deflection: chord error, mm; angular_deflection: rad.",
      py::arg("brep"), py::kw_only(), py::arg("deflection"), py::arg("angular_deflection") = 0.5);

  m.def(
      "tessellate_cad_file",
      [](const std::string& path, double deflection, double angularDeflection,
         const std::string& format) {
        TessellationOptions options{deflection, angularDeflection};
        const CadFormat f = parseCadFormat(format);
        TriMesh mesh;
        {
          py::gil_scoped_release release;
          mesh = tessellateCadFile(path, f, options);
        }
        return meshDict(mesh);
      },
      "Reads a STEP/IGES/BREP file and tessellates it (see tessellate_brep).", py::arg("path"),
      py::kw_only(), py::arg("deflection"), py::arg("angular_deflection") = 0.5,
      py::arg("format") = "auto");

  m.def(
      "count_brep_faces", [](const std::string& brep) { return countBrepFaces(brep); },
      "Number of faces of a BREP shape (the largest FaceN).", py::arg("brep"));

  m.def("deflection_for_voxel_size", &deflectionForVoxelSize,
        "Chord error (mm) the workbench tessellates with at voxel size L (mm): L/4.",
        py::arg("voxel_size"));

  m.def(
      "read_mesh", [](const std::string& path) { return meshDict(readMesh(path)); },
      "Reads an STL or OBJ file: dict with vertices, triangles, face_ids (file positions).",
      py::arg("path"));

  m.def(
      "write_mesh",
      [](const std::string& path, const DoubleArray& vertices, const IntArray& triangles,
         const std::optional<IntArray>& faceIds) {
        const TriMesh mesh = toTriMesh(vertices, triangles, faceIds, "mesh");
        py::gil_scoped_release release;
        writeMesh(path, mesh);
      },
      "Writes a mesh atomically; the format follows the extension (.stl binary, .obj, .ply).",
      py::arg("path"), py::arg("vertices"), py::arg("triangles"), py::arg("face_ids") = py::none());

  registerPlanBindings(m);

  m.def("physical_memory_bytes", &physicalMemoryBytes, "Physical memory of this machine, bytes.");
}
