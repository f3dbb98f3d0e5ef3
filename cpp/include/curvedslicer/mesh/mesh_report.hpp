// Mesh diagnostics: the report a user sees before slicing (open edges, non-manifold edges,
// degenerate triangles, inconsistent orientation, volume, bounding box). Cost O(n log n).
#pragma once

#include <cstddef>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

struct MeshReport {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t openEdges = 0;            ///< edges used by exactly one triangle
  std::size_t nonManifoldEdges = 0;     ///< edges used by three or more triangles
  std::size_t degenerateTriangles = 0;  ///< repeated vertex index or area below 1e-12·diag²
  /// Manifold edges whose two triangles traverse them in the same direction.
  std::size_t inconsistentEdges = 0;
  std::size_t components = 0;  ///< edge-connected components
  double area = 0.0;           ///< mm²
  double volume = 0.0;         ///< mm³, signed (negative: inward-oriented)
  Aabb bounds;                 ///< part frame
  /// Part frame: the box of the open, non-manifold and inconsistent edges' end points (where a
  /// fill rule may have to guess); empty when the mesh has none.
  Aabb defectBounds;

  bool closed() const { return openEdges == 0 && nonManifoldEdges == 0; }
  bool consistentlyOriented() const { return inconsistentEdges == 0; }
};

MeshReport analyzeMesh(const TriMesh& mesh);

}  // namespace curvedslicer
