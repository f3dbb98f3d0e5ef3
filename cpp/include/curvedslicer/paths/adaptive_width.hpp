// Adaptive bead width: per connected region of a layer, the ring widths and
// iso-values that fill the region's half-width with a whole number of beads.
//
// A region whose largest distance from its initial curve (GDTC) is m gets K = round(m/s) rings
// (at least 1) of width w' = m/K: from the boundary at (k + ½)·w', k = 0 … K−1, so the outer
// bead's edge sits on the part edge and the innermost beads meet on the medial axis; from an
// interior curve at k·w', k = 0 … K with K = round(m/s − ½) and w' = m/(K + ½). Where w' falls
// outside [widthMin·s, widthMax·s] the nearest allowed width is taken and the iso-values are the
// usual ones at that spacing (the planner's narrow-strip handling then treats what is left).
// Regions are the vertex-connected components of the layer mesh. Cost: O(V + T).
#pragma once

#include <cstdint>
#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/iso_lines.hpp"

namespace curvedslicer {

/// The rings of one region.
struct RegionRings {
  double width = 0.0;          ///< w', mm, bead width (and ring spacing) of the region
  std::vector<double> values;  ///< GDTC iso-values of the rings, mm, ascending
  bool widthClamped = false;   ///< m/K lay outside the allowed range; `width` is its nearest end
  double wholeWidth = 0.0;     ///< mm, m/K (or m/(K + ½)), the width a whole number needs
};

/// Ring width and iso-values for a region reaching `halfWidth` (m, mm) from its initial curve.
/// @param beadSpacing  s, mm (> 0)
/// @param widthMin, widthMax  allowed widths as fractions of s, 0 < widthMin <= 1 <= widthMax
/// @return no values when m < w'/2 (boundary) or m is not finite.
RegionRings computeRegionRings(double halfWidth, double beadSpacing, double widthMin,
                               double widthMax, IsoValueStart start);

/// Vertex-connected components of a mesh: per vertex a region number 0, 1, … in order of the
/// lowest vertex index of each region; isolated vertices get a region of their own.
/// @return labels, one per vertex; `count` gets the number of regions.
std::vector<std::int32_t> labelMeshRegions(const TriMesh& mesh, std::int32_t& count);

}  // namespace curvedslicer
