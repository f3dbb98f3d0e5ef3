// Conversions shared by the pybind11 sources of `_curvedslicer` (internal to cpp/bindings): numpy
// arrays <-> TriMesh, small vectors, and the progress wrapper that runs a core call without the
// GIL while a Python callable reports progress (re-acquiring the GIL) and may cancel it.
// Preconditions: called with the GIL held. Cost: one copy of the arrays.
#pragma once

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer::bindings {

namespace py = pybind11;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

// ---- numpy <-> TriMesh ---------------------------------------------------------------------

inline TriMesh toTriMesh(const DoubleArray& vertices, const IntArray& triangles,
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

inline py::array_t<double> verticesArray(const TriMesh& mesh) {
  py::array_t<double> out({static_cast<py::ssize_t>(mesh.vertices.size()), py::ssize_t{3}});
  double* p = out.mutable_data();
  for (const Vec3& v : mesh.vertices) {
    *p++ = v.x();
    *p++ = v.y();
    *p++ = v.z();
  }
  return out;
}

inline py::array_t<std::int32_t> trianglesArray(const TriMesh& mesh) {
  py::array_t<std::int32_t> out({static_cast<py::ssize_t>(mesh.triangles.size()), py::ssize_t{3}});
  std::int32_t* p = out.mutable_data();
  for (const Vec3i& t : mesh.triangles) {
    *p++ = t.x();
    *p++ = t.y();
    *p++ = t.z();
  }
  return out;
}

inline py::dict meshDict(const TriMesh& mesh) {
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

inline py::list vec3List(const Vec3& v) {
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
inline auto runWithProgress(const py::object& callable, Work&& work) {
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

/// Registers the plan JSON, cell, motion and export functions (plan_bindings.cpp).
void registerPlanBindings(py::module_& m);
/// Registers the options classes (option_bindings.cpp); before the functions that use them.
void registerOptionBindings(py::module_& m);
/// Registers run_layer_job, run_plan_job, plan_layers and plan_thin_wall (job_bindings.cpp).
void registerJobBindings(py::module_& m);

}  // namespace curvedslicer::bindings
