// Corner fill: at an acute convex corner of a layer region, the outer ring dips
// toward the corner so its bead covers the corner's wedge, its edge going past the layer
// boundary by at most a bound.
//
// Why: the outer ring runs at w/2 from the boundary (w the bead width), so at a convex corner of
// angle θ it has a corner of the same angle whose round bead touches both edges and leaves the
// wedge between them and the bead uncovered: (w/2)²·(cot(θ/2) − (π − θ)/2), 1.6 mm² at θ = 70°
// and w = 3.7 mm. A machined WAAM part tolerates a little metal past its edge (stock
// allowance), not a void inside it.
//
// Method, per outer-ring bead (a polyline with per-point normals and widths):
//   1. Corners: points where the chords to the points `cornerArm` of arc length before and after
//      (projected into the point's tangent plane) turn by more than 180° − `maxCornerAngle`
//      (acute corners by default), the sharpest within cornerArm on either side; the corner angle
//      is θ = π − turn, the outside of the turn o = u₁ − u₂ (normalised; u₁, u₂ the chord
//      directions).
//   2. Only a ring point at the outer ring's offset is moved (its edge distance within 25 % of
//      w/2), and only at a convex corner of the boundary: moving it toward o must bring it nearer
//      the edge (by at least half of δ·sin(θ/2), what a straight-edged corner gives).
//   3. The corner point C moves along o by δ = min(w/2·(1/sin(θ/2) − 1), b/sin(θ/2)): the first
//      term puts the corner's tip within the bead (the whole wedge covered), the second keeps the
//      bead's edge at most b = `maxOverdeposit` past the two straight edges. The edge distance
//      measured at the moved point Q decides: where w/2 − distance(Q) > b (a curved or
//      irregular edge), δ shrinks by a quarter until it is not (at most 12 times; else C
//      stays).
//   4. The path goes …, A, Q, B, … instead of …, C, …, with A and B on the ring's chords at
//      min(δ, half the neighbouring segment) before and after C: a short dip into the corner.
// The bead's edge past the boundary is the largest w/2 − distance over the moved points; along
// the segments A→Q and Q→B it varies linearly in a corner with straight edges, so the bound
// holds there too. The dip deposits the corner region twice over a few millimetres (the torch
// goes in and comes back): extra metal inside the corner, measured as overlap only where the two
// passes are more than a bead width apart along the path (paths/coverage.hpp).
//
// Preconditions: the ring lies on the layer surface; the sampler gives points on that surface,
// their unit normals and their distance to the layer's boundary (the GDTC from the boundary in
// the planner). Part frame, mm. Cost: O(n) per bead of n points plus a few samples per corner.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

struct CornerFillOptions {
  double beadSpacing = 3.7;  ///< s, mm (> 0): the bead width where a bead carries none
  double maxOverdeposit =
      -1.0;  ///< mm, largest distance a bead's edge passes the boundary; < 0: s/4
  /// Degrees, in (0, 180): only corners sharper than this are filled (the ring turns by more
  /// than 180° − this). Default 85°: acute corners; a right angle (wedge 0.74 mm² at s = 3.7)
  /// keeps its plain ring.
  double maxCornerAngle = 85.0;
  double cornerArm = -1.0;  ///< mm of arc length either side that measures a turn; < 0: s/4
};

/// A point of the layer surface near a queried point: the closest point, its unit normal, and
/// its distance to the layer's boundary (mm; not finite: unknown).
struct EdgeSample {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  double edgeDistance = 0.0;
};

/// Samples the layer surface at (near) a point, part frame, mm.
using EdgeSampler = std::function<EdgeSample(const Vec3&)>;

/// One outer-ring bead to dip into corners (changed in place).
struct CornerFillBead {
  Polyline* line = nullptr;               ///< part frame, mm; not owned
  std::vector<Vec3>* normals = nullptr;   ///< one per point; not owned
  std::vector<double>* widths = nullptr;  ///< mm per point, or empty (= s); may be null (= s)
};

struct CornerFillResult {
  std::size_t corners = 0;          ///< corners dipped into
  double largestOverdeposit = 0.0;  ///< mm, largest bead edge past the boundary at a moved point
  double largestDip = 0.0;          ///< mm, largest δ
};

/// Dips the outer rings `beads` into the layer's acute convex corners (see the file comment).
/// @throws InvalidInput for a non-positive spacing, a non-finite bound, an angle outside (0, 180),
///         or a bead without one normal (and width, when given) per point.
CornerFillResult fillRingCorners(const std::vector<CornerFillBead>& beads,
                                 const EdgeSampler& sample, const CornerFillOptions& options = {});

}  // namespace curvedslicer
