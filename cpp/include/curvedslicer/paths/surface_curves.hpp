// Curves on a triangle surface: boundary loops, and sections with a plane or another surface
// (the paper's "intersection of a user-input surface and the STL model", §3.1), all as chained
// polylines in the part frame.
//
// Method: boundary loops walk the edges used by exactly one triangle. Sections evaluate a signed
// distance at the vertices (exact for a plane; for a user surface the exact signed distance to its
// nearest triangle, sign from the angle-weighted pseudo-normal — geom/triangle_bvh.hpp), place a
// crossing point on every edge whose ends have opposite signs (for a user surface refined by
// bisection on the exact distance to within 1e-9 of the edge length), and chain the crossings
// triangle by triangle (marching triangles; iso_lines.hpp). Sections split where they leave the
// surface and are closed where they return to their start.
// Preconditions: an indexed mesh (neighbouring triangles share vertex indices), finite
// coordinates. Non-manifold edges (used by more than two triangles) end boundary walks.
// Cost: O(T) for loops and plane sections; one closest-point query per vertex near the user
// surface plus ~30 per crossed edge for user-surface sections.
#pragma once

#include <cstdint>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

/// The boundary loops of `mesh` (edges used by exactly one triangle), each closed and ordered
/// along the triangles' orientation (the surface on the left when seen against the normals).
/// Points are the mesh's vertex positions (so inserting them into the mesh adds no vertex).
/// Longest loop first; loops of equal length in order of their smallest vertex index.
/// A closed mesh gives no loop. Open chains (at non-manifold vertices) are returned open.
std::vector<Polyline> extractBoundaryLoops(const TriMesh& mesh);

/// The boundary of a surface found in one pass: its loops (as extractBoundaryLoops) and the
/// vertices on its boundary edges (edges used by exactly one triangle; sorted, unique), e.g. the
/// sources of the surface distance from the boundary.
struct SurfaceBoundary {
  std::vector<Polyline> loops;
  std::vector<std::int32_t> vertices;
};
SurfaceBoundary findBoundary(const TriMesh& mesh);

/// The section of `mesh` with the plane through `point` with normal `normal` (part frame; the
/// normal need not be unit length). Vertices exactly on the plane count as on its positive side.
/// @throws InvalidInput for a zero or non-finite normal.
std::vector<Polyline> computePlaneSection(const TriMesh& mesh, const Vec3& point,
                                          const Vec3& normal);

/// The section of `mesh` with another triangle surface `userSurface` (part frame, mm). The user
/// surface may be open; it should extend past the layer where the section is wanted.
/// @throws InvalidInput for an empty user surface.
std::vector<Polyline> computeSurfaceSection(const TriMesh& mesh, const TriMesh& userSurface);

}  // namespace curvedslicer
