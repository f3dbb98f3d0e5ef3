// The deposition plan (paper §3.1 and the first part of §3.2): equidistant bead paths on
// every curved layer, ordered, with seams staggered and a deposition direction per point.
//
// Per layer (`planLayers`), bottom to top:
//   0. surface index ("surface index"): the layer's closest-point tree and vertex normals;
//   1. initial curve ("initial curves"): (a) Boundary — the layer's boundary loops (the paper's
//      blade case), paths at GDTC = (k + ½)·s so the outer bead's edge sits on the part edge;
//      (b) Plane / Surface — the section of the layer with a user plane or surface mesh (the
//      paper's "intersection of a user-input surface and the STL model"), paths at k·s on both
//      sides, k = 0 being the section itself;
//   2. GDTC ("surface geodesic"): paths/surface_geodesic.hpp, the curve inserted into the mesh;
//   3. iso-lines ("iso-lines"): paths/iso_lines.hpp; pieces shorter than `minPathLength` are
//      dropped (counted in the layer's warnings); where paths of one level come closer than
//      0.95·s, `narrowStrips` (default CentreBead: paths/narrow_strips.hpp) puts one centre bead
//      instead, joined to the ring piece it continues, and reports it in the layer's warnings;
//   4. fit ("fit"): paths/path_fit.hpp (smoothing cubic B-spline within `fitTolerance`, resampled
//      at `pointSpacing`); the points are then projected onto the layer surface and get its
//      normal (area-weighted vertex normals interpolated on the closest triangle);
//   5. order ("order"): paths/ordering.hpp, from the previous layer's end, seams `seamSeparation`
//      (2·s) from its seams; `connectInsets` joins rings (paths/connected_insets.hpp);
//   6. deposition ("deposition"): paths/deposition.hpp — first layer: the start surface and the
//      earlier beads of the layer; later layers: the previous layer surface;
//   7. coverage ("coverage", when `measureCoverage`): paths/coverage.hpp, the share of the layer
//      surface no bead covers and the share two beads cover, into PlanLayer::coverage (thin
//      walls: not measured).
// `planThinWall` (the paper's turbine base): a wall surface and one of its boundary loops (the
// edge on the substrate); curves at GDTC = k·s, k = 1, 2, …, each one bead and one plan layer;
// the normal of a point is the surface direction of increasing GDTC (the wall's growth
// direction); V points to the nearest point of the previous bead (bead 1: of the edge).
//
//   4b. corner fill (Boundary only, `cornerFill`; "iso-lines"): paths/corner_fill.hpp — the
//      outer ring dips into the layer's acute convex corners, its bead's edge at most
//      `cornerOverdeposit` past the boundary;
//   3b. thin regions (Boundary only; "iso-lines"): paths/thin_regions.hpp — a connected part of
//      the layer that no ring reaches gets a bead on its centre line, a spot (2 points, dwell
//      w / spotWeldSpeed) when it is a tiny island, or keeps its short ring; narrower than s: a
//      note with the shortfall; narrower than `minFeatureWidth`: left out and reported;
// Problems of one layer (no boundary, an initial curve that misses it, no room for a bead) are
// written into PlanLayer::warnings and the layer keeps no paths; when no layer gets a path at all
// the call throws InvalidInput naming the reason (e.g. the spacing is wider than every layer).
// Preconditions: layer surfaces as extractLayers returns them (indexed, oriented towards
// increasing distance), part frame, mm. Cost: per layer O(V log V) for GDTC plus the fits
// (paths/path_fit.hpp) and one closest-point query per path point.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/layers/layer_extraction.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/deposition.hpp"
#include "curvedslicer/paths/ordering.hpp"
#include "curvedslicer/paths/surface_geodesic.hpp"
#include "curvedslicer/plan/plan.hpp"

