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
//
// Two methods (`DepositionOptions::method`):
//  - Nearest: the paper's V exactly as above.
//  - Growth (default): the paper's V where it agrees with the layer's local growth direction
//    within `maxDeviation`, else that growth direction. The growth direction is −normal (the
//    layer surfaces are iso-surfaces of the distance field, their normals its gradient), unless
//    the normal itself disagrees by more than `maxDeviation` with the mean V of the layer below
//    within `DepositionSupport::belowRadius` (distance-weighted, (1 − d/R)²); then that mean.
//    Why: on a small fragment of a layer surface (a blade tip, a neck a voxel wide) the nearest
//    material can lie beside the point rather than under it, and the fragment's own normals are
//    noise (neighbouring points 60–180° apart), so the paper's V lays the torch along the layer
//    into the beads beside it. Where the deposit is sound (every point of a smooth layer) the two
//    agree to a few degrees and the paper's V is kept. Points given another V are counted.
// Preconditions: paths in deposition order with finite positions and unit normals.
// Cost: one closest-point query per point on the surface (O(log T)) plus a bounded ring search
// of the bead grid; O(segments) to insert each finished bead.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/paths/polyline.hpp"
#include "curvedslicer/plan/plan.hpp"

namespace curvedslicer {

enum class DepositionMethod {
  Nearest,  ///< the paper's V: towards the nearest deposited material
  Growth,   ///< the paper's V unless it leaves the layer's growth direction (file comment)
};

struct DepositionOptions {
  DepositionMethod method = DepositionMethod::Growth;
  /// rad; Growth: largest angle between the paper's V and the growth direction, and between the
  /// layer normal and the layer below's V, before the second one is taken.
  double maxDeviation = 30.0 * 3.14159265358979323846 / 180.0;
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
  /// The surface is the substrate the part stands on (a thin wall's plate): V towards it is
  /// kept under Growth too, since a bead that lies nearer the substrate than any bead before it
  /// rests on the substrate, whatever the wall's growth direction.
  bool surfaceIsSubstrate = false;
  /// mm, surfaceIsSubstrate: the substrate is taken while it is at most this much farther than
  /// the nearest earlier bead or curve (a bead of width w laid at the tip spreads w/2 towards
  /// the substrate: it rests on it as well as on the bead beside it).
  double substrateMargin = 0.0;
  /// The layer below with its deposition directions (Growth); nullptr or empty: none (the first
  /// layer), the growth direction is then −normal.
  const std::vector<PlanPath>* below = nullptr;
  /// mm; Growth: the neighbourhood of a point on the layer below whose V are averaged.
  double belowRadius = 0.0;
};

struct DepositionStats {
  std::size_t points = 0;             ///< points given a direction
  std::size_t towardsSurface = 0;     ///< of those, pointing to the support surface
  std::size_t towardsBeads = 0;       ///< of those, pointing to an earlier bead or support curve
  std::size_t normalFallbacks = 0;    ///< of those, set to −normal (contact or no material)
  std::size_t growthCorrections = 0;  ///< of those, Growth: V replaced by the growth direction
  std::size_t normalsOverruled = 0;   ///< of those, Growth: growth from the layer below's V
  double minDistance = kInf;  ///< mm, nearest-material distance over the points (not fallbacks)
  double maxDistance = 0.0;   ///< mm

  void add(const DepositionStats& other);
};

/// Sets PathPoint::deposition of every point of `paths` (one layer, in deposition order); reads
/// positions and normals. @throws InvalidInput for a non-finite position.
DepositionStats assignDepositionDirections(std::vector<PlanPath>& paths,
                                           const DepositionSupport& support,
                                           const DepositionOptions& options = {});

/// "nearest" / "growth" (plan files, options); parse throws InvalidInput naming the value.
const char* depositionMethodName(DepositionMethod method);
DepositionMethod parseDepositionMethod(const std::string& name);

}  // namespace curvedslicer
