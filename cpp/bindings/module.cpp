// Python module `_curvedslicer`: the core for the FreeCAD workbench and for scripts.
//
// Thin conversions only: meshes in and out as numpy arrays (vertices float64 (n, 3) in mm, part
// frame; triangles int32 (m, 3); face ids int32 (m,)), the options structs as classes
// (option_bindings.cpp), the layer and plan jobs (job_bindings.cpp), OpenCASCADE tessellation of
// BREP text and CAD files, mesh files, and the grid/memory estimate of the task panel. Long calls
// release the GIL; the progress callback `progress(stage: str, fraction: float) -> bool | None`
// runs on the calling thread with the GIL re-acquired; returning False or raising cancels the job,
// which then raises `Cancelled`. Core errors arrive as Python exceptions derived from
// `CurvedSlicerError` with the core's message.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <limits>
#include <optional>
#include <string>

#include "binding_helpers.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/mesh/mesh_report.hpp"
#include "curvedslicer/occ/shape_tessellation.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace py = pybind11;
using namespace curvedslicer;
using namespace curvedslicer::bindings;

namespace {

// ---- estimates -----------------------------------------------------------------------------

py::dict estimateGridPy(const DoubleArray& vertices, const IntArray& triangles,
                        VoxelizeOptions options) {  // a copy: used without the GIL
  const TriMesh model = toTriMesh(vertices, triangles, std::nullopt, "model");
  GridEstimate e;
  {
    py::gil_scoped_release release;
    e = estimateGrid(model, options);
  }
  py::dict d;
  d["dims"] =
      py::make_tuple(static_cast<std::int64_t>(e.dims[0]), static_cast<std::int64_t>(e.dims[1]),
                     static_cast<std::int64_t>(e.dims[2]));
  d["cells"] = static_cast<std::int64_t>(e.cells);
  d["bytes"] = e.bytes;
  d["budget_bytes"] = e.budgetBytes;
  d["fits"] = e.fits;
  d["message"] = e.message;
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

  registerOptionBindings(m);
  registerJobBindings(m);

  m.def("estimate_grid", &estimateGridPy,
        "Voxel grid a job would use with options: VoxelizeOptions (planGrid, no allocation): "
        "dict with dims, cells, bytes (cells × bytes_per_cell), budget_bytes, fits and message "
        "(the core's ResourceLimit text with a voxel size that fits, when it does not).",
        py::arg("vertices"), py::arg("triangles"), py::kw_only(), py::arg("options"));

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
      py::arg("brep"), py::kw_only(), py::arg("deflection"),
      py::arg("angular_deflection") = TessellationOptions{}.angularDeflection);

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
      py::kw_only(), py::arg("deflection"),
      py::arg("angular_deflection") = TessellationOptions{}.angularDeflection,
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
