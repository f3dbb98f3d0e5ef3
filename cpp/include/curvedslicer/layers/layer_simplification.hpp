// Simplification of a layer surface within a stated distance of the full-resolution surface.
//
// Marching tetrahedra give about 4–5 triangles per crossed dual-grid cube, most of them slivers,
// whatever the surface's curvature. This step removes triangles by edge collapse (CGAL
// Surface_mesh_simplification, Lindstrom & Turk, "Fast and memory efficient polygonal
// simplification", IEEE Visualization 1998: cost and placement) and accepts a collapse only if
// every triangle it creates lies inside the polyhedral envelope of the input surface (CGAL
// Polyhedral_envelope; Wang, Schneider, Hu, Attene & Panozzo, "Exact and efficient polyhedral
// envelope containment check", ACM TOG 39(4), 2020): the union of one prism per input triangle,
// each contained in the triangle's offset by the tolerance ε, tested with exact predicates.
// Bound: every point of the simplified surface lies within ε of the full-resolution surface.
// (The converse direction is not bounded by the test; the collapses keep the surface's border and
// every vertex lies in the envelope, so a hole would need to open inside the surface.)
// The rim is kept exactly: border edges (the rim on the part surface after clipping, or the end
// of the field) are constrained, so border vertices neither move nor merge and border edges are
// not collapsed. Vertices where two fans of triangles meet at one point (the rim touching itself)
// are split for the collapse, held fixed with all their edges, and welded again afterwards.
// Preconditions: finite coordinates; triangles consistently oriented (layer surfaces are); no
// edge shared by more than two triangles — a surface that is not an oriented 2-manifold with
// boundary after the vertex split is returned unchanged (`keptFull`).
// Cost: O(T log T) for T input triangles (priority queue of edges), the envelope ~ a few hundred
// bytes per input triangle while the step runs; measured on the bunny in tests/bench/README.md §3.
#pragma once

#include <cstddef>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

/// Default tolerance of the layer simplification, in voxel edge lengths L.
inline constexpr double kDefaultLayerToleranceVoxels = 0.05;

struct LayerSimplificationOptions {
  /// Simplify the layer surfaces (false: keep the marching-tetrahedra resolution).
  bool enabled = true;
  /// ε, mm: largest distance of the simplified surface from the full-resolution one (≥ 0);
  /// 0 means automatic, kDefaultLayerToleranceVoxels × L (L the voxel edge length).
  double tolerance = 0.0;
};

/// One simplified surface with its diagnostics.
struct SimplifiedSurface {
  TriMesh mesh;  ///< part frame, indexed, orientation of the input
  std::size_t trianglesBefore = 0, trianglesAfter = 0;
  std::size_t verticesBefore = 0, verticesAfter = 0;
  std::size_t fixedVertices = 0;  ///< border and non-manifold vertices held in place
  bool keptFull = false;          ///< the input was not a 2-manifold; returned unchanged
};

/// Simplifies `surface` (part frame, mm; indexed, no degenerate triangles) so that every point of
/// the result lies within `tolerance` mm of it and its border is unchanged (see the file comment).
/// Deterministic: the result depends only on the input (vertex and triangle order included).
/// @throws InvalidInput if `tolerance` is not positive and finite.
SimplifiedSurface simplifyLayerSurface(const TriMesh& surface, double tolerance);

/// The tolerance `options` asks for on a grid of voxel edge `voxelSize` (mm).
/// @throws InvalidInput for a negative or non-finite tolerance.
double resolveLayerTolerance(const LayerSimplificationOptions& options, double voxelSize);

}  // namespace curvedslicer
