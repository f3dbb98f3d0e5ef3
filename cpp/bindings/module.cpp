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

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// ---- numpy <-> TriMesh ---------------------------------------------------------------------

TriMesh toTriMesh(const DoubleArray& vertices, const IntArray& triangles,
                  const std::optional<IntArray>& faceIds, const char* what) {
  const std::string name(what);
  if (vertices.ndim() != 2 || vertices.shape(1) != 3) {
    throw InvalidInput(name + " vertices must be an (n, 3) array: ndim " +
                       std::to_string(vertices.ndim()) + "; pass numpy.asarray(points)");
  }
  if (triangles.ndim() != 2 || triangles.shape(1) != 3) {
    throw InvalidInput(name + " triangles must be an (m, 3) array: ndim " +
                       std::to_string(triangles.ndim()) + "; pass vertex indices per triangle");
  }
  TriMesh mesh;
  const auto n = static_cast<std::size_t>(vertices.shape(0));
  const auto m = static_cast<std::size_t>(triangles.shape(0));
  const double* v = vertices.data();
  const std::int64_t* t = triangles.data();
  mesh.vertices.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    mesh.vertices.emplace_back(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  mesh.triangles.reserve(m);
  for (std::size_t i = 0; i < 3 * m; ++i) {
    if (t[i] < 0 || t[i] >= static_cast<std::int64_t>(n)) {
      throw InvalidInput(name + " triangle index out of range: " + std::to_string(t[i]) +
                         " (vertices: " + std::to_string(n) + "); pass 0-based vertex indices");
    }
  }
  for (std::size_t i = 0; i < m; ++i) {
    mesh.triangles.emplace_back(static_cast<int>(t[3 * i]), static_cast<int>(t[3 * i + 1]),
                                static_cast<int>(t[3 * i + 2]));
  }
  if (faceIds) {
    if (faceIds->ndim() != 1 || static_cast<std::size_t>(faceIds->shape(0)) != m) {
      throw InvalidInput(
          name + " face ids must have one entry per triangle: " + std::to_string(faceIds->size()) +
          " for " + std::to_string(m) + " triangles; pass an (m,) array or None");
    }
    const std::int64_t* f = faceIds->data();
    mesh.faceIds.assign(f, f + m);
  }
  return mesh;
}

py::array_t<double> verticesArray(const TriMesh& mesh) {
  py::array_t<double> out({static_cast<py::ssize_t>(mesh.vertices.size()), py::ssize_t{3}});
  double* p = out.mutable_data();
  for (const Vec3& v : mesh.vertices) {
    *p++ = v.x();
    *p++ = v.y();
    *p++ = v.z();
  }
  return out;
}

py::array_t<std::int32_t> trianglesArray(const TriMesh& mesh) {
  py::array_t<std::int32_t> out({static_cast<py::ssize_t>(mesh.triangles.size()), py::ssize_t{3}});
  std::int32_t* p = out.mutable_data();
  for (const Vec3i& t : mesh.triangles) {
    *p++ = t.x();
    *p++ = t.y();
    *p++ = t.z();
  }
  return out;
}

py::dict meshDict(const TriMesh& mesh) {
  py::dict d;
  d["vertices"] = verticesArray(mesh);
  d["triangles"] = trianglesArray(mesh);
  if (mesh.faceIds.empty()) {
    d["face_ids"] = py::none();
  } else {
    py::array_t<std::int32_t> ids(static_cast<py::ssize_t>(mesh.faceIds.size()));
    std::copy(mesh.faceIds.begin(), mesh.faceIds.end(), ids.mutable_data());
    d["face_ids"] = ids;
  }
  return d;
}

py::list vec3List(const Vec3& v) {
  py::list l;
  l.append(v.x());
  l.append(v.y());
  l.append(v.z());
  return l;
}

// ---- progress ------------------------------------------------------------------------------

// Wraps a Python callable as the core's callback. Called with the GIL released (the job runs
// without it); re-acquires it, and records a Python exception so it can be named in Cancelled.
struct PythonProgress {
  py::object callable;
  std::string raised;  // "<type>: <message>" of an exception the callable raised

  bool operator()(double fraction, std::string_view stage) {
    py::gil_scoped_acquire gil;
    try {
      py::object answer = callable(std::string(stage), fraction);
      return answer.is_none() || answer.cast<bool>();
    } catch (py::error_already_set& e) {
      raised = std::string(py::str(e.type().attr("__name__"))) + ": " + e.what();
      return false;
    }
  }
};

// Runs `work(progress)` without the GIL; converts a cancellation caused by a raising callback
// into Cancelled naming the Python exception.
template <class Work>
auto runWithProgress(const py::object& callable, Work&& work) {
  if (callable.is_none()) {
    py::gil_scoped_release release;
    return work(Progress{});
  }
  auto state = std::make_shared<PythonProgress>();
  state->callable = callable;
  Progress progress([state](double f, std::string_view s) { return (*state)(f, s); });
  try {
    py::gil_scoped_release release;
    return work(progress);
  } catch (const Cancelled& e) {
    if (!state->raised.empty()) {
      throw Cancelled(std::string(e.what()) + " (the progress callback raised " + state->raised +
                      ")");
    }
    throw;
  }
}

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
        "'model' (the cleaned mesh) and 'report_json'. start: 'build_plate' | 'plane' "
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

  m.def("physical_memory_bytes", &physicalMemoryBytes, "Physical memory of this machine, bytes.");
}
