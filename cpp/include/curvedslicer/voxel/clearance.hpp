// Clearance field: for every inside cell, the Euclidean distance (in units of L) from its centre to
// the nearest centre of an outside cell (cells beyond the grid count as outside); 0 for outside
// cells. Exact Euclidean distance transform (Felzenszwalb & Huttenlocher 2012, separable lower
// envelope of parabolas), O(cells), parallel over lines (OpenMP).
//
// Used for line-of-sight tests: a point x with |x − c| < clearance(c)·L − (√3/2)·L, where c is the
// centre of any inside cell, lies in an inside cell.
#pragma once

#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/voxel/voxel_grid.hpp"

namespace curvedslicer {

std::vector<float> computeClearance(const VoxelGrid& grid, Progress progress = {});

}  // namespace curvedslicer
