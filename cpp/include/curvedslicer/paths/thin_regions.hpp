// Thin features and small islands: the beads of the parts of a layer that the
// contour-parallel rings leave without any bead — a branch's cross-section narrower than one bead,
// a cap, a thin fin cut off from the rest of the layer.
//
// Method, per region (a connected part of the layer where the distance to the layer's boundary,
// GDTC, is known; connected through shared triangle edges) that holds no bead of the rings:
//   1. Short rings: a closed iso-line shorter than the planner's fragment length that lies in the
//      region is its only cover (a small disc with a ring at s/2 whose bead covers it all): it is
//      kept as it is.
//   2. Width: W = 2·m, m the inscribed half-width: the largest straight distance to the region's
//      boundary edges over its vertices and a barycentric grid (step 1/4) on its triangles (the
//      vertex GDTC alone underestimates m on a region a few edges wide). W below the minimum
//      feature width: the region is left out and reported with its size and location.
//   3. Centre line (medial axis): the GDTC ridge, found as a longest path along it. Edges cost
//      ℓ/(d̄ + 0.1·m)² (ℓ the edge length, d̄ the mean GDTC of its ends), so cheapest paths run along
//      the ridge; from the highest vertex the tree-farthest vertex with GDTC ≥ m/2 (arc length
//      along the cheapest path) is one end A, the tree-farthest such vertex from A the other end
//      B, and the cheapest path A→B is the centre line. It is resampled, smoothed by two box
//      filters as wide as the mean edge (the vertex path zig-zags by up to half an edge). Each end
//      then moves along the line's direction there (taken between w and 2·w from the end, past a
//      dip into a corner) until the bead's round end, w/2 beyond it, just reaches the region's
//      tip — the farthest boundary point ahead within w/2 of the line: trimmed where the tip is
//      closer than w/2, extended straight where it is farther (w the region's bead width).
//   4. Tiny island: when less than w/4 is left after moving the ends (the centre line is shorter
//      than about one bead), the region gets a spot: two points `spotSeparation` apart along the
//      centre line at the inscribed disc's centre, to be deposited with a dwell (the planner
//      states the dwell rule).
// A region narrower than one bead (W < s) gets one bead and a note with the shortfall s − W.
// Bead widths: s when widthMin = widthMax = 1 (fixed); otherwise the local width 2·d (d the larger
// of the interpolated GDTC and the straight distance to the region's boundary edges at the point
// of the centre line) clamped to [widthMin·s, widthMax·s].
// Preconditions: the GDTC from the layer's boundary (InitialCurveKind::Boundary) on an indexed
// mesh, part frame, mm. Cost: per region without beads O(V log V) (two Dijkstra searches) and
// O(T·R) for the inscribed disc (T triangles, R boundary edges); one closest-point query per
// point of the rings.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

struct ThinRegionOptions {
  double beadSpacing = 3.7;       ///< s, mm (> 0)
  double minFeatureWidth = -1.0;  ///< mm; narrower regions are left out; < 0 means 0.5·s
  double widthMin = 1.0;          ///< fraction of s, smallest bead width (adaptive width)
  double widthMax = 1.0;          ///< fraction of s, largest bead width; min = max = 1: fixed s
  double spotSeparation = 0.1;    ///< mm between the two points of a spot (≥ 0.05)
};

/// What a thin region got.
enum class ThinBeadKind {
  CentreLine,  ///< an open bead on the region's centre line
  Spot,        ///< two points `spotSeparation` apart, to be deposited with a dwell
  KeptRing,    ///< a closed ring shorter than the fragment length, the only cover of its region
};

struct ThinBead {
  ThinBeadKind kind = ThinBeadKind::CentreLine;
  Polyline line;       ///< part frame, mm; on (CentreLine, Spot) or near (KeptRing) the mesh
  double width = 0.0;  ///< mm, bead width at the region's widest point (spot: its width)
};

/// One region without a ring bead and what became of it.
struct ThinRegion {
  Vec3 centroid = Vec3::Zero();  ///< area-weighted centroid of the region, part frame, mm
  double width = 0.0;            ///< W = 2·m, mm
  double extent = 0.0;           ///< mm, largest side of its bounding box
  double area = 0.0;             ///< mm²
  bool leftOut = false;          ///< narrower than the minimum feature width: no bead
  ThinBeadKind kind = ThinBeadKind::CentreLine;  ///< when not left out
};

struct ThinRegionResult {
  std::vector<ThinBead> beads;
  std::vector<ThinRegion> regions;  ///< every region that held no ring bead, in label order
  std::size_t regionCount = 0;      ///< regions of the layer (with and without ring beads)
};

/// The regions of one layer and their GDTC, queried for the beads of the regions the rings miss.
/// Its closest-point tree and region rims are built on first use (layers whose regions all hold
/// a ring bead need neither), so one planner must not be used by two threads at once.
class ThinRegionPlanner {
 public:
  /// @param mesh      the layer surface the GDTC lives on (SurfaceGeodesicResult::mesh)
  /// @param distance  GDTC from the layer's boundary per vertex of `mesh`, mm (+inf: unreached)
  /// @throws InvalidInput for a size mismatch or bad options (naming the option).
  ThinRegionPlanner(const TriMesh& mesh, const std::vector<double>& distance,
                    const ThinRegionOptions& options = {});
  ~ThinRegionPlanner();
  ThinRegionPlanner(const ThinRegionPlanner&) = delete;
  ThinRegionPlanner& operator=(const ThinRegionPlanner&) = delete;

  /// Beads for the regions that none of `beads` (the ring beads kept, part frame, on the mesh)
  /// touches. `shortRings`: closed iso-lines shorter than the fragment length (step 1).
  ThinRegionResult plan(const std::vector<Polyline>& beads,
                        const std::vector<Polyline>& shortRings) const;

  /// Bead width at each of `points` (on the mesh): s when fixed, else 2·d clamped (file comment).
  std::vector<double> widthsAt(const std::vector<Vec3>& points) const;

  /// The region's local width 2·d at each of `points` (file comment, "Bead widths"), unclamped,
  /// mm; 0 off the regions.
  std::vector<double> localWidthsAt(const std::vector<Vec3>& points) const;

  /// The bead width for a region of width W: s when fixed, else W clamped.
  double beadWidthFor(double regionWidth) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace curvedslicer