namespace curvedslicer {

/// How the initial curve of every layer is chosen.
enum class InitialCurveKind {
  Boundary,  ///< the layer's boundary loops; contour-parallel paths inward at (k + ½)·s
  Plane,     ///< the section with a plane; parallel paths on both sides at k·s
  Surface,   ///< the section with a user surface mesh; parallel paths on both sides at k·s
};

/// "boundary" | "plane" | "surface" (the Python module's names of the kinds).
std::string_view toString(InitialCurveKind kind);
/// @throws InvalidInput naming the text and the choices.
InitialCurveKind parseInitialCurveKind(std::string_view name);

struct InitialCurve {
  InitialCurveKind kind = InitialCurveKind::Boundary;
  Vec3 planePoint = Vec3::Zero();    ///< Plane: a point of the plane, part frame, mm
  Vec3 planeNormal = Vec3::UnitX();  ///< Plane: its normal (need not be unit length)
  TriMesh surface;                   ///< Surface: the user surface, part frame, mm
  std::string describe() const;      ///< e.g. "boundary", "plane:0,0,0,1,0,0", "surface"
};

/// What happens where contour-parallel fronts meet and paths of one level come closer than
/// 0.95·s (the innermost ring of a thin region, a hole's front meeting the rim's).
enum class NarrowStripMode {
  CentreBead,  ///< paths/narrow_strips.hpp: one centre bead instead, joined to its ring piece
  Overlap,     ///< keep the iso-lines as they are; their beads overlap there
};

/// "centre_bead" | "overlap" (the command line's and the plan file's names).
std::string narrowStripModeName(NarrowStripMode mode);
/// @throws InvalidInput for another name.
NarrowStripMode parseNarrowStripMode(const std::string& name);

struct PlannerOptions {
  double beadSpacing = 3.7;    ///< s, mm, distance between neighbouring bead centre lines (> 0)
  double pointSpacing = 2.0;   ///< mm, largest distance between robot points (> 0)
  double fitTolerance = 0.05;  ///< mm, spline fit tolerance (> 0)
  /// Degrees, in (0, 180]: where a path turns by more than this within 0.2 mm, the fit keeps the
  /// raw vertex as an exact corner (paths/path_fit.hpp); 180 keeps none.
  double cornerAngle = 30.0;
  InitialCurve initialCurve;        ///< default: the layer boundary
  SurfaceGeodesicOptions geodesic;  ///< GDTC method (default: accurate) and curve tolerance
  /// mm; iso-line pieces shorter than this are not deposited; < 0 means s (one bead width).
  double minPathLength = -1.0;
  /// mm; smallest distance between seams of consecutive layers; < 0 means 2·s.
  double seamSeparation = -1.0;
  int improvementPasses = 4;  ///< 2-opt passes of the ordering (paths/ordering.hpp)
  /// Where paths of one level come closer than 0.95·s (default: one centre bead).
  NarrowStripMode narrowStrips = NarrowStripMode::CentreBead;
  DepositionOptions deposition;
  /// mm; a region (or strip) narrower than one bead but at least this wide gets a single
  /// bead on its centre line and a note with the shortfall; narrower ones are left out and
  /// reported with size and location; < 0 means 0.5·s.
  double minFeatureWidth = -1.0;
  /// Adaptive bead width: bead widths may vary per point within
  /// [widthMin·s, widthMax·s] (fractions of s); widthMin = widthMax = 1 is a fixed width s.
  /// Must satisfy 0 < widthMin <= 1 <= widthMax.
  double widthMin = 1.0;
  double widthMax = 1.0;
  /// Consecutive rings of one region joined by a short step-over inside the layer into
  /// one arc-on path (fewer arc starts).
  bool connectInsets = true;
  /// The uncovered strips the beads leave (between rings of one level, in corners) get
  /// a bead on their centre line when at least minFeatureWidth wide (paths/gap_fill.hpp); the
  /// beads beside narrower strips between beads grow into them (paths/bead_widening.hpp).
  bool fillGaps = true;
  /// Gap fill: mm², smallest uncovered patch that gets a fill bead (smaller ones stay
  /// empty; GapFillOptions::minGapArea); < 0 means s².
  double minGapArea = -1.0;
  /// Corner fill (paths/corner_fill.hpp): at an acute convex corner of the layer
  /// boundary the outer ring dips toward the corner so its bead covers the corner's wedge.
  bool cornerFill = true;
  /// mm, how far a corner-fill bead's edge may pass the layer boundary (stock allowance);
  /// < 0 means s/4.
  double cornerOverdeposit = -1.0;
  /// Degrees, in (0, 180): corner fill takes corners of the layer boundary sharper than this
  /// (CornerFillOptions::maxCornerAngle; default: acute corners).
  double cornerFillAngle = 85.0;
  /// Measure every layer's coverage (paths/coverage.hpp) into PlanLayer::coverage.
  bool measureCoverage = true;
  /// Thin regions (paths/thin_regions.hpp): mm/s, the weld speed a spot's dwell is
  /// reckoned with. A spot (a tiny island) dwells w / spotWeldSpeed seconds, the time the torch
  /// takes to lay one bead width of bead, so it deposits about one bead's worth (a round deposit
  /// w across). Default: the default cell's weld speed (robot/cell.hpp ProcessDescription).
  double spotWeldSpeed = 8.0;
  /// Threads planning layers (>= 0): their surface index, initial curves, surface geodesic,
  /// iso-lines and fit run in parallel (up to 4 layers per thread ahead), while ordering,
  /// connected insets, deposition and coverage run layer by layer in order on the calling thread
  /// (they carry the torch, the seams and the support from one layer to the next), which drafts
  /// layers too while it waits. 0: OpenMP's default (OMP_NUM_THREADS, else the cores). The plan
  /// is the same for any number.
  int threads = 0;
};

/// Which boundary loop of a wall surface is the edge it grows from.
enum class WallEdgeKind {
  LowestAlongAxis,  ///< the loop whose lowest point along `axis` is lowest (e.g. on the plate)
  NearestToPoint,   ///< the loop nearest to `point`
};

/// "lowest" | "nearest" (the names in the thin-wall edge spec, pipeline/option_parsing.hpp, and
/// the Python module's `edge` argument).
std::string_view toString(WallEdgeKind kind);
/// @throws InvalidInput for another name, listing the choices.
WallEdgeKind parseWallEdgeKind(std::string_view name);

struct ThinWallOptions {
  double beadSpacing = 1.65;   ///< mm, distance between beads along the surface (bead height)
  double pointSpacing = 2.0;   ///< mm (> 0)
  double fitTolerance = 0.05;  ///< mm (> 0)
  double cornerAngle = 30.0;   ///< degrees, in (0, 180] (as PlannerOptions::cornerAngle)
  WallEdgeKind edge = WallEdgeKind::LowestAlongAxis;
  Vec3 axis = Vec3::UnitZ();  ///< LowestAlongAxis: the "up" direction, part frame
  Vec3 point = Vec3::Zero();  ///< NearestToPoint: part frame, mm
  SurfaceGeodesicOptions geodesic;
  double minPathLength = -1.0;   ///< mm; < 0 means s
  double seamSeparation = -1.0;  ///< mm; < 0 means 2·s
  int improvementPasses = 4;
  DepositionOptions deposition;
};

/// Time of one planner stage, summed over layers (with PlannerOptions::threads > 1, over the
/// threads too: the stages before ordering then add up to more than the wall time).
struct PlanStageTime {
  std::string name;  ///< "surface index" (closest-point tree and normals of the layer),
                     ///< "initial curves", "surface geodesic", "iso-lines", "fit", "order",
                     ///< "deposition", "coverage"
  double seconds = 0.0;
};

struct PlanStats {
  std::vector<PlanStageTime> stageTimes;
  DepositionStats deposition;
  std::size_t droppedFragments = 0;  ///< iso-line pieces shorter than minPathLength
  std::size_t seamsTooClose = 0;     ///< rings whose seam could not keep the separation
  std::size_t insetLinks = 0;        ///< connected insets: step-overs joining two rings
  double travel = 0.0;               ///< mm, straight-line travel over the whole plan
  double arcLength = 0.0;            ///< mm, deposited length
  double maxFitDeviation = 0.0;      ///< mm, largest spline-to-iso-line deviation
  std::size_t layersWithoutPaths = 0;
};

struct PlanResult {
  /// parameters.beadSpacing, pointSpacing, fitTolerance, surfaceMethod and initialCurve are set;
  /// model, start, layerThickness, voxelSize, fieldMethod and PlanLayer::surface are left to the
  /// caller.
  Plan plan;
  PlanStats stats;
};

/// Checks the options without touching geometry. @throws InvalidInput naming the parameter.
void validatePlannerOptions(const PlannerOptions& options);
void validateThinWallOptions(const ThinWallOptions& options);

/// Plans every layer (see the file comment). Progress stages as the step names above.
/// @param layers        the layer surfaces, bottom to top (extractLayers().surfaces)
/// @param startSurface  the start-surface triangles (deposited material under the first layer;
///                      may be empty)
/// @throws InvalidInput for bad options, no layers, or no path on any layer (the message gives
///         the reason of the first layer); NumericalFailure from the stages; Cancelled.
PlanResult planLayers(const std::vector<LayerSurface>& layers, const TriMesh& startSurface,
                      const PlannerOptions& options = {}, Progress progress = {});

/// Plans a thin wall (see the file comment).
/// @param surface  the wall's surface, open, indexed, part frame, mm
/// @throws InvalidInput for bad options, a surface without a boundary loop, a wall lower than
///         one bead; NumericalFailure, Cancelled.
PlanResult planThinWall(const TriMesh& surface, const ThinWallOptions& options = {},
                        Progress progress = {});

}  // namespace curvedslicer
