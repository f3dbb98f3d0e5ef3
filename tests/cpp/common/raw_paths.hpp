// Raw iso-line-like polylines shared by the path-fit tests and benchmarks.
#pragma once

#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer::testing {

/// A closed ring of four parabolic arcs bulging outward from the sides of a square of side `side`
/// (mm, sagitta `bulge`), raw points about `step` mm apart, with a z wave: iso-line-like, smooth
/// except for four corners (the square's vertices, turns of 90° − 2·atan(4·bulge/side)).
/// Sets `corners` to the corner points. If `microGap` > 0, every tenth raw point gets a twin
/// `microGap` mm further along (a sub-micrometre segment).
Polyline makeBulgedSquareRing(double side, double bulge, double step, double microGap,
                              std::vector<Vec3>& corners);

}  // namespace curvedslicer::testing
