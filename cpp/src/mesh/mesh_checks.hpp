// Internal helpers shared by mesh_repair.cpp and mesh_report.cpp: input validation and the
// degenerate-area threshold (both must agree so a cleaned mesh reports no degenerate triangle).
#pragma once

#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer::detail {

/// Triangles with area below this (mm²) count as degenerate: 1e-12·diag², diag = bounding-box
/// diagonal in mm.
inline double degenerateAreaThreshold(double diagonal) {
  return 1e-12 * diagonal * diagonal;
}

/// Throws InvalidInput (naming `caller`) for a non-finite vertex or an out-of-range index.
inline void requireValidMesh(const TriMesh& mesh, const std::string& caller) {
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      throw InvalidInput(caller + ": vertex " + std::to_string(i) +
                         " has a non-finite coordinate; repair or re-export the model");
    }
  }
  const auto n = static_cast<long long>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const long long v = mesh.triangles[t][k];
      if (v < 0 || v >= n) {
        throw InvalidInput(caller + ": triangle " + std::to_string(t) +
                           " has a vertex index out of range: " + std::to_string(v) + " (" +
                           std::to_string(n) + " vertices); fix the mesh indices");
      }
    }
  }
}

}  // namespace curvedslicer::detail
