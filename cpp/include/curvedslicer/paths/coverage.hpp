// Bead coverage of one layer: how much of the layer surface no bead covers
// (voids) and how much two or more beads cover (overlap), measured on the layer surface.
//
// Bead model: a bead is the set of surface points within half its width of its centre line (the
// path's polyline, closing segment included for a closed path); the width is PathPoint::width
// interpolated linearly along each segment, 0 meaning the bead spacing s. A spot deposit (a path
// with dwell > 0) is the same: a disc of radius width/2 around each point (a path of one point,
// or of coincident points, is a disc).
//
// Method: the surface is sampled area-weighted — each triangle is cut into n² congruent
// sub-triangles (n = ⌈longest edge / sample spacing⌉) and each sub-triangle carries its area on
// one sample placed uniformly at random inside it (stratified sampling), so the sample areas add
// up exactly to the surface area. The positions come from a hash of the triangle and
// sub-triangle indices (deterministic); a fixed pattern such as the centroids would alias with a
// regular layer mesh (narrow gaps between beads parallel to the mesh lines missed or hit on every
// triangle alike). Triangles are processed in a fixed
// number of blocks (OpenMP), summed in block order: the result does not depend on the thread
// count. A sample is
//   - void when no bead covers it;
//   - overlap when two different paths cover it, or one path at two points more than one bead
//     width apart along the path (a tight turn, connected insets running side by side);
//   - covered once otherwise.
// Void samples are clustered into patches (samples in neighbouring cells of a grid with twice the
// sample spacing as cell size: patches separated by less than about 7 sample spacings, 0.7·s by
// default, count as one), and the largest patches are listed with area, centre and size.
// Beads are found through a uniform grid of cells holding every bead segment whose reach (segment
// box grown by half its width) touches the cell, so a sample tests only the segments of its cell.
//
// Preconditions: surface and paths in the same frame (the part frame), mm; the paths lie on (or
// near) the surface — distances are 3D distances. Cost: O(A / h²) samples for area A and sample
// spacing h, each testing the few segments of one cell; plus O(segments · cells per segment).
#pragma once

#include <cstddef>
#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/plan/plan.hpp"

namespace curvedslicer {

struct CoverageOptions {
  /// mm, largest edge of the sub-triangles that each hold one area sample; < 0 means s/10
  /// (s = the bead spacing passed to computeLayerCoverage).
  double sampleSpacing = -1.0;
  /// How many of the largest uncovered patches LayerCoverage::voids lists (largest first).
  std::size_t maxVoids = 10;
  /// Threads sampling the surface (>= 0); 0: OpenMP's default (OMP_NUM_THREADS, else the
  /// cores). The result is the same for any number.
  int threads = 0;
};

/// Measures the coverage of one layer (see the file comment).
/// @param layerSurface  the layer's surface, part frame, mm (any triangle soup; no connectivity
///                      needed)
/// @param paths         the layer's beads (PathPoint::position, ::width; PlanPath::closed, ::dwell)
/// @param beadSpacing   s, mm (> 0): the width of points whose width is 0, and the reported
///                      nominal bead width
/// @return measured = true, area, voidShare, overlapShare, beadWidth = s,
///         arcStarts = paths.size(), voids (area mm², centre part frame, size = the largest
///         distance between two samples of the patch plus one sample spacing, mm)
/// @throws InvalidInput for s ≤ 0, a sample spacing of 0 or not finite, or a negative width.
LayerCoverage computeLayerCoverage(const TriMesh& layerSurface, const std::vector<PlanPath>& paths,
                                   double beadSpacing, const CoverageOptions& options = {});

/// A plan's coverage in total (report.json, the command-line summary, the workbench).
struct PlanCoverageSummary {
  std::size_t measuredLayers = 0;  ///< layers whose coverage was measured
  double area = 0.0;               ///< mm², summed over the measured layers
  double voidShare = 0.0;          ///< [0, 1], area-weighted over the measured layers
  double overlapShare = 0.0;       ///< [0, 1], area-weighted over the measured layers
  std::size_t arcStarts = 0;       ///< paths of all layers (each is one arc start)
  /// Indices of the measured layers with the largest void share (> 0), largest first, ties by
  /// index; at most the number asked for.
  std::vector<int> worstLayers;
};

/// Sums the layers' coverage (see PlanCoverageSummary); `worst` bounds worstLayers.
PlanCoverageSummary summarizeCoverage(const Plan& plan, std::size_t worst = 3);

}  // namespace curvedslicer
