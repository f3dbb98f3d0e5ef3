// GDTC (paper §2.2.1, §3.1): the geodesic distance on a layer surface from an initial curve (one
// or more polylines lying on the surface), per vertex of the surface with the curve inserted.
//
// Methods (`SurfaceGeodesicMethod`):
//  - `Accurate` (default): the curve is inserted into the mesh — every curve point and every
//    crossing of a curve segment with a mesh edge becomes a vertex (the triangles it crosses are
//    split, nothing is snapped except points within 1e-7 of an edge length of an existing vertex
//    or edge), so curve segments are mesh edges with distance exactly 0. The distance is then
//    propagated by fast marching on triangles (Kimmel & Sethian, "Computing geodesic paths on
//    manifolds", PNAS 95(15), 1998): a vertex is updated from two accepted vertices of a triangle
//    by the planar wavefront through them (exact for straight fronts, first order for curved
//    ones); at obtuse corners the triangle is unfolded across the opposite edge until the
//    virtual triangle is acute; where the front direction falls outside the triangle the update
//    falls back to the edge (Dijkstra) value. Two refinements for curved and singular fronts:
//    vertices within two edge rings of the curve start from their exact Euclidean distance to the
//    curve, and each update also fits the front through the two known corners and the known
//    vertex across their edge as a circle (exact for circular fronts; the planar update is kept
//    when the fit is ill-conditioned, tighter than twice the stencil, or disagrees).
//    docs/METHODS.md explains the choice and gives measured errors.
//  - `Paper`: the paper's method on the surface points (the vertices of the same cut mesh): a
//    Dijkstra propagation between points closer than a search radius, each step of projected
//    length l = |QP − (QP·Np)Np| (eq. 15), Np the unit normal at P from a least-squares plane fit
//    to the points within the search radius. Sources are the curve's vertices.
// Preconditions: an indexed mesh (neighbouring triangles share vertex indices), part frame, mm;
// the curve within `curveTolerance` of the surface.
// Cost: insertion O(curve length / edge length) splits plus one O(T) location per curve
// component; fast marching O(V log V). Paper method O(V·k log V) with k points per search ball.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

enum class SurfaceGeodesicMethod {
  Accurate,  ///< curve inserted into the mesh, fast marching with unfolding (default)
  Paper,     ///< paper §3.1: Dijkstra over a search ball with the projected length of eq. 15
};

/// "accurate" | "paper" (the command line's, the workbench's and the plan file's names).
std::string_view toString(SurfaceGeodesicMethod method);
/// Parses "accurate" or "paper". @throws InvalidInput listing the choices.
SurfaceGeodesicMethod parseSurfaceGeodesicMethod(std::string_view name);

struct SurfaceGeodesicOptions {
  SurfaceGeodesicMethod method = SurfaceGeodesicMethod::Accurate;
  /// Largest allowed distance of an initial-curve point from the surface, mm; a farther point is
  /// an InvalidInput error that says how far it is.
  double curveTolerance = 0.05;
  /// Paper method: radius of the search ball, mm; ≤ 0 means 2·√3 × the mean edge length (the
  /// paper's r = 2√3·L with the mean edge length standing in for the voxel edge L).
  double paperSearchRadius = 0.0;
  /// Stop propagating beyond this distance, mm (vertices farther away stay +inf).
  double maxDistance = kInf;
  /// Accurate method: second-order update — the front through the two known corners and the
  /// known vertex across their edge is fitted as a circle (exact for circular fronts); false uses
  /// the first-order planar update only.
  bool secondOrder = true;
  /// Accurate method: vertices within this many edge rings of the inserted curve start from their
  /// exact Euclidean distance to the curve (the front is singular next to curve end points and
  /// corners, where fast marching is least accurate); 0 seeds the curve vertices only.
  int nearFieldRings = 2;
};

/// A surface with initial curves inserted as vertices and edges.
struct CurveInsertion {
  /// The input mesh with the curve inserted: the input's vertices keep their indices (new ones
  /// are appended); split triangles are replaced (triangle indices are not preserved).
  TriMesh mesh;
  /// Vertices lying on the initial curve (sorted, unique).
  std::vector<std::int32_t> curveVertices;
  /// Largest distance of an initial-curve point from the input surface, mm.
  double maxCurveDeviation = 0.0;
  std::size_t insertedVertices = 0;  ///< vertices added to the mesh
};

struct SurfaceGeodesicResult {
  /// The surface the field lives on: the input mesh with the initial curve inserted
  /// (see CurveInsertion::mesh).
  TriMesh mesh;
  /// GDTC per vertex of `mesh`, mm; +inf where not reached (another component, or beyond
  /// `maxDistance`).
  std::vector<double> distance;
  std::vector<std::int32_t> curveVertices;  ///< vertices of `mesh` on the initial curve
  double maxCurveDeviation = 0.0;           ///< mm, see CurveInsertion
  std::size_t insertedVertices = 0;         ///< vertices added by the insertion
  std::size_t unreachedVertices = 0;        ///< vertices left at +inf
  std::size_t unfoldings = 0;               ///< fast marching: obtuse corners resolved by unfolding
  double searchRadius = 0.0;                ///< paper method: the search radius used, mm
  double seconds = 0.0;                     ///< wall time
};

/// Inserts `curves` (part frame, mm; open or closed polylines with ≥ 1 point) into `surface`:
/// every point and every crossing of a segment with a mesh edge becomes a vertex, consecutive
/// curve vertices are joined by mesh edges. Segments are traced across the triangles along the
/// plane spanned by the segment and the local surface normal.
/// @throws InvalidInput for an empty surface, non-finite coordinates, or a curve point farther
///         than `curveTolerance` (mm) from the surface (the message gives the distance and the
///         point); NumericalFailure if a segment cannot be traced to its end on the surface
///         (e.g. it jumps across a gap between components).
CurveInsertion insertCurves(const TriMesh& surface, const std::vector<Polyline>& curves,
                            double curveTolerance = 0.05);

/// GDTC from `initialCurve` on `surface` (see the file comment). Progress stages: "inserting
/// initial curve", "propagating surface distance".
/// @param surface       layer surface, part frame, mm, indexed triangles
/// @param initialCurve  polylines on the surface (part frame, mm), e.g. extractBoundaryLoops()
///                      or computePlaneSection() of the same surface
/// @throws InvalidInput for an empty surface, no curve point, non-positive or non-finite
///         tolerance or search radius, a curve off the surface (how far); NumericalFailure as in
///         insertCurves; Cancelled via `progress`.
SurfaceGeodesicResult computeSurfaceGeodesic(const TriMesh& surface,
                                             const std::vector<Polyline>& initialCurve,
                                             const SurfaceGeodesicOptions& options = {},
                                             Progress progress = {});

/// GDTC from given vertices of `mesh` (no insertion): `sourceVertices[i]` starts at
/// `sourceValues[i]` (mm, ≥ 0; empty = all 0). Same methods as computeSurfaceGeodesic; the result's
/// mesh is a copy of `mesh`.
/// @throws InvalidInput for an empty mesh, no source, an index out of range, sizes that differ.
SurfaceGeodesicResult computeSurfaceGeodesicFromVertices(
    const TriMesh& mesh, const std::vector<std::int32_t>& sourceVertices,
    const std::vector<double>& sourceValues = {}, const SurfaceGeodesicOptions& options = {},
    Progress progress = {});

}  // namespace curvedslicer
