// Bead widening: an uncovered strip between beads that no bead of its own takes (one
// narrower than the gap fill's minimum width, e.g. the 1–2 mm strip down the middle of a thin
// wall that holds one ring of beads on each side; the rim of a strip too short for a fill bead)
// is taken, or narrowed, by widening the beads beside it,
// each on its own side only: a bead point whose edge on one side lies e mm short of an
// uncovered point gets e more width on that side and its centre moves e/2 that way, so its
// other edge stays where it was. Two beads facing each other across a strip of width g thus
// each take g/2 of it; the overlap this costs is measured with the plan's coverage.
//
// Method: the layer mesh is sampled on a barycentric grid (about `sampleSpacing` apart) in every
// triangle that is not covered well inside a bead. An uncovered sample at most `maxExtension`
// beyond the nearest bead's edge, in a strip between two beads (a bead edge on the sample's far
// side, nearer than the part edge), asks the nearest bead to reach it, on the sample's side of
// the bead (side = sign of the offset along tangent × normal). Left alone: samples farther off
// (gap fill's, or beyond reach: such a strip is only narrowed); bands along the part edge and
// open voids (a bead grown into a corner of the part would cross its edge); slivers narrower
// than `minStripWidth` (strip width: nearest bead edge to the far bead edge; fit noise, not
// worth a wider bead); samples beyond a bead's end. Per bead point the largest ask per side is
// kept, plus half a sample spacing; a stretch of consecutive widened points shorter than
// `minRunLength` is left as it was (a ring corner's small void costs more overlap than it
// holds); the total width is capped at `maxWidth` (the cap taken from both sides alike). Spots
// (one-point beads) are never widened. Cost: O(samples · segments per cell).
#pragma once

#include <cstddef>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

/// Options of computeBeadWidening. Negative lengths are the defaults relative to s.
struct BeadWideningOptions {
  double beadSpacing = 3.7;     ///< s, mm (> 0): bead width where a bead carries none
  double maxExtension = -1.0;   ///< mm per side a bead may grow; negative: s/4 (half of s/2)
  double maxWidth = -1.0;       ///< mm, widest bead after widening; negative: 1.25·s
  double sampleSpacing = -1.0;  ///< mm between coverage samples; negative: s/16
  double minRunLength = -1.0;   ///< mm, shortest stretch of a bead widened; negative: s
  double minStripWidth = -1.0;  ///< mm, narrower slivers are left (fit noise); negative: s/10
};

/// One bead to widen: its points, per-point surface normals and widths (part frame, mm).
struct WidenableBead {
  const Polyline* line = nullptr;              ///< not owned; ≥ 2 points to be widened
  const std::vector<Vec3>* normals = nullptr;  ///< one per point (not owned)
  std::vector<double> widths;                  ///< mm per point; empty: s
};

/// Per bead, per point: how far each edge moves out (mm, ≥ 0). Left is −(tangent × normal).
struct BeadWidening {
  std::vector<std::vector<double>> left, right;  ///< [bead][point]; empty for untouched beads
  std::size_t widenedPoints = 0;                 ///< points with any extension
  double largestWidth = 0.0;                     ///< mm, widest bead point after widening
};

/// Extensions of `beads` that cover the uncovered samples of `mesh` within reach (file comment).
/// @param mesh  the layer surface (part frame, mm)
/// @param edgeDistance  per vertex of `mesh`, its distance to the part edge (mm, e.g. the GDTC
///        from the boundary; non-finite: unknown); empty: no part edge is known
/// @throws InvalidInput for a non-positive or non-finite spacing, or a bead without one normal
///         per point
BeadWidening computeBeadWidening(const TriMesh& mesh, const std::vector<WidenableBead>& beads,
                                 const std::vector<double>& edgeDistance = {},
                                 const BeadWideningOptions& options = {});

}  // namespace curvedslicer
