// Simplification of a layer surface within a stated distance of the full-resolution surface.
//
// Marching tetrahedra give about 4–5 triangles per crossed dual-grid cube, most of them slivers,
// whatever the surface's curvature. This step removes vertices by half-edge collapse (a vertex u
// merged into a neighbour v, which keeps its position), ordered and bounded by quadric error
// metrics (Garland & Heckbert, "Surface simplification using quadric error metrics", SIGGRAPH
// 1997): every vertex carries the quadric Q of the planes of its ORIGINAL incident triangles (unit
// weight each), a collapse u → v adds Q_u to Q_v, and it is accepted only if
//  - Q_u + Q_v at v's position is at most ε² — the sum of squared distances from v to all original
//    planes merged into it, so v lies within ε of every one of those planes;
//  - no new triangle is a sliver (sine of its angles ≥ 1e-6) or turns more than 60° from the
//    triangle it replaces, and the link condition holds (u and v share exactly the two neighbours
//    of the edge's triangles; v keeps at least three triangles), so the surface stays a manifold
//    with the same topology.
// The collapses run in threshold passes over a flat triangle array (ε²/256, ε²/32, ε²/4, then ε²
// until a pass removes fewer than 1 % of the vertices left, at most 8 passes), each vertex removed
// or collapsed onto at most once per pass — a cheap stand-in for a global priority queue (own
// code; CGAL's Surface_mesh edge collapse with a closest-point filter, the previous version, took
// far too long on the bunny: see docs/METHODS.md).
// Bound. Guaranteed: every vertex of the result is a vertex of the full surface (distance 0), and
// lies within ε of the planes of all original triangles merged into it. Not guaranteed but checked
// by sampling in the tests (a second computation: closest points on the full surface from the
// vertices and a barycentric grid of step 1/8 or 1/4 on every new triangle): triangle interiors
// within ε of the full surface — a plane bound on the corners is not a distance bound on the
// interior, so this is a measured bound, not a proof.
// The rim is kept exactly: border vertices are never removed, so border edges stay as they were.
// Vertices where two fans of triangles meet at one point (the rim touching itself) and vertices of
// a zero-area triangle are never removed either.
// Preconditions: finite coordinates; triangles consistently oriented (layer surfaces are); no
// edge shared by more than two triangles — otherwise the surface is returned unchanged
// (`keptFull`).
// Cost: O(T) per pass for T input triangles (about 6 passes), no search structure; memory about
// 150 bytes per input vertex and 40 per triangle while the step runs. Measured on the bunny in
// tests/bench/README.md §3.
#pragma once

#include <cstddef>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

/// Default tolerance of the layer simplification, in voxel edge lengths L.
inline constexpr double kDefaultLayerToleranceVoxels = 0.05;

/// Longest edge a collapse may create, in voxel edge lengths L. Flat regions would otherwise
/// collapse into a few triangles tens of mm long, on which the planner's surface geodesic (a
/// fast-marching scheme on the mesh) bends the rings: on the branches model's flat base layers
/// that left 6.8 % void instead of 0.3 %.
inline constexpr double kDefaultLayerMaxEdgeVoxels = 3.0;

struct LayerSimplificationOptions {
  /// Simplify the layer surfaces (false: keep the marching-tetrahedra resolution). Off by
  /// default: on the simplified layers of flat boxes the beads are up to 4 % farther apart than
  /// the bead spacing and a box's void share triples (docs/METHODS.md "Lighter layer surfaces").
  bool enabled = false;
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
/// within `tolerance` mm of it (vertices: on it, and within `tolerance` of their merged original
/// planes; triangle interiors checked by sampling in the tests; see the file comment) and its
/// border is unchanged.
/// Deterministic: the result depends only on the input (vertex and triangle order included).
/// @throws InvalidInput if `tolerance` is not positive and finite.
/// No collapse creates an edge longer than `maxEdgeLength` mm (≤ 0: no limit).
SimplifiedSurface simplifyLayerSurface(const TriMesh& surface, double tolerance,
                                       double maxEdgeLength = 0.0);

/// The tolerance `options` asks for on a grid of voxel edge `voxelSize` (mm).
/// @throws InvalidInput for a negative or non-finite tolerance.
double resolveLayerTolerance(const LayerSimplificationOptions& options, double voxelSize);

}  // namespace curvedslicer
