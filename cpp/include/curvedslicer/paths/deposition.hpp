// Deposition direction V per path point (paper §3.2, fig. 14): the unit vector from the wire tip
// (the path point) to the closest point of the material deposited before it.
//
// What counts as deposited material is given per layer (`DepositionSupport`):
//  - the first layer: the start surface (the substrate) and, with `earlierBeads`, every bead of
//    the same layer deposited before the current one (the paper's case 1, "the nearest point in
//    the former deposited beam");
//  - later layers: the previous layer surface (the paper's case 2);
//  - a thin wall built bead on bead: the wall's start edge and every earlier bead.
// Surfaces are triangle meshes queried through an AABB tree (geom/triangle_bvh.hpp); beads are the
// polylines of the earlier paths (centre lines), held in a uniform hash grid of segments that is
// searched ring by ring only up to the distance already found on the surface. A bead's own points
// never count (the material just behind the torch would otherwise always be nearest).
// Where the nearest material is closer than `contactTolerance` (a point on the support itself) or
// there is none, V falls back to −normal (normals point away from the deposited material); the
// fallbacks are counted.
// Preconditions: paths in deposition order with finite positions and unit normals.
// Cost: one closest-point query per point on the surface (O(log T)) plus a bounded ring search
// of the bead grid; O(segments) to insert each finished bead.
#pragma once

#include <cstddef>
#include <vector>

#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/paths/polyline.hpp"
#include "curvedslicer/plan/plan.hpp"

namespace curvedslicer {

struct DepositionOptions {
  /// mm; a point closer than this to the deposited material has no defined direction to it and
  /// gets V = −normal.
  double contactTolerance = 1e-6;
  /// mm; edge of the hash-grid cells holding bead segments; ≤ 0 means the longest bead segment
  /// (at least 1e-3 mm).
  double gridCell = 0.0;
};

/// The material below one layer (see the file comment).
struct DepositionSupport {
  /// Surface of deposited material (previous layer, or the start surface for the first layer);
  /// nullptr or an empty hierarchy means none.
  const TriangleBvh* surface = nullptr;
  /// Curves of deposited material that are not paths of this layer (e.g. a thin wall's start
  /// edge), part frame, mm.
  std::vector<Polyline> curves;
  /// Beads of this layer deposited earlier (the paths before the current one) count too.
  bool earlierBeads = false;
};

struct DepositionStats {
  std::size_t points = 0;           ///< points given a direction
  std::size_t towardsSurface = 0;   ///< of those, pointing to the support surface
  std::size_t towardsBeads = 0;     ///< of those, pointing to an earlier bead or support curve
  std::size_t normalFallbacks = 0;  ///< of those, set to −normal (contact or no material)
  double minDistance = kInf;  ///< mm, nearest-material distance over the points (not fallbacks)
  double maxDistance = 0.0;   ///< mm

  void add(const DepositionStats& other);
};

/// Sets PathPoint::deposition of every point of `paths` (one layer, in deposition order); reads
/// positions and normals. @throws InvalidInput for a non-finite position.
DepositionStats assignDepositionDirections(std::vector<PlanPath>& paths,
                                           const DepositionSupport& support,
                                           const DepositionOptions& options = {});

}  // namespace curvedslicer
