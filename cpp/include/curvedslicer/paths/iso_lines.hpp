// Iso-lines of a per-vertex scalar field on a triangle surface (paper §3.1: "the points with the
// same GDTC values equal to the given beam spacing constitute the planned path"), and the value
// sequence for bead paths.
//
// Method: marching triangles. The field is linear on each triangle; a crossing point is placed on
// every edge whose end values straddle the iso-value (vertices exactly at the value count as
// above it, so a crossing is never placed twice), shared between the two triangles of the edge,
// and the segments are chained through shared edges into polylines. A chain ends where it reaches
// the boundary of the surface or a triangle with a non-finite value (the field stops there), so
// iso-lines are split where they leave the surface; a chain that returns to its start is closed.
// Points lie exactly on the triangles (linear interpolation along edges).
// Preconditions: an indexed mesh (neighbouring triangles share vertex indices); one value per
// vertex. Cost: O(T) per iso-value; several values in one pass: O(T + crossings) (each triangle
// visits only the values between its corner values).
#pragma once

#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

/// Iso-lines of `field` (one value per vertex of `mesh`; +inf/NaN = no value) at `value`.
/// Order: by the first triangle (lowest index) each chain passes (deterministic). Orientation:
/// walking along a line, the side with field > value lies on the left when the surface is seen
/// from the side its triangle normals point to.
/// @throws InvalidInput if field.size() != mesh.vertexCount().
std::vector<Polyline> extractIsoLines(const TriMesh& mesh, const std::vector<double>& field,
                                      double value);

/// The iso-lines at every one of `values` (any order), in one pass over the triangles: result k
/// equals extractIsoLines(mesh, field, values[k]).
/// @throws InvalidInput as extractIsoLines, naming the first non-finite value.
std::vector<std::vector<Polyline>> extractIsoLines(const TriMesh& mesh,
                                                   const std::vector<double>& field,
                                                   const std::vector<double>& values);

/// Where bead paths start counting.
enum class IsoValueStart {
  Boundary,       ///< (k + ½)·s, k = 0, 1, …: the outer bead's edge sits on the boundary
  InteriorCurve,  ///< k·s, k = 0, 1, …: the first bead lies on the initial curve itself
};

/// The iso-values for bead spacing `spacing` (s, mm) up to and including `maxValue` (mm):
/// (k + ½)·s or k·s (see IsoValueStart), in increasing order; empty if none fits.
/// @throws InvalidInput for spacing ≤ 0 or non-finite, or more than 10^6 values.
std::vector<double> computeIsoValues(double spacing, double maxValue, IsoValueStart start);

}  // namespace curvedslicer
