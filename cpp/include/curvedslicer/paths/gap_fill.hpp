// Gap fill: beads for the strips of a layer that its beads leave
// uncovered — between two rings of one level that run 1–2 bead widths apart where the next level
// has no ring, in corners where rings turn, between a ring and a thin-region bead.
//
// Method, on one layer:
//   1. Uncovered clearance per vertex: c = min(GDTC, min over the beads of (|v − bead| − w/2))
//      (w the bead's width at its closest point, interpolated along the segment; a vertex farther
//      than `reach` from every bead gets min(GDTC, reach)). c > 0 where no bead covers the vertex;
//      c is then the straight distance to the nearest covered point or the layer's boundary.
//   2. The layer mesh is clipped to c ≥ 0 (each triangle cut along the linear zero of c on its
//      edges, shared cut points shared between neighbours): the uncovered patches with c on them,
//      their rims the edges of the beads and of the layer.
//   3. Every patch is a region for the thin-region planner (paths/thin_regions.hpp, no ring
//      beads): its width W = 2·m from its inscribed disc, its centre line (medial axis) with ends
//      fitted so the bead's round end reaches the patch's tip, or a spot on a tiny patch.
//   4. A patch gets its bead when W ≥ minGapWidth and its area ≥ minGapArea; smaller patches stay
//      (a bead there would mostly cover what is covered already: overlap, not coverage). Of a
//      centre line only the stretches where the patch's local width 2·c is at least minGapWidth
//      and that are at least minRunLength long are kept (a band along a ring that widens only at
//      the corners gets no bead along its narrow stretches).
// Bead widths: s at a fixed width (widthMin = widthMax = 1); otherwise the patch's local width 2·d
// clamped to [widthMin·s, widthMax·s], so a strip narrower than a bead gets a narrower bead.
// Preconditions: GDTC from the layer's boundary on an indexed mesh, beads on (or near) it, part
// frame, mm. Cost: O(V·b) for the clearance (b the bead segments within reach of a vertex) plus
// the thin-region planner's cost on the patches (small: the uncovered area).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/polyline.hpp"
#include "curvedslicer/paths/thin_regions.hpp"

namespace curvedslicer {

struct GapFillOptions {
  double beadSpacing = 3.7;    ///< s, mm (> 0)
  double minGapWidth = -1.0;   ///< mm; narrower patches stay empty; < 0 means 0.5·s
  double minGapArea = -1.0;    ///< mm²; smaller patches stay empty; < 0 means s²
  double widthMin = 1.0;       ///< fraction of s, smallest bead width (adaptive width)
  double widthMax = 1.0;       ///< fraction of s, largest bead width; min = max = 1: fixed s
  double minRunLength = -1.0;  ///< mm; shorter stretches of a centre line stay; < 0 means 0.5·s
  double reach = -1.0;         ///< mm, largest clearance looked for (step 1); < 0 means s
  bool allowSpots = true;      ///< a short patch gets a spot (dwell); false: it stays empty
};

/// A bead already on the layer: its centre line and width.
struct LayerBead {
  const Polyline* line = nullptr;  ///< part frame, mm (not owned)
  std::vector<double> widths;      ///< mm per point of `line`; empty: s
};

/// The fill beads of one layer.
struct GapFillResult {
  std::vector<ThinBead> beads;    ///< CentreLine or Spot, part frame, on the layer mesh
  std::vector<ThinRegion> gaps;   ///< every uncovered patch, in label order
  std::size_t filled = 0;         ///< patches that got a bead
  double uncoveredArea = 0.0;     ///< mm², all patches (before the fill)
  double filledArea = 0.0;        ///< mm², the patches that got a bead
  std::vector<double> clearance;  ///< c per vertex of the layer mesh, mm (step 1)
};

/// The uncovered clearance c (step 1) per vertex of `mesh`.
/// @param distance  GDTC from the layer's boundary per vertex, mm (+inf: unreached)
/// @param beads     the layer's beads
/// @param beadSpacing, reach  mm
std::vector<double> computeUncoveredClearance(const TriMesh& mesh,
                                              const std::vector<double>& distance,
                                              const std::vector<LayerBead>& beads,
                                              double beadSpacing, double reach);

/// Plans the fill beads of one layer (see the file comment); widths through `widthsAt`.
class GapFillPlanner {
 public:
  /// @throws InvalidInput for a size mismatch or bad options (naming the option).
  GapFillPlanner(const TriMesh& mesh, const std::vector<double>& distance,
                 const std::vector<LayerBead>& beads, const GapFillOptions& options = {});
  ~GapFillPlanner();
  GapFillPlanner(const GapFillPlanner&) = delete;
  GapFillPlanner& operator=(const GapFillPlanner&) = delete;

  const GapFillResult& result() const { return result_; }

  /// Bead width at each of `points` (on the patches): s when fixed, else 2·d clamped.
  std::vector<double> widthsAt(const std::vector<Vec3>& points) const;

 private:
  void planPatches(const TriMesh& mesh, const std::vector<double>& distance,
                   const std::vector<LayerBead>& beads, const GapFillOptions& options);
  void addFill(const ThinRegion& gap, std::vector<ThinBead> beads);

  double beadSpacing_ = 0.0;
  TriMesh patches_;
  std::vector<double> patchClearance_;
  std::unique_ptr<ThinRegionPlanner> planner_;
  GapFillResult result_;
};

}  // namespace curvedslicer
