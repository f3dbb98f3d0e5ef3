// Connected insets: fewer arc starts. Consecutive contour-parallel rings of one
// region — the iso-lines at levels k and k + 1, nested, s apart — are deposited as one arc-on
// path: round ring k from its seam back to the seam, a short step-over (the link) to the nearest
// point of ring k + 1, round ring k + 1 back to that point, a link to ring k + 2, and so on to the
// innermost ring of the chain (a spiral-like connected inset).
//
// Method, on one layer's paths in deposition order (as paths/ordering.hpp left them: every closed
// ring starts at its seam, so the seam staggering between layers is the outermost ring's):
//   1. Chains, greedily: the rings (closed paths with a level ≥ 0) by increasing level, ties in
//      deposition order; each ring not yet used starts a chain; a chain ending at ring A (level
//      k) goes on to the ring B of level k + 1, not yet used, whose nearest point q to A's seam
//      e is nearest, if the link e → q is admissible (2.); else the next such ring is tried.
//   2. A link is admissible if |e − q| ≤ maxLinkLength (default 1.5·s) and every link point (the
//      chord e → q sampled at most `pointSpacing` apart, each projected onto the layer surface)
//      (a) lies within `maxSurfaceGap` (default s/4) of the chord before projection — the layer
//      is under the chord, the link does not jump a gap —, (b) keeps `clearance` (default s/2)
//      from every other path of the layer and from the rings already joined, and (c) stays at
//      least half its distance from e away from ring A and half its distance from q away from
//      ring B — the link leaves A and reaches B without running along or across them.
//   3. The joined path: each ring part in full, its first point repeated at its end (the ring's
//      closing segment), then the link's interior points. It replaces the chain's first ring in
//      the deposition order; the other rings of the chain leave the order. It is open
//      (PlanPath::closed = false); its length is the arc-on length including the links.
// The ring parts are the rings' own points (no point moved), so their spacing is unchanged; a
// joined path splits back into its ring parts and links with `splitJoinedPath`. Link points get
// the surface normal at their projection; their deposition direction is left to the deposition
// stage, and their bead width is that of the ring they lead to.
// Preconditions: paths of one layer, part frame, mm; closed rings have ≥ 3 points.
// Cost: O(R²·m) for R rings of m points (nearest points) plus O(links · P) for the clearance
// checks against all P points of the layer.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/plan/plan.hpp"

namespace curvedslicer {

struct ConnectedInsetOptions {
  double beadSpacing = 3.7;     ///< s, mm (> 0)
  double pointSpacing = 2.0;    ///< mm, largest distance between link points (> 0)
  double maxLinkLength = -1.0;  ///< mm, longest step-over; < 0 means 1.5·s
  double clearance = -1.0;      ///< mm, a link keeps this from other paths; < 0 means s/2
  double maxSurfaceGap = -1.0;  ///< mm, chord-to-surface distance allowed; < 0 means s/4
};

/// A point on the layer surface and the surface's unit normal there.
struct SurfacePoint {
  Vec3 point = Vec3::Zero();    ///< mm, part frame
  Vec3 normal = Vec3::UnitZ();  ///< unit
};

/// Projects a point (mm, part frame) onto the layer surface (the closest point) with its normal.
using SurfaceProjection = std::function<SurfacePoint(const Vec3&)>;

struct ConnectedInsetResult {
  std::size_t arcStartsBefore = 0;  ///< paths before joining
  std::size_t arcStartsAfter = 0;   ///< paths after joining
  std::size_t links = 0;            ///< step-overs made
  std::size_t rejectedLinks = 0;    ///< candidate step-overs not admissible (see file comment)
  /// First point of every ring part (the arc start of each path and where each link reaches its
  /// ring), in deposition order: the next layer keeps its seams away from all of them.
  std::vector<Vec3> seams;
};

/// Joins consecutive rings of one layer (see the file comment), in place.
/// @param paths    the layer's paths in deposition order; rings start at their seams
/// @param levels   per path: the iso-line level it was extracted at (k of the value list), or −1
///                 for a path that is not to be joined (open pieces, centre beads)
/// @param project  onto the layer surface (link points)
/// @throws InvalidInput for bad options or `levels` of another size than `paths`.
ConnectedInsetResult connectInsets(std::vector<PlanPath>& paths, const std::vector<int>& levels,
                                   const SurfaceProjection& project,
                                   const ConnectedInsetOptions& options = {});

/// One stretch of a joined path: a ring part or a link, as point index range [first, last].
struct JoinedPathPart {
  std::size_t first = 0;
  std::size_t last = 0;  ///< inclusive
  bool ring = false;     ///< a ring part (points[first] == points[last]) or a link
};

/// The ring parts and links of a path as connectInsets builds them: a ring part runs from a point
/// to the next exact repeat of it; the points between two ring parts are the link (a link part
/// shares its end points with the ring parts around it). A closed path is one ring part over all
/// its points (its closing segment implied); an open path with no repeated first point is one
/// non-ring part over all of it.
std::vector<JoinedPathPart> splitJoinedPath(const PlanPath& path);

}  // namespace curvedslicer
