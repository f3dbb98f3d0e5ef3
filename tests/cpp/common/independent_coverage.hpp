// Bead coverage recomputed independently of the planner's paths/coverage.hpp, for acceptance
// tests (bunny, turbine): the share of layer area farther than half a bead width from every
// path's centre line, on a barycentric sample grid of every layer triangle (each triangle cut
// into m² sub-triangles, m = ⌈longest edge / 0.5 mm⌉, each counted at its centroid), the paths'
// segments found through a hash grid. Differences from paths/coverage.hpp: a fixed centroid
// pattern instead of stratified random samples, no overlap, and (unless `useWidths`) every bead
// s wide.
#pragma once

#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/plan/plan.hpp"

namespace curvedslicer::testing {

struct Coverage {
  double area = 0.0, voidArea = 0.0;  ///< mm²
  double voidShare() const { return area > 0.0 ? voidArea / area : 0.0; }
};

/// Adds the area and void area of one layer to `c`.
/// @param s          bead spacing, mm: the bead width (and the width of points whose width is 0)
/// @param useWidths  false: every bead is s wide; true: PathPoint::width, interpolated linearly
///                   along each segment (a one-point path is a disc)
void addLayerCoverage(const TriMesh& mesh, const std::vector<PlanPath>& paths, double s,
                      Coverage& c, bool useWidths = false);

}  // namespace curvedslicer::testing
