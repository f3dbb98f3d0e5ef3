// Simplification of a layer surface within a stated distance of the full-resolution surface.
//
// Marching tetrahedra give about 4–5 triangles per crossed dual-grid cube, most of them slivers,
// whatever the surface's curvature. This step removes triangles by edge collapse (CGAL
// Surface_mesh_simplification: Lindstrom & Turk, "Fast and memory efficient polygonal
// simplification", IEEE Visualization 1998, for the cost and placement) and accepts a collapse
// only if (own filter, layer_simplification.cpp):
//  - the new vertex lies within ε of the full-resolution surface (closest-point query on a
//    TriangleBvh of the full surface),
//  - the points of the barycentric grid of step 1/3 on every triangle the collapse creates lie
//    within 0.75·ε of it (the margin covers the surface bulging between samples a third of an
//    edge apart),
//  - no new triangle is a sliver (sine of its angles ≥ 1e-6) or turns more than 60° from the
//    triangle it replaces.
// Bound: vertices exactly within ε; triangle interiors within ε at the checked samples and, as
// measured by the tests at denser samples (a grid of step 1/8), within ε everywhere they looked —
// a sampled bound, not a proof. CGAL's Polyhedral_envelope_filter would give a proof (every new
// triangle inside the union of ε-prisms of the input), but without GMP its exact predicates fall
// back to boost::multiprecision rationals on every nearly coplanar test — i.e. on every flat layer
// — and the custom_base example's layer stage had not finished after 11 minutes (3.5 CPU minutes
// under load), the stacks in those predicates; hence the sampled filter.
// The rim is kept exactly: border edges (the rim on the part surface after clipping, or the end
// of the field) are constrained, so border vertices neither move nor merge and border edges are
// not collapsed. Vertices where two fans of triangles meet at one point (the rim touching itself)
// are split for the collapse, held fixed with all their edges, and welded again afterwards.
// Preconditions: finite coordinates; triangles consistently oriented (layer surfaces are); no
// edge shared by more than two triangles — a surface that is not an oriented 2-manifold with
// boundary after the vertex split is returned unchanged (`keptFull`).
// Cost: O(T log T) for T input triangles (priority queue of edges) plus about 10–30 hinted
// closest-point queries per accepted collapse; memory: the CGAL mesh and a hierarchy over the
// input while the step runs (a few hundred bytes per input triangle). Measured on the bunny in
// tests/bench/README.md §3.
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

/// Simplifies `surface` (part frame, mm; indexed, no degenerate triangles) so that the result lies
/// within `tolerance` mm of it (vertices exactly, triangles at samples; see the file comment) and
/// its border is unchanged.
/// Deterministic: the result depends only on the input (vertex and triangle order included).
/// @throws InvalidInput if `tolerance` is not positive and finite.
SimplifiedSurface simplifyLayerSurface(const TriMesh& surface, double tolerance);

/// The tolerance `options` asks for on a grid of voxel edge `voxelSize` (mm).
/// @throws InvalidInput for a negative or non-finite tolerance.
double resolveLayerTolerance(const LayerSimplificationOptions& options, double voxelSize);

}  // namespace curvedslicer
