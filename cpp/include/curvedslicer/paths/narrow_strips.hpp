// Narrow strips where the contour-parallel fronts meet: the planner rule that keeps the
// bead paths of one layer at least 0.95·s apart where an iso-line comes close to its own opposite
// side (the innermost ring of a thin region, whose sides are 2·(m − c) apart at the GDTC ridge m)
// or to another iso-line of the same value (two fronts meeting, e.g. a hole's and the rim's).
//
// Method, per iso-value (level):
//   1. Detection: every line is sampled at `sampleSpacing`; a sample is *narrow* when a sample of
//      the same level closer than δ = minSeparation·s + margin exists on another line, or on the
//      same line further than `arcExclusion` (default π·s/2) along it. The arc exclusion spares
//      legitimate neighbours on a tight curve: on any curve whose radius of curvature is at least
//      s/2 two points π·s/2 apart along it are at least s apart in space. The margin (the planner
//      passes 2 × the fit tolerance) keeps the fitted paths at 0.95·s when each moves by up to the
//      fit tolerance. A wide stretch shorter than `minLength` between narrow samples of one line,
//      facing a point within 1.25·δ, counts as narrow too (a strip whose width wavers around δ
//      gives one centre bead, not short pieces and gaps).
//   2. Narrow runs (maximal stretches of narrow samples) are paired with the run their nearest
//      samples lie on. Each pair becomes ONE centre bead: the midpoints between every sample and
//      its nearest point (refined onto the facing segments), an open line; a pair that covers two
//      whole closed lines (two fronts meeting all round) gives a closed centre ring. Where the two
//      runs of a pair are joined by a short turn of the same line (the cap of a thin loop, at most
//      1.5 × the arc exclusion long), the cap is dropped and the centre bead extended to the
//      cap's middle, so the bead reaches as far as the ring did.
//      A pair whose centre bead would be shorter than `minLength` once it gives up δ at each end
//      that meets a kept piece (an acute corner of a ring, a brief pinch) is not replaced: the
//      paths stay as they are there (a local overlap rather than a hole), and it is reported.
//   3. The rest of every line is kept: closed lines without narrow samples stay closed rings, the
//      others are cut into open pieces between the runs.
//   4. Leftover strips (optional input `innerEdges`, the iso-lines at c + s/2 + u, just inside
//      the inner edge of the beads at c): where the next level has no ring (the GDTC ridge m lies
//      between c + s/2 and c + s), these lines enclose a strip 2·(m − c) − s wide that no bead
//      covers. Their facing sides are paired as in 2 and give a centre bead on the ridge; in 5 it
//      keeps only the stretches where it is δ from the beads at c, i.e. where the strip is at
//      least 2·δ − s (≈ 0.9·s) wide — a narrower strip cannot take a bead without overlapping
//      its neighbours by more than 5 %, so it is left empty and reported. Stretches of these
//      lines within s/2 − u + s/4 of a ring of the next level are ignored (that ring fills them).
//   5. Clearance: pieces shorter than `minLength` are dropped; then every open centre bead, the
//      longest first, keeps only its stretches that are δ from the pieces of its own and the
//      neighbouring levels, from the centre beads kept before it, and from itself beyond the arc
//      exclusion; then the ends of open pieces are shortened until they are δ from every path of
//      their level. Stretches shorter than `minLength` are dropped.
// A centre bead in place of a thin ring fills one bead width s of a strip d + s wide (d < δ the
// separation of the two replaced stretches), so the strip is under-filled by up to d/2 on each
// side; that strip is never narrower than one bead, so such centre beads are dropped only for
// their length (< minLength, the planner's fragment rule). Every replacement, drop, shortening
// and leftover strip is reported in `warnings`.
//   6. Linking: an end of a centre bead at most `linkDistance` (default 1.25·δ, the gap step 5
//      leaves between a ring's open piece and the bead that continues it) from an end of another
//      open path of the level is joined to it by a straight connector, nearest pairs first, when
//      the connector stays s/2 from every other path of the level and the join does not close a
//      chain on itself: the ring piece and its centre bead become one path, one arc start.
// Preconditions: iso-lines of one surface (part frame, mm), spacing s > 0. Cost: O(N) grid
// queries per level for N = total length / sampleSpacing samples (uniform hash grid, cell δ).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

struct NarrowStripOptions {
  double minSeparation = 0.95;  ///< fraction of s: paths of one level closer than this are narrow
  double margin = 0.1;          ///< mm added to minSeparation·s (planner: 2 × fit tolerance)
  double arcExclusion = -1.0;   ///< mm along a line not compared with itself; < 0 means π·s/2
  double sampleSpacing = -1.0;  ///< mm, detection sampling; < 0 means s/16
  double minLength = -1.0;      ///< mm, shorter centre beads and pieces are dropped; < 0 means s
  /// u, mm (> 0): the inner-edge lines lie at c + s/2 + u; strips narrower than 2·u go unnoticed.
  double innerEdgeOffset = 0.2;
  /// mm; a centre bead's end at most this far from an open path's end of the same level is
  /// joined to it (step 6); < 0 means 1.25·(minSeparation·s + margin); 0 disables linking.
  double linkDistance = -1.0;
};

struct NarrowStripResult {
  /// The paths per level, same order as the input levels: kept rings, open pieces, centre beads.
  std::vector<std::vector<Polyline>> levels;
  /// Per level, per path: true for a centre bead (the midline of a narrow strip), or a path a
  /// centre bead was joined to (step 6).
  std::vector<std::vector<bool>> centreBead;
  std::vector<std::string> warnings;   ///< one sentence per replacement, drop or shortening
  std::size_t centreBeads = 0;         ///< centre beads kept
  std::size_t droppedCentreBeads = 0;  ///< centre beads shorter than minLength
  std::size_t droppedCaps = 0;         ///< turns of thin loops replaced by a centre bead's end
  std::size_t shortenedEnds = 0;       ///< path ends shortened for clearance
  double closestBefore = kInf;         ///< mm, closest narrow pair found (kInf: none below δ)
  double widestUnderfill = 0.0;        ///< mm, largest d/2 beside a centre bead
  std::size_t links = 0;               ///< connectors joining a centre bead to an open path
  std::size_t keptShortStretches = 0;  ///< narrow stretches too short for a bead, kept as they are
};

/// Applies the rule above to the iso-lines of one layer.
/// @param levels       iso-lines per iso-value, in increasing value order (part frame, mm)
/// @param levelValues  the iso-values (mm), same size as `levels`; used in the warnings
/// @param spacing      bead spacing s, mm
/// @param innerEdges   empty, or per level the iso-lines at levelValues[k] + s/2 +
///                     options.innerEdgeOffset (step 4)
/// @throws InvalidInput for spacing ≤ 0 or non-finite, bad options, or mismatched sizes.
NarrowStripResult resolveNarrowStrips(const std::vector<std::vector<Polyline>>& levels,
                                      const std::vector<double>& levelValues, double spacing,
                                      const NarrowStripOptions& options = {},
                                      const std::vector<std::vector<Polyline>>& innerEdges = {});

}  // namespace curvedslicer
