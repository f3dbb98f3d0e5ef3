#include "curvedslicer/paths/planner.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include <omp.h>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/paths/adaptive_width.hpp"
#include "curvedslicer/paths/bead_widening.hpp"
#include "curvedslicer/paths/connected_insets.hpp"
#include "curvedslicer/paths/corner_fill.hpp"
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/paths/gap_fill.hpp"
#include "curvedslicer/paths/iso_lines.hpp"
#include "curvedslicer/paths/narrow_strips.hpp"
#include "curvedslicer/paths/path_fit.hpp"
#include "curvedslicer/paths/polyline.hpp"
#include "curvedslicer/paths/surface_curves.hpp"
#include "curvedslicer/paths/thin_regions.hpp"
#include "paths_internal.hpp"

namespace curvedslicer {

namespace {

using paths_detail::formatNumber;

using Clock = std::chrono::steady_clock;

const char* const kStages[] = {"surface index", "initial curves", "surface geodesic", "iso-lines",
                               "fit",           "order",          "deposition",       "coverage"};
enum Stage { kIndex, kCurves, kGeodesic, kIso, kFit, kOrder, kDeposition, kCoverage, kStageCount };

std::string formatVec(const Vec3& v) {
  return formatNumber(v.x()) + "," + formatNumber(v.y()) + "," + formatNumber(v.z());
}

std::string describeKind(InitialCurveKind kind) {
  return kind == InitialCurveKind::Plane ? "plane" : "surface";
}

void checkCornerAngle(double degrees) {
  if (!std::isfinite(degrees) || degrees <= 0.0 || degrees > 180.0) {
    throw InvalidInput("corner angle must be in (0, 180] degrees: " + formatNumber(degrees) +
                       "; pass a value such as 30, or 180 to keep no corners");
  }
}

/// The bead coverage options: a minimum feature width > 0 (or < 0 for s/2), a width range that
/// contains the bead spacing.
void checkCoverageOptions(const PlannerOptions& o) {
  if (!std::isfinite(o.minFeatureWidth) || o.minFeatureWidth == 0.0) {
    throw InvalidInput(
        "minimum feature width (--min-feature-width, MinFeatureWidth) must be a "
        "positive number of mm: " +
        formatNumber(o.minFeatureWidth) + "; pass e.g. " + formatNumber(0.5 * o.beadSpacing) +
        " (half the bead spacing, the default)");
  }
  if (!std::isfinite(o.widthMin) || !std::isfinite(o.widthMax) || o.widthMin <= 0.0 ||
      o.widthMin > o.widthMax) {
    throw InvalidInput(
        "bead width range (--bead-width-range, BeadWidthMin/BeadWidthMax) must be "
        "two fractions of the bead spacing with 0 < min <= max: " +
        formatNumber(o.widthMin) + "," + formatNumber(o.widthMax) +
        "; pass e.g. 0.7,1.3, or off for a fixed width");
  }
  if (o.widthMin > 1.0 || o.widthMax < 1.0) {
    throw InvalidInput(
        "bead width range (--bead-width-range, BeadWidthMin/BeadWidthMax) excludes "
        "the bead spacing: " +
        formatNumber(o.widthMin) + "," + formatNumber(o.widthMax) +
        " × s = " + formatNumber(o.widthMin * o.beadSpacing) + "–" +
        formatNumber(o.widthMax * o.beadSpacing) + " mm, s = " + formatNumber(o.beadSpacing) +
        " mm; choose a range with min <= 1 <= max, e.g. 0.7,1.3, or off");
  }
  if (!std::isfinite(o.minGapArea) || o.minGapArea == 0.0) {
    throw InvalidInput(
        "minimum gap area (--min-gap-area, MinGapArea) must be a positive number "
        "of mm²: " +
        formatNumber(o.minGapArea) + "; pass e.g. " + formatNumber(o.beadSpacing * o.beadSpacing) +
        " (the bead spacing squared, the default)");
  }
  if (!(o.cornerFillAngle > 0.0 && o.cornerFillAngle < 180.0)) {
    throw InvalidInput(
        "corner fill angle (--corner-fill-angle, CornerFillAngle) must lie in "
        "(0, 180) degrees: " +
        formatNumber(o.cornerFillAngle) + "; pass e.g. 85 (acute corners)");
  }
  if (!std::isfinite(o.cornerOverdeposit)) {
    throw InvalidInput(
        "corner fill overdeposit (--corner-overdeposit) must be a finite number of mm: " +
        formatNumber(o.cornerOverdeposit) + "; pass e.g. " + formatNumber(0.25 * o.beadSpacing) +
        " (a quarter of the bead spacing, the default)");
  }
}

void checkPositive(double value, const char* what, const char* example) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw InvalidInput(std::string(what) + " must be a positive number of mm: " +
                       formatNumber(value) + "; pass a value such as " + example);
  }
}

/// The options both planners derive alike from theirs (PlannerOptions, ThinWallOptions), and the
/// plan parameters they record alike.
struct PathStages {
  template <typename Options>
  explicit PathStages(const Options& o)
      : minLength(o.minPathLength < 0.0 ? o.beadSpacing : o.minPathLength) {
    ordering.seamSeparation = o.seamSeparation < 0.0 ? 2.0 * o.beadSpacing : o.seamSeparation;
    ordering.improvementPasses = o.improvementPasses;
    fit.tolerance = o.fitTolerance;
    fit.pointSpacing = o.pointSpacing;
    fit.cornerAngle = o.cornerAngle;
  }
  template <typename Options>
  void record(const Options& o, PlanParameters& p) const {
    p.beadSpacing = o.beadSpacing;
    p.pointSpacing = o.pointSpacing;
    p.fitTolerance = o.fitTolerance;
    p.cornerAngle = o.cornerAngle;
    p.surfaceMethod = std::string(toString(o.geodesic.method));
    p.depositionDirection = depositionMethodName(o.deposition.method);
  }

  double minLength;  ///< mm, shortest deposited piece
  OrderingOptions ordering;
  PathFitOptions fit;
};

class StageTimer {
 public:
  explicit StageTimer(PlanStats& stats) : stats_(stats), seconds_(kStageCount, 0.0) {}
  template <typename F>
  auto run(Stage stage, F&& f) {
    const auto begin = Clock::now();
    struct Add {
      StageTimer* t;
      Stage s;
      Clock::time_point b;
      ~Add() { t->seconds_[s] += std::chrono::duration<double>(Clock::now() - b).count(); }
    } add{this, stage, begin};
    return f();
  }
  /// Adds another timer's seconds (a layer timed on another thread).
  void add(const StageTimer& other) {
    for (int s = 0; s < kStageCount; ++s) seconds_[s] += other.seconds_[s];
  }
  void finish() {
    stats_.stageTimes.clear();
    for (int s = 0; s < kStageCount; ++s) stats_.stageTimes.push_back({kStages[s], seconds_[s]});
  }

 private:
  PlanStats& stats_;
  std::vector<double> seconds_;
};

/// Area-weighted unit vertex normals (zero for isolated vertices).
std::vector<Vec3> computeVertexNormals(const TriMesh& mesh) {
  std::vector<Vec3> normals(mesh.vertexCount(), Vec3::Zero());
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 n = mesh.areaNormal(t);
    for (int k = 0; k < 3; ++k) normals[mesh.triangles[t][k]] += n;
  }
  for (Vec3& n : normals) {
    const double len = n.norm();
    if (len > 0.0) n /= len;
  }
  return normals;
}

Vec3 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = p - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 0.0)) return Vec3(1.0, 0.0, 0.0);
  const double v = (d11 * d20 - d01 * d21) / den;
  const double w = (d00 * d21 - d01 * d20) / den;
  return Vec3(1.0 - v - w, v, w);
}

/// A layer surface with what the planner asks of it: closest points and normals.
struct SurfaceQuery {
  const TriMesh* mesh = nullptr;
  TriangleBvh bvh;
  std::vector<Vec3> vertexNormals;

  explicit SurfaceQuery(const TriMesh& m)
      : mesh(&m), bvh(m), vertexNormals(computeVertexNormals(m)) {}

  /// The interpolated unit normal at a closest point of this surface.
  Vec3 normalAt(const ClosestPoint& c) const {
    const Vec3i& tri = mesh->triangles[c.triangle];
    const Vec3 w = barycentric(c.point, mesh->vertices[tri[0]], mesh->vertices[tri[1]],
                               mesh->vertices[tri[2]]);
    Vec3 n =
        w[0] * vertexNormals[tri[0]] + w[1] * vertexNormals[tri[1]] + w[2] * vertexNormals[tri[2]];
    if (!(n.norm() > 1e-12)) n = mesh->areaNormal(c.triangle);
    return n.normalized();
  }
};

/// One bead before ordering: its points, per-point normals and (when set) widths, and its dwell.
struct RawBead {
  Polyline line;
  std::vector<Vec3> normals;
  std::vector<double> widths;  ///< mm per point; empty: PathPoint::width stays 0 (= s)
  double dwell = 0.0;          ///< s, spot deposit (thin regions)
};

/// What the level stage hands on besides the beads: the level of every bead (connected insets;
/// -1 = none) and the short closed iso-lines before and after the narrow-strip rule (thin regions).
struct LevelFit {
  std::vector<int> beadLevels;
  std::vector<Polyline> shortRings;
  std::vector<Polyline> fitWouldDrop;
};

/// Fits the iso-lines at one value and turns them into beads on the surface.
/// `normalOf` gives the normal at a projected point.
template <typename NormalFn>
void fitBeads(const std::vector<Polyline>& lines, double minLength, const PathFitOptions& fit,
              const TriangleBvh& projectOnto, NormalFn&& normalOf, std::vector<RawBead>& beads,
              PlanStats& stats, std::size_t& dropped) {
  for (const Polyline& raw : lines) {
    const std::size_t need = raw.closed ? 3 : 2;
    if (raw.points.size() < need || raw.length() < minLength) {
      ++dropped;
      continue;
    }
    PathFitResult fitted = fitPath(raw, fit);
    stats.maxFitDeviation = std::max(stats.maxFitDeviation, fitted.fitDeviation);
    RawBead bead;
    bead.line.closed = fitted.points.closed;
    ClosestPoint hint;
    for (const Vec3& p : fitted.points.points) {
      hint = projectOnto.closestPoint(p, hint);
      bead.line.points.push_back(hint.point);
      bead.normals.push_back(normalOf(hint));
    }
    // Projection can merge neighbouring points only where the spline folds; drop exact repeats.
    std::size_t w = 0;
    for (std::size_t i = 0; i < bead.line.points.size(); ++i) {
      if (w > 0 && (bead.line.points[i] - bead.line.points[w - 1]).norm() <= 1e-9) continue;
      bead.line.points[w] = bead.line.points[i];
      bead.normals[w] = bead.normals[i];
      ++w;
    }
    bead.line.points.resize(w);
    bead.normals.resize(w);
    if (bead.line.closed && w >= 2 &&
        (bead.line.points.back() - bead.line.points.front()).norm() <= 1e-9) {
      bead.line.points.pop_back();
      bead.normals.pop_back();
    }
    if (bead.line.points.size() < (bead.line.closed ? 3u : 2u)) {
      ++dropped;
      continue;
    }
    beads.push_back(std::move(bead));
  }
}

/// Orders the beads of one layer and appends them to `layer` (without deposition directions).
LayerOrder orderBeads(const std::vector<RawBead>& beads, int layerIndex,
                      const std::optional<Vec3>& torch, const std::vector<Vec3>& previousSeams,
                      const OrderingOptions& ordering, PlanLayer& layer) {
  std::vector<Polyline> lines;
  lines.reserve(beads.size());
  for (const RawBead& b : beads) lines.push_back(b.line);
  LayerOrder order = orderLayerPaths(lines, torch, previousSeams, ordering);
  for (std::size_t k = 0; k < order.paths.size(); ++k) {
    const OrderedPath& o = order.paths[k];
    const RawBead& b = beads[o.source];
    const std::vector<Vec3> points = applyOrder(b.line.points, b.line.closed, o);
    const std::vector<Vec3> normals = applyOrder(b.normals, b.line.closed, o);
    const std::vector<double> widths = applyOrder(b.widths, b.line.closed, o);
    PlanPath path;
    path.layer = layerIndex;
    path.index = static_cast<int>(k);
    path.closed = b.line.closed;
    path.length = b.line.length();
    path.dwell = b.dwell;
    path.points.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      path.points[i].position = points[i];
      path.points[i].normal = normals[i];
      path.points[i].deposition = -normals[i];
      if (i < widths.size()) path.points[i].width = widths[i];
    }
    layer.paths.push_back(std::move(path));
  }
  return order;
}

void finishStats(PlanResult& result, StageTimer& timer) {
  timer.finish();
  for (const PlanLayer& layer : result.plan.layers) {
    if (layer.paths.empty()) ++result.stats.layersWithoutPaths;
    for (const PlanPath& p : layer.paths) result.stats.arcLength += p.length;
  }
}

}  // namespace

std::string InitialCurve::describe() const {
  switch (kind) {
    case InitialCurveKind::Boundary:
      return "boundary";
    case InitialCurveKind::Plane:
      return "plane:" + formatVec(planePoint) + "," + formatVec(planeNormal);
    case InitialCurveKind::Surface:
      return "surface";
  }
  return "boundary";
}

std::string_view toString(InitialCurveKind kind) {
  switch (kind) {
    case InitialCurveKind::Boundary:
      return "boundary";
    case InitialCurveKind::Plane:
      return "plane";
    case InitialCurveKind::Surface:
      return "surface";
  }
  return "boundary";
}

InitialCurveKind parseInitialCurveKind(std::string_view name) {
  for (InitialCurveKind kind :
       {InitialCurveKind::Boundary, InitialCurveKind::Plane, InitialCurveKind::Surface}) {
    if (name == toString(kind)) return kind;
  }
  throw InvalidInput("unknown initial curve kind: '" + std::string(name) +
                     "'; choose boundary, plane or surface");
}

std::string_view toString(WallEdgeKind kind) {
  return kind == WallEdgeKind::NearestToPoint ? "nearest" : "lowest";
}

WallEdgeKind parseWallEdgeKind(std::string_view name) {
  if (name == "lowest") return WallEdgeKind::LowestAlongAxis;
  if (name == "nearest") return WallEdgeKind::NearestToPoint;
  throw InvalidInput("unknown thin-wall edge: '" + std::string(name) +
                     "'; choose lowest (the loop lowest along the axis) or nearest (the loop "
                     "nearest to the point)");
}

std::string narrowStripModeName(NarrowStripMode mode) {
  return mode == NarrowStripMode::Overlap ? "overlap" : "centre_bead";
}

NarrowStripMode parseNarrowStripMode(const std::string& name) {
  if (name == "centre_bead") return NarrowStripMode::CentreBead;
  if (name == "overlap") return NarrowStripMode::Overlap;
  throw InvalidInput("unknown narrow-strip mode: \"" + name +
                     "\"; pass centre_bead (one bead where paths of one level come closer than "
                     "0.95·s) or overlap (keep the overlapping paths)");
}

/// The narrow-strip notes of one layer: a summary line, then the first few notes in full.
void reportNarrowStrips(const NarrowStripResult& strips, std::vector<std::string>& warnings) {
  if (strips.warnings.empty()) return;
  std::string summary =
      "paths of one level closer than 0.95·s: " + std::to_string(strips.centreBeads) +
      " centre bead(s) put instead";
  if (strips.links > 0) {
    summary += ", " + std::to_string(strips.links) + " of them joined to the path they continue";
  }
  if (strips.keptShortStretches > 0) {
    summary += ", " + std::to_string(strips.keptShortStretches) +
               " short stretch(es) (e.g. acute corners) kept overlapping";
  }
  if (strips.droppedCentreBeads > 0) {
    summary += ", " + std::to_string(strips.droppedCentreBeads) +
               " strip(s) too short or too narrow for a bead left empty";
  }
  if (strips.shortenedEnds > 0) {
    summary += ", " + std::to_string(strips.shortenedEnds) + " path end(s) shortened";
  }
  warnings.push_back(summary + " (details follow)");
  constexpr std::size_t kDetails = 3;
  for (std::size_t i = 0; i < strips.warnings.size() && i < kDetails; ++i) {
    warnings.push_back(strips.warnings[i]);
  }
  if (strips.warnings.size() > kDetails) {
    warnings.push_back("… and " + std::to_string(strips.warnings.size() - kDetails) +
                       " more such note(s) on this layer");
  }
}

/// The options of the thin-region beads.
void validateThinRegionOptions(const PlannerOptions& o) {
  if (!std::isfinite(o.minFeatureWidth) || o.minFeatureWidth == 0.0) {
    throw InvalidInput("minimum feature width must be a positive number of mm: " +
                       formatNumber(o.minFeatureWidth) +
                       "; pass a value such as 1.85, or a negative one for half the bead spacing");
  }
  checkPositive(o.spotWeldSpeed, "spot weld speed (mm/s)", "8");
}

void validatePlannerOptions(const PlannerOptions& o) {
  checkPositive(o.beadSpacing, "bead spacing", "3.7");
  checkPositive(o.pointSpacing, "point spacing", "2");
  checkPositive(o.fitTolerance, "fit tolerance", "0.05");
  checkCornerAngle(o.cornerAngle);
  if (o.initialCurve.kind == InitialCurveKind::Plane &&
      (!o.initialCurve.planeNormal.allFinite() || !(o.initialCurve.planeNormal.norm() > 0.0) ||
       !o.initialCurve.planePoint.allFinite())) {
    throw InvalidInput("initial plane needs a finite point and a non-zero normal: " +
                       o.initialCurve.describe() + "; pass e.g. plane:0,0,0,1,0,0");
  }
  if (o.initialCurve.kind == InitialCurveKind::Surface && o.initialCurve.surface.empty()) {
    throw InvalidInput(
        "initial surface has no triangles: 0; pass a surface mesh that crosses the layers");
  }
  if (o.improvementPasses < 0) {
    throw InvalidInput("ordering improvement passes must not be negative: " +
                       std::to_string(o.improvementPasses) + "; pass 0 or more");
  }
  checkCoverageOptions(o);
  validateThinRegionOptions(o);
  if (o.threads < 0) {
    throw InvalidInput("planner threads must not be negative: " + std::to_string(o.threads) +
                       "; pass 0 (OpenMP's default) or a number of threads");
  }
}

void validateThinWallOptions(const ThinWallOptions& o) {
  checkPositive(o.beadSpacing, "bead spacing", "1.65");
  checkPositive(o.pointSpacing, "point spacing", "2");
  checkPositive(o.fitTolerance, "fit tolerance", "0.05");
  checkCornerAngle(o.cornerAngle);
  if (o.edge == WallEdgeKind::LowestAlongAxis && (!o.axis.allFinite() || !(o.axis.norm() > 0.0))) {
    throw InvalidInput("thin-wall axis must be a finite non-zero vector: " + formatVec(o.axis) +
                       "; pass e.g. 0,0,1");
  }
  if (o.edge == WallEdgeKind::NearestToPoint && !o.point.allFinite()) {
    throw InvalidInput("thin-wall edge point is not finite: " + formatVec(o.point) +
                       "; pass a point in mm");
  }
}

namespace {

/// The stages both planners run on every layer (thin wall: every bead) after the iso-lines —
/// fit, order, deposition — with what they carry from one layer to the next (the torch position,
/// the seams) and the statistics they add to.
class LayerTail {
 public:
  /// `seamNeighbour`: "layer" or "bead", what the previous seams belong to (warnings).
  LayerTail(const PathStages& stages, PlanStats& stats, StageTimer& timer,
            const char* seamNeighbour)
      : stages_(stages), stats_(stats), timer_(timer), seamNeighbour_(seamNeighbour) {}

  // ---- fit ----
  /// Fits `lines` and projects them onto `projectOnto` as beads (appended to `beads`); pieces too
  /// short or too few points to deposit are counted in `dropped`.
  template <typename NormalFn>
  void fit(const std::vector<Polyline>& lines, const TriangleBvh& projectOnto, NormalFn&& normalOf,
           std::vector<RawBead>& beads, std::size_t& dropped) {
    timer_.run(kFit, [&] {
      fitBeads(lines, stages_.minLength, stages_.fit, projectOnto, normalOf, beads, stats_,
               dropped);
      return 0;
    });
  }
  /// Adds a layer's dropped pieces to the statistics.
  void countDropped(std::size_t dropped) { stats_.droppedFragments += dropped; }
  double minLength() const { return stages_.minLength; }
  /// The note for `dropped` (> 0) pieces shorter than the shortest deposited one.
  std::string droppedNote(std::size_t dropped) const {
    return std::to_string(dropped) + " path piece(s) shorter than " +
           formatNumber(stages_.minLength) + " mm not deposited";
  }

  // ---- order ----
  void order(const std::vector<RawBead>& beads, PlanLayer& layer) {
    torchBefore_ = torch_;
    lastOrder_ = timer_.run(kOrder, [&] {
      return orderBeads(beads, layer.index, torch_, previousSeams_, stages_.ordering, layer);
    });
    const LayerOrder& ordered = lastOrder_;
    if (layer.paths.empty()) return;
    torch_ = ordered.end;
    previousSeams_ = ordered.seams;
    stats_.travel += ordered.travel;
    stats_.seamsTooClose += ordered.seamsTooClose;
    if (ordered.seamsTooClose > 0) {
      layer.warnings.push_back(std::to_string(ordered.seamsTooClose) +
                               " ring(s) too short to keep the seam " +
                               formatNumber(stages_.ordering.seamSeparation) +
                               " mm from the previous " + seamNeighbour_ + "'s seams");
    }
  }

  // ---- connected insets (volume layers) ----
  /// After `order`: joins consecutive rings of the layer into one path each
  /// (paths/connected_insets.hpp) and makes the torch, the seams and the travel follow the
  /// joined paths. `beadLevels`: the level of every bead `order` was given (−1: not a ring).
  void connectInsets(const std::vector<int>& beadLevels, const SurfaceProjection& project,
                     const ConnectedInsetOptions& options, PlanLayer& layer) {
    std::vector<int> levels;
    for (const OrderedPath& o : lastOrder_.paths) levels.push_back(beadLevels[o.source]);
    const ConnectedInsetResult joined = timer_.run(
        kOrder, [&] { return curvedslicer::connectInsets(layer.paths, levels, project, options); });
    if (joined.links == 0) return;
    stats_.insetLinks += joined.links;
    previousSeams_ = joined.seams;
    Vec3 torch = torchBefore_.value_or(layer.paths.front().points.front().position);
    double travel = 0.0;
    for (const PlanPath& p : layer.paths) {
      travel += (p.points.front().position - torch).norm();
      torch = p.closed ? p.points.front().position : p.points.back().position;
    }
    stats_.travel += travel - lastOrder_.travel;
    torch_ = torch;
  }

  // ---- deposition ----
  void deposit(const DepositionSupport& support, const DepositionOptions& options,
               PlanLayer& layer) {
    const DepositionStats ds = timer_.run(
        kDeposition, [&] { return assignDepositionDirections(layer.paths, support, options); });
    stats_.deposition.add(ds);
  }

 private:
  const PathStages& stages_;
  PlanStats& stats_;
  StageTimer& timer_;
  const char* seamNeighbour_;
  std::optional<Vec3> torch_;
  std::vector<Vec3> previousSeams_;
  std::optional<Vec3> torchBefore_;  // the torch before the last `order`
  LayerOrder lastOrder_;             // what the last `order` decided
};

double largestFiniteDistance(const SurfaceGeodesicResult& gdtc) {
  double maxDistance = 0.0;
  for (const double d : gdtc.distance) {
    if (std::isfinite(d)) maxDistance = std::max(maxDistance, d);
  }
  return maxDistance;
}

/// Copies of the closed iso-lines shorter than `minLength`, all levels.
std::vector<Polyline> copyShortRings(const std::vector<std::vector<Polyline>>& levelLines,
                                     double minLength) {
  std::vector<Polyline> rings;
  for (const std::vector<Polyline>& lines : levelLines) {
    for (const Polyline& line : lines) {
      if (line.closed && line.length() < minLength) rings.push_back(line);
    }
  }
  return rings;
}

/// Closed iso-lines shorter than `minLength`, taken out of `levelLines` (the others keep their
/// order): the fragment rule drops them unless one is the only cover of its region (thin regions).
std::vector<Polyline> takeShortRings(std::vector<std::vector<Polyline>>& levelLines,
                                     double minLength) {
  std::vector<Polyline> rings;
  for (std::vector<Polyline>& lines : levelLines) {
    std::size_t w = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (lines[i].closed && lines[i].length() < minLength) {
        rings.push_back(std::move(lines[i]));
        continue;
      }
      if (w != i) lines[w] = std::move(lines[i]);
      ++w;
    }
    lines.resize(w);
  }
  return rings;
}

// ---- volume layers ----

/// What the stages of one layer that need nothing from the layer before (surface index, initial
/// curves, surface geodesic, iso-lines, fit, thin regions) leave for the stages that do (order,
/// connected insets, deposition; then coverage), which LayerPlanner runs layer by layer.
struct LayerDraft {
  PlanLayer layer;                    ///< index, height and the notes so far
  std::optional<SurfaceQuery> query;  ///< set unless the layer surface is empty
  bool onField = false;               ///< the GDTC was found: order, insets, deposition follow
  std::vector<RawBead> beads;
  std::vector<int> beadLevels;  ///< per bead its level (connected insets; −1 = none)
  std::string firstReason;      ///< the layer's first "no paths" reason (empty: none)
  double widest = 0.0;          ///< mm, largest finite GDTC of the layer
  PlanStats stats;              ///< its fit deviation and dropped pieces
  /// Its stage seconds; once the draft has left its drafter only StageTimer::add may read it
  /// (its statistics reference is the drafter's).
  std::optional<StageTimer> timer;
};

/// The first stages of one layer (LayerDraft), on any thread: one drafter per layer, reading
/// only the options and the layer surface.
class LayerDrafter {
 public:
  explicit LayerDrafter(const PlannerOptions& options)
      : options_(options),
        s_(options.beadSpacing),
        stages_(options),
        fromBoundary_(options.initialCurve.kind == InitialCurveKind::Boundary) {
    narrowStrips_.margin = 2.0 * options.fitTolerance;
    narrowStrips_.minLength = stages_.minLength;
    draft_.timer.emplace(draft_.stats);
    tail_.emplace(stages_, draft_.stats, *draft_.timer, "layer");
  }
  LayerDrafter(const LayerDrafter&) = delete;
  LayerDrafter& operator=(const LayerDrafter&) = delete;

  /// Drafts layer `li`; `progress` is only called on this thread (pass none on a worker).
  LayerDraft draft(std::size_t li, const LayerSurface& surface, const Progress& progress) &&;

 private:
  void warn(PlanLayer& layer, const std::string& text) {
    layer.warnings.push_back(text);
    if (draft_.firstReason.empty()) {
      draft_.firstReason = "layer " + std::to_string(layer.index) + ": " + text;
    }
  }
  StageTimer& timer() { return *draft_.timer; }
  std::vector<Polyline> findInitialCurves(const TriMesh& mesh,
                                          std::vector<std::int32_t>& boundaryVertices);
  std::optional<SurfaceGeodesicResult> computeLayerGeodesic(
      const TriMesh& mesh, const std::vector<Polyline>& curves,
      const std::vector<std::int32_t>& boundaryVertices, const Progress& progress,
      PlanLayer& layer);
  void fitOnField(const SurfaceGeodesicResult& gdtc, const std::vector<Polyline>& curves,
                  const SurfaceQuery& query, const Progress& progress, PlanLayer& layer);
  std::vector<std::vector<Polyline>> extractLevelLines(const SurfaceGeodesicResult& gdtc,
                                                       const std::vector<Polyline>& curves,
                                                       const std::vector<double>& values);
  void resolveNarrowStripsOf(const SurfaceGeodesicResult& gdtc, const std::vector<double>& values,
                             std::vector<std::vector<Polyline>>& levelLines, PlanLayer& layer);
  void noteMissingBeads(const std::vector<double>& values, double maxDistance,
                        const std::vector<RawBead>& beads, std::size_t dropped, PlanLayer& layer);
  // thin regions
  void addThinRegionBeads(const SurfaceGeodesicResult& gdtc,
                          const std::vector<Polyline>& shortRings,
                          const std::vector<Polyline>& fitWouldDrop, const SurfaceQuery& query,
                          std::vector<RawBead>& beads, std::size_t& dropped, PlanLayer& layer);
  void addThinBead(const ThinBead& thin,
                   const std::function<std::vector<double>(const std::vector<Vec3>&)>& widthsAt,
                   const SurfaceQuery& query, std::vector<RawBead>& beads, std::size_t& lost);
  void addGapFillBeads(const SurfaceGeodesicResult& gdtc, const SurfaceQuery& query,
                       std::vector<RawBead>& beads, std::size_t& dropped, PlanLayer& layer);
  void fillOuterRingCorners(const SurfaceGeodesicResult& gdtc, const SurfaceQuery& query,
                            std::vector<RawBead>& beads, const std::vector<int>& beadLevels);
  void widenBeadsIntoStrips(const SurfaceGeodesicResult& gdtc, const SurfaceQuery& query,
                            std::vector<RawBead>& beads, PlanLayer& layer);
  std::vector<double> fitFixedWidthLevels(const SurfaceGeodesicResult& gdtc,
                                          const std::vector<Polyline>& curves,
                                          const SurfaceQuery& query, double maxDistance,
                                          const Progress& progress, PlanLayer& layer,
                                          std::vector<RawBead>& beads, std::size_t& dropped,
                                          LevelFit& fit);
  // adaptive bead width (paths/adaptive_width.hpp)
  bool adaptiveWidth() const { return options_.widthMin < 1.0 || options_.widthMax > 1.0; }
  std::vector<double> fitAdaptiveRegions(const SurfaceGeodesicResult& gdtc,
                                         const std::vector<Polyline>& curves,
                                         const SurfaceQuery& query, const Progress& progress,
                                         PlanLayer& layer, std::vector<RawBead>& beads,
                                         std::size_t& dropped, LevelFit& fit);
  std::vector<std::vector<Polyline>> extractRegionLevelLines(const TriMesh& mesh,
                                                             const std::vector<double>& field,
                                                             const std::vector<Polyline>& curves,
                                                             const std::vector<double>& values);
  void noteClampedWidth(const RegionRings& rings, double halfWidth, PlanLayer& layer);
  void resolveRegionNarrowStrips(const TriMesh& mesh, const std::vector<double>& field,
                                 const std::vector<double>& values, double width,
                                 std::vector<std::vector<Polyline>>& levelLines, PlanLayer& layer);

  const PlannerOptions& options_;
  const double s_;
  const PathStages stages_;
  const bool fromBoundary_;
  NarrowStripOptions narrowStrips_;
  LayerDraft draft_;               // what draft() hands on
  std::optional<LayerTail> tail_;  // its fit only (into draft_.stats, timed by draft_.timer)
};

LayerDraft LayerDrafter::draft(std::size_t li, const LayerSurface& surface,
                               const Progress& progress) && {
  PlanLayer& layer = draft_.layer;
  layer.index = static_cast<int>(li);
  layer.height = surface.level;
  std::optional<SurfaceQuery>& query = draft_.query;
  std::vector<Polyline> curves;
  std::vector<std::int32_t> boundaryVertices;  // Boundary: the GDTC sources
  std::optional<SurfaceGeodesicResult> field;
  if (surface.mesh.empty()) {
    warn(layer, "the layer surface is empty; no paths");
  } else {
    // ---- surface index: closest points and normals on the layer (fit projection, deposition)
    progress.report(0.0, kStages[kIndex]);
    timer().run(kIndex, [&] {
      query.emplace(surface.mesh);
      return 0;
    });
    progress.report(0.0, kStages[kCurves]);
    curves = findInitialCurves(surface.mesh, boundaryVertices);
    if (curves.empty()) {
      warn(layer, fromBoundary_
                      ? "the layer is a closed surface without a boundary; no paths (choose an "
                        "initial plane or surface that crosses it)"
                      : "the initial " + describeKind(options_.initialCurve.kind) +
                            " misses this layer; no paths (choose one that crosses every layer)");
    }
  }
  if (!curves.empty()) {
    field = computeLayerGeodesic(surface.mesh, curves, boundaryVertices, progress, layer);
  }
  if (field) fitOnField(*field, curves, *query, progress, layer);
  return std::move(draft_);
}

/// planLayers in layer order: what one layer passes to the next (the support under it, the
/// torch, the seams) and the plan-wide statistics and notes, from the layers' drafts.
class LayerPlanner {
 public:
  LayerPlanner(const TriMesh& startSurface, const PlannerOptions& options, PlanResult& result)
      : options_(options),
        s_(options.beadSpacing),
        stages_(options),
        fromBoundary_(options.initialCurve.kind == InitialCurveKind::Boundary),
        result_(result),
        timer_(result.stats),
        tail_(stages_, result.stats, timer_, "layer") {
    stages_.record(options, result.plan.parameters);
    result.plan.parameters.initialCurve = options.initialCurve.describe();
    result.plan.parameters.narrowStrips = narrowStripModeName(options.narrowStrips);
    result.plan.parameters.minFeatureWidth =
        options.minFeatureWidth < 0.0 ? 0.5 * s_ : options.minFeatureWidth;
    result.plan.parameters.beadWidthRange =
        std::array<double, 2>{options.widthMin, options.widthMax};
    result.plan.parameters.connectInsets = options.connectInsets;
    result.plan.parameters.fillGaps = options.fillGaps;
    result.plan.parameters.minGapArea = options.minGapArea < 0.0 ? s_ * s_ : options.minGapArea;
    result.plan.parameters.cornerOverdeposit =
        options.cornerFill
            ? (options.cornerOverdeposit < 0.0 ? 0.25 * s_ : options.cornerOverdeposit)
            : -1.0;
    if (options.cornerFill) result.plan.parameters.cornerFillAngle = options.cornerFillAngle;
    if (!startSurface.empty()) support_.emplace(startSurface);
  }

  /// The next layer from its draft: order, connected insets, deposition, coverage.
  PlanLayer completeLayer(LayerDraft draft, const Progress& progress);
  /// Threads of the coverage measurement (0: OpenMP's default); 1 while other threads draft.
  void setCoverageThreads(int threads) { coverage_.threads = threads; }
  void finish();

 private:
  void connectInsetsOf(const SurfaceQuery& query, const std::vector<int>& beadLevels,
                       PlanLayer& layer);

  const PlannerOptions& options_;
  const double s_;
  const PathStages stages_;
  const bool fromBoundary_;
  PlanResult& result_;
  StageTimer timer_;
  LayerTail tail_;
  CoverageOptions coverage_;
  std::optional<TriangleBvh> support_;  // material under the current layer
  double widest_ = 0.0;  // largest GDTC over all layers (for the "spacing too wide" message)
  std::string firstReason_;
};

PlanLayer LayerPlanner::completeLayer(LayerDraft draft, const Progress& progress) {
  PlanLayer& layer = draft.layer;
  timer_.add(*draft.timer);
  result_.stats.maxFitDeviation =
      std::max(result_.stats.maxFitDeviation, draft.stats.maxFitDeviation);
  result_.stats.droppedFragments += draft.stats.droppedFragments;
  widest_ = std::max(widest_, draft.widest);
  if (firstReason_.empty()) firstReason_ = draft.firstReason;
  if (draft.onField) {
    progress.report(0.9, kStages[kOrder]);
    tail_.order(draft.beads, layer);
    if (options_.connectInsets) connectInsetsOf(*draft.query, draft.beadLevels, layer);
    progress.report(0.95, kStages[kDeposition]);
    DepositionSupport dep;
    dep.surface = support_ ? &*support_ : nullptr;
    dep.earlierBeads = layer.index == 0;
    // Growth: the layer below's V within two bead spacings (its beads reach s/2 to each side).
    if (!result_.plan.layers.empty()) dep.below = &result_.plan.layers.back().paths;
    dep.belowRadius = 2.0 * s_;
    tail_.deposit(dep, options_.deposition, layer);
  }
  if (options_.measureCoverage && draft.query) {
    progress.report(0.98, kStages[kCoverage]);
    layer.coverage = timer_.run(kCoverage, [&] {
      return computeLayerCoverage(*draft.query->mesh, layer.paths, s_, coverage_);
    });
  }
  // The material under the next layer is this layer's surface (if it has one).
  if (draft.query) support_.emplace(std::move(draft.query->bvh));
  return std::move(layer);
}

// ---- initial curves ----

std::vector<Polyline> LayerDrafter::findInitialCurves(const TriMesh& mesh,
                                                      std::vector<std::int32_t>& boundaryVertices) {
  return timer().run(kCurves, [&] {
    switch (options_.initialCurve.kind) {
      case InitialCurveKind::Plane:
        return computePlaneSection(mesh, options_.initialCurve.planePoint,
                                   options_.initialCurve.planeNormal);
      case InitialCurveKind::Surface:
        return computeSurfaceSection(mesh, options_.initialCurve.surface);
      case InitialCurveKind::Boundary:
        break;
    }
    SurfaceBoundary boundary = findBoundary(mesh);
    boundaryVertices = std::move(boundary.vertices);
    return std::move(boundary.loops);
  });
}

// ---- surface geodesic ----

/// Boundary loops consist of mesh vertices and edges: those vertices are the sources as they are
/// (nothing to insert). Sections are inserted into the mesh. A failure is the layer's warning.
std::optional<SurfaceGeodesicResult> LayerDrafter::computeLayerGeodesic(
    const TriMesh& mesh, const std::vector<Polyline>& curves,
    const std::vector<std::int32_t>& boundaryVertices, const Progress& progress, PlanLayer& layer) {
  try {
    return timer().run(kGeodesic, [&] {
      return fromBoundary_
                 ? computeSurfaceGeodesicFromVertices(mesh, boundaryVertices, {}, options_.geodesic,
                                                      progress.sub(0.0, 0.7))
                 : computeSurfaceGeodesic(mesh, curves, options_.geodesic, progress.sub(0.0, 0.7));
    });
  } catch (const NumericalFailure& e) {
    warn(layer, std::string("the surface distance from the initial curve failed (") + e.what() +
                    "); no paths");
  }
  return std::nullopt;
}

/// Iso-lines, fit and thin regions on a layer whose GDTC is known: the draft's beads.
void LayerDrafter::fitOnField(const SurfaceGeodesicResult& gdtc,
                              const std::vector<Polyline>& curves, const SurfaceQuery& query,
                              const Progress& progress, PlanLayer& layer) {
  const double maxDistance = largestFiniteDistance(gdtc);
  draft_.widest = maxDistance;
  draft_.onField = true;
  if (gdtc.unreachedVertices > 0) {
    layer.warnings.push_back(std::to_string(gdtc.unreachedVertices) +
                             " vertices of the layer are not reached from the initial curve "
                             "(a separate piece of the layer); they get no paths");
  }
  progress.report(0.7, kStages[kIso]);
  std::vector<RawBead>& beads = draft_.beads;
  std::size_t dropped = 0;
  LevelFit fit;  // per bead its level (connected insets); the short rings (thin regions)
  const std::vector<double> values =
      adaptiveWidth()
          ? fitAdaptiveRegions(gdtc, curves, query, progress, layer, beads, dropped, fit)
          : fitFixedWidthLevels(gdtc, curves, query, maxDistance, progress, layer, beads, dropped,
                                fit);
  std::vector<int>& beadLevels = fit.beadLevels;
  beadLevels.resize(beads.size(), -1);
  if (fromBoundary_ && options_.cornerFill) fillOuterRingCorners(gdtc, query, beads, beadLevels);
  if (fromBoundary_) {
    addThinRegionBeads(gdtc, fit.shortRings, fit.fitWouldDrop, query, beads, dropped, layer);
    if (options_.fillGaps) {
      addGapFillBeads(gdtc, query, beads, dropped, layer);
      widenBeadsIntoStrips(gdtc, query, beads, layer);
    }
  }
  beadLevels.resize(beads.size(), -1);  // thin-region beads belong to no level: never joined
  draft_.beadLevels = std::move(beadLevels);
  tail_->countDropped(dropped);
  noteMissingBeads(values, maxDistance, beads, dropped, layer);
}

/// The iso-lines at (k + ½)·s (or k·s) over the whole layer, narrow strips resolved, fitted into
/// `beads`; returns the iso-values.
std::vector<double> LayerDrafter::fitFixedWidthLevels(const SurfaceGeodesicResult& gdtc,
                                                      const std::vector<Polyline>& curves,
                                                      const SurfaceQuery& query, double maxDistance,
                                                      const Progress& progress, PlanLayer& layer,
                                                      std::vector<RawBead>& beads,
                                                      std::size_t& dropped, LevelFit& fit) {
  const std::vector<double> values = computeIsoValues(
      s_, maxDistance, fromBoundary_ ? IsoValueStart::Boundary : IsoValueStart::InteriorCurve);
  std::vector<std::vector<Polyline>> levelLines = extractLevelLines(gdtc, curves, values);
  progress.check();
  // Short rings as the iso-lines give them: the narrow-strip rule drops them too.
  if (fromBoundary_) fit.shortRings = copyShortRings(levelLines, stages_.minLength);
  if (options_.narrowStrips == NarrowStripMode::CentreBead && !values.empty()) {
    resolveNarrowStripsOf(gdtc, values, levelLines, layer);
  }
  if (fromBoundary_) fit.fitWouldDrop = takeShortRings(levelLines, stages_.minLength);
  const auto normalOf = [&](const ClosestPoint& c) { return query.normalAt(c); };
  for (std::size_t k = 0; k < levelLines.size(); ++k) {
    tail_->fit(levelLines[k], query.bvh, normalOf, beads, dropped);
    fit.beadLevels.resize(beads.size(), static_cast<int>(k));
    progress.check();
  }
  return values;
}

// ---- iso-lines ----

/// All levels in one pass over the layer; k = 0 (value 0) is the initial curve itself, the first
/// bead.
std::vector<std::vector<Polyline>> LayerDrafter::extractLevelLines(
    const SurfaceGeodesicResult& gdtc, const std::vector<Polyline>& curves,
    const std::vector<double>& values) {
  return timer().run(kIso, [&] {
    std::vector<double> positive;
    for (const double value : values) {
      if (value > 0.0) positive.push_back(value);
    }
    std::vector<std::vector<Polyline>> lines = extractIsoLines(gdtc.mesh, gdtc.distance, positive);
    if (positive.size() < values.size()) lines.insert(lines.begin(), curves);
    return lines;
  });
}

/// Where the fronts meet (paths/narrow_strips.hpp): paths of one level closer than 0.95·s
/// become one centre bead; the margin keeps the fitted paths at 0.95·s. The inner edges
/// outline the strips beyond the beads where the next level has no ring.
void LayerDrafter::resolveNarrowStripsOf(const SurfaceGeodesicResult& gdtc,
                                         const std::vector<double>& values,
                                         std::vector<std::vector<Polyline>>& levelLines,
                                         PlanLayer& layer) {
  std::vector<double> edgeValues;
  for (const double value : values) {
    edgeValues.push_back(value + 0.5 * s_ + narrowStrips_.innerEdgeOffset);
  }
  const std::vector<std::vector<Polyline>> innerEdges =
      timer().run(kIso, [&] { return extractIsoLines(gdtc.mesh, gdtc.distance, edgeValues); });
  NarrowStripResult strips = timer().run(
      kIso, [&] { return resolveNarrowStrips(levelLines, values, s_, narrowStrips_, innerEdges); });
  reportNarrowStrips(strips, layer.warnings);
  levelLines = std::move(strips.levels);
}

/// Connected insets (paths/connected_insets.hpp): link points projected onto the layer like the
/// fit's points, with the layer's normal.
void LayerPlanner::connectInsetsOf(const SurfaceQuery& query, const std::vector<int>& beadLevels,
                                   PlanLayer& layer) {
  ConnectedInsetOptions insets;
  insets.beadSpacing = s_;
  insets.pointSpacing = options_.pointSpacing;
  const SurfaceProjection project = [&query](const Vec3& p) {
    const ClosestPoint c = query.bvh.closestPoint(p);
    return SurfacePoint{c.point, query.normalAt(c)};
  };
  tail_.connectInsets(beadLevels, project, insets, layer);
}

void LayerDrafter::noteMissingBeads(const std::vector<double>& values, double maxDistance,
                                    const std::vector<RawBead>& beads, std::size_t dropped,
                                    PlanLayer& layer) {
  if (values.empty() && beads.empty()) {
    warn(layer,
         "no room for a bead: the layer reaches at most " + formatNumber(maxDistance) +
             " mm from its initial curve, less than " +
             (fromBoundary_ ? "s/2 = " + formatNumber(0.5 * s_) : "s = " + formatNumber(s_)) +
             " mm; no paths");
  } else if (beads.empty()) {
    warn(layer, "no room for a bead: every iso-line is shorter than " +
                    formatNumber(stages_.minLength) + " mm; no paths");
  } else if (dropped > 0) {
    layer.warnings.push_back(tail_->droppedNote(dropped));
  }
}

// ---- thin regions ----

/// "at x,y,z mm, W mm wide, E mm long, A mm²" for a region's note.
std::string describeRegion(const ThinRegion& r) {
  return "at " + formatVec(r.centroid) + " mm, " + formatNumber(r.width) + " mm wide, " +
         formatNumber(r.extent) + " mm long, " + formatNumber(r.area) + " mm²";
}

/// The thin-region notes of one layer: per outcome a summary with the shortfall and the longest
/// spot dwell (s); every region left out in full (the first ten, then their count and area).
void reportThinRegions(const ThinRegionResult& thin, double s, double minWidth, double dwell,
                       std::vector<std::string>& warnings) {
  std::size_t narrow = 0, spots = 0, lines = 0, rings = 0, leftOut = 0;
  double shortfall = 0.0, leftOutArea = 0.0;
  for (const ThinRegion& r : thin.regions) {
    if (r.leftOut) {
      ++leftOut;
      leftOutArea += r.area;
      continue;
    }
    spots += r.kind == ThinBeadKind::Spot;
    lines += r.kind == ThinBeadKind::CentreLine;
    rings += r.kind == ThinBeadKind::KeptRing;
    if (r.width < s) {
      ++narrow;
      shortfall = std::max(shortfall, s - r.width);
    }
  }
  if (lines + spots + rings > 0) {
    std::string note = "parts of the layer no ring reaches: " + std::to_string(lines) +
                       " bead(s) on their centre line, " + std::to_string(spots) +
                       " spot(s) on tiny islands (dwell up to " + formatNumber(dwell) + " s), " +
                       std::to_string(rings) + " short ring(s) kept as their only cover";
    if (narrow > 0) {
      note += "; " + std::to_string(narrow) +
              " of them narrower than one bead (s = " + formatNumber(s) +
              " mm), width shortfall up to " + formatNumber(shortfall) + " mm";
    }
    warnings.push_back(note);
  }
  constexpr std::size_t kDetails = 10;
  std::size_t listed = 0;
  for (const ThinRegion& r : thin.regions) {
    if (!r.leftOut || listed++ >= kDetails) continue;
    warnings.push_back("region " + describeRegion(r) + " left out: narrower than the minimum " +
                       "feature width " + formatNumber(minWidth) + " mm");
  }
  if (leftOut > kDetails) {
    warnings.push_back("… and " + std::to_string(leftOut - kDetails) +
                       " more region(s) left out, " + formatNumber(leftOutArea) +
                       " mm² in all on this layer");
  }
}

/// Beads for the parts of the layer no ring reaches (paths/thin_regions.hpp). `shortRings`: the
/// short closed iso-lines before the narrow-strip rule; `fitWouldDrop`: those left after it,
/// which the fit would drop — counted in `dropped` unless kept.
void LayerDrafter::addThinRegionBeads(const SurfaceGeodesicResult& gdtc,
                                      const std::vector<Polyline>& shortRings,
                                      const std::vector<Polyline>& fitWouldDrop,
                                      const SurfaceQuery& query, std::vector<RawBead>& beads,
                                      std::size_t& dropped, PlanLayer& layer) {
  ThinRegionOptions o;
  o.beadSpacing = s_;
  o.minFeatureWidth = options_.minFeatureWidth;
  o.widthMin = options_.widthMin;
  o.widthMax = options_.widthMax;
  const ThinRegionPlanner planner(gdtc.mesh, gdtc.distance, o);
  std::vector<Polyline> ringBeads;
  for (const RawBead& b : beads) ringBeads.push_back(b.line);
  const ThinRegionResult thin =
      timer().run(kIso, [&] { return planner.plan(ringBeads, shortRings); });
  std::size_t keptFitDrops = 0, lost = 0;
  for (const ThinBead& t : thin.beads) {
    if (t.kind == ThinBeadKind::KeptRing) {
      keptFitDrops += std::any_of(fitWouldDrop.begin(), fitWouldDrop.end(),
                                  [&](const Polyline& r) { return r.points == t.line.points; });
    }
    addThinBead(
        t, [&](const std::vector<Vec3>& points) { return planner.widthsAt(points); }, query, beads,
        lost);
  }
  dropped += fitWouldDrop.size() - keptFitDrops + lost;
  const double minWidth = options_.minFeatureWidth < 0.0 ? 0.5 * s_ : options_.minFeatureWidth;
  double longestDwell = 0.0;
  for (const RawBead& b : beads) longestDwell = std::max(longestDwell, b.dwell);
  reportThinRegions(thin, s_, minWidth, longestDwell, layer.warnings);
}

/// One thin-region bead: a spot is projected as it is (widths w, dwell w / spotWeldSpeed); a
/// centre line or kept ring is fitted like the rings, whatever its length. `lost`: fits that
/// left too few points.
void LayerDrafter::addThinBead(
    const ThinBead& thin,
    const std::function<std::vector<double>(const std::vector<Vec3>&)>& widthsAt,
    const SurfaceQuery& query, std::vector<RawBead>& beads, std::size_t& lost) {
  if (thin.kind == ThinBeadKind::Spot) {
    RawBead bead;
    ClosestPoint hint;
    for (const Vec3& p : thin.line.points) {
      hint = query.bvh.closestPoint(p, hint);
      bead.line.points.push_back(hint.point);
      bead.normals.push_back(query.normalAt(hint));
    }
    bead.widths.assign(bead.line.points.size(), thin.width);
    bead.dwell = thin.width / options_.spotWeldSpeed;
    beads.push_back(std::move(bead));
    return;
  }
  const std::size_t before = beads.size();
  const auto normalOf = [&](const ClosestPoint& c) { return query.normalAt(c); };
  timer().run(kFit, [&] {
    fitBeads({thin.line}, 0.0, stages_.fit, query.bvh, normalOf, beads, draft_.stats, lost);
    return 0;
  });
  if (beads.size() == before) return;
  RawBead& bead = beads.back();
  bead.widths = thin.kind == ThinBeadKind::KeptRing
                    ? std::vector<double>(bead.line.points.size(), s_)
                    : widthsAt(bead.line.points);
}

/// Beads for the uncovered strips the beads so far leave (paths/gap_fill.hpp), with a note of
/// what was filled and what stays.
void LayerDrafter::addGapFillBeads(const SurfaceGeodesicResult& gdtc, const SurfaceQuery& query,
                                   std::vector<RawBead>& beads, std::size_t& dropped,
                                   PlanLayer& layer) {
  std::vector<LayerBead> layerBeads;
  for (const RawBead& b : beads) layerBeads.push_back({&b.line, b.widths});
  GapFillOptions o;
  o.beadSpacing = s_;
  o.minGapWidth = options_.minFeatureWidth;
  o.minGapArea = options_.minGapArea;
  o.widthMin = options_.widthMin;
  o.widthMax = options_.widthMax;
  const std::unique_ptr<GapFillPlanner> gaps = timer().run(kIso, [&] {
    return std::make_unique<GapFillPlanner>(gdtc.mesh, gdtc.distance, layerBeads, o);
  });
  const GapFillResult& fill = gaps->result();
  std::size_t lost = 0;
  for (const ThinBead& t : fill.beads) {
    addThinBead(
        t, [&](const std::vector<Vec3>& points) { return gaps->widthsAt(points); }, query, beads,
        lost);
  }
  dropped += lost;
  if (fill.filled > 0) {
    layer.warnings.push_back("gap fill: " + std::to_string(fill.filled) +
                             " bead(s) in uncovered strips between beads (" +
                             formatNumber(fill.filledArea) + " mm²); " +
                             std::to_string(fill.gaps.size() - fill.filled) +
                             " patch(es) too narrow or too small stay uncovered (" +
                             formatNumber(fill.uncoveredArea - fill.filledArea) + " mm²)");
  }
}

/// Corner fill (paths/corner_fill.hpp) of the outer rings (level 0); the edge distance of a
/// point is the GDTC from the boundary interpolated on its closest triangle.
void LayerDrafter::fillOuterRingCorners(const SurfaceGeodesicResult& gdtc,
                                        const SurfaceQuery& query, std::vector<RawBead>& beads,
                                        const std::vector<int>& beadLevels) {
  std::vector<CornerFillBead> rings;
  for (std::size_t k = 0; k < beads.size() && k < beadLevels.size(); ++k) {
    if (beadLevels[k] == 0) rings.push_back({&beads[k].line, &beads[k].normals, &beads[k].widths});
  }
  if (rings.empty()) return;
  const EdgeSampler sample = [&](const Vec3& p) {
    const ClosestPoint c = query.bvh.closestPoint(p);
    const Vec3i& tri = gdtc.mesh.triangles[c.triangle];
    const Vec3 w = barycentric(c.point, gdtc.mesh.vertices[tri[0]], gdtc.mesh.vertices[tri[1]],
                               gdtc.mesh.vertices[tri[2]]);
    const double d =
        w[0] * gdtc.distance[tri[0]] + w[1] * gdtc.distance[tri[1]] + w[2] * gdtc.distance[tri[2]];
    return EdgeSample{c.point, query.normalAt(c), d};
  };
  CornerFillOptions o;
  o.beadSpacing = s_;
  o.maxOverdeposit = options_.cornerOverdeposit;
  o.maxCornerAngle = options_.cornerFillAngle;
  timer().run(kIso, [&] { return fillRingCorners(rings, sample, o); });
}

/// Splits the segments of `bead` longer than `longest` (mm) that end at a point with an
/// extension (`left`/`right` per point) into equal pieces; points, normals and widths are
/// interpolated, so the bead's centre line and widths stay as they were.
void densifyWidenedBead(RawBead& bead, const std::vector<double>& left,
                        const std::vector<double>& right, double longest) {
  const std::size_t n = bead.line.points.size();
  const std::size_t count = bead.line.closed && n >= 3 ? n : (n >= 2 ? n - 1 : 0);
  RawBead out;
  out.line.closed = bead.line.closed;
  out.dwell = bead.dwell;
  const bool hasWidths = !bead.widths.empty();
  const auto push = [&](std::size_t i, std::size_t j, double t) {
    out.line.points.push_back(bead.line.points[i] +
                              t * (bead.line.points[j] - bead.line.points[i]));
    const Vec3 normal = bead.normals[i] + t * (bead.normals[j] - bead.normals[i]);
    out.normals.push_back(normal.norm() > 0.0 ? Vec3(normal.normalized()) : bead.normals[i]);
    if (hasWidths) out.widths.push_back(bead.widths[i] + t * (bead.widths[j] - bead.widths[i]));
  };
  for (std::size_t i = 0; i < n; ++i) {
    push(i, i, 0.0);
    if (i >= count) continue;
    const std::size_t j = (i + 1) % n;
    const bool widened = left[i] + right[i] > 0.0 || left[j] + right[j] > 0.0;
    const double length = (bead.line.points[j] - bead.line.points[i]).norm();
    const int pieces = widened ? static_cast<int>(std::ceil(length / longest)) : 1;
    for (int p = 1; p < pieces; ++p) push(i, j, static_cast<double>(p) / pieces);
  }
  bead = std::move(out);
}

/// Widens `bead` by `left`/`right` (mm per point, paths/bead_widening.hpp): each point moves by
/// half the difference towards the wider side and goes back onto the layer surface; its width
/// grows by both (from s where the bead carried none).
void applyBeadWidening(RawBead& bead, const std::vector<double>& left,
                       const std::vector<double>& right, double s, const SurfaceQuery& query) {
  const std::vector<Vec3> before = bead.line.points;
  const std::size_t n = before.size();
  const bool closed = bead.line.closed && n >= 3;
  if (bead.widths.empty()) bead.widths.assign(n, s);
  ClosestPoint hint;
  for (std::size_t i = 0; i < n; ++i) {
    if (left[i] + right[i] <= 0.0) continue;
    const Vec3& prev = i > 0 ? before[i - 1] : (closed ? before[n - 1] : before[i]);
    const Vec3& next = i + 1 < n ? before[i + 1] : (closed ? before[0] : before[i]);
    const Vec3 side = (next - prev).cross(bead.normals[i]);
    const Vec3 shift = side.norm() > 0.0 ? Vec3(0.5 * (right[i] - left[i]) * side.normalized())
                                         : Vec3(Vec3::Zero());
    hint = query.bvh.closestPoint(before[i] + shift, hint);
    bead.line.points[i] = hint.point;
    bead.normals[i] = query.normalAt(hint);
    bead.widths[i] += left[i] + right[i];
  }
}

/// The beads beside uncovered strips between beads widened into them (paths/bead_widening.hpp):
/// each side by at most half the minimum fill width, to at most the widest allowed bead
/// (widthMax·s, or 1.25·s at fixed width); moved points are put back on the layer surface.
void LayerDrafter::widenBeadsIntoStrips(const SurfaceGeodesicResult& gdtc,
                                        const SurfaceQuery& query, std::vector<RawBead>& beads,
                                        PlanLayer& layer) {
  std::vector<WidenableBead> widenable;
  for (const RawBead& b : beads) widenable.push_back({&b.line, &b.normals, b.widths});
  BeadWideningOptions o;
  o.beadSpacing = s_;
  const double minWidth = options_.minFeatureWidth < 0.0 ? 0.5 * s_ : options_.minFeatureWidth;
  o.maxExtension = 0.5 * minWidth;
  o.maxWidth = std::max(options_.widthMax, 1.25) * s_;
  BeadWidening widening = timer().run(
      kIso, [&] { return computeBeadWidening(gdtc.mesh, widenable, gdtc.distance, o); });
  if (widening.widenedPoints == 0) return;
  // Widths vary linearly along a segment: split the long ones next to widened points so that
  // the growth stays where the strip is, then ask again on the finer beads.
  std::vector<std::pair<std::size_t, RawBead>> coarse;  // beads as they were before the split
  for (std::size_t k = 0; k < beads.size(); ++k) {
    if (!widening.left[k].empty()) {
      coarse.emplace_back(k, beads[k]);
      densifyWidenedBead(beads[k], widening.left[k], widening.right[k], 0.25 * s_);
    }
    widenable[k] = {&beads[k].line, &beads[k].normals, beads[k].widths};
  }
  widening = timer().run(
      kIso, [&] { return computeBeadWidening(gdtc.mesh, widenable, gdtc.distance, o); });
  for (auto& [k, bead] : coarse) {  // split for nothing: back as it was
    const std::vector<double>& l = widening.left[k];
    if (std::all_of(l.begin(), l.end(), [](double e) { return e == 0.0; }) &&
        std::all_of(widening.right[k].begin(), widening.right[k].end(),
                    [](double e) { return e == 0.0; })) {
      beads[k] = std::move(bead);
      widening.left[k].clear();
      widening.right[k].clear();
    }
  }
  if (widening.widenedPoints == 0) return;
  for (std::size_t k = 0; k < beads.size(); ++k) {
    if (!widening.left[k].empty()) {
      applyBeadWidening(beads[k], widening.left[k], widening.right[k], s_, query);
    }
  }
  layer.warnings.push_back("bead widening: " + std::to_string(widening.widenedPoints) +
                           " bead point(s) widened into uncovered strips between beads, up "
                           "to " +
                           formatNumber(widening.largestWidth) + " mm wide");
}

// ---- adaptive bead width (paths/adaptive_width.hpp) ----

/// The region of the vertex of `mesh` nearest to `p` (initial curves run through the inserted
/// mesh's vertices, so the nearest one is on the curve).
std::int32_t regionNear(const TriMesh& mesh, const std::vector<std::int32_t>& region,
                        const Vec3& p) {
  std::size_t best = 0;
  double bestDistance = kInf;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const double d = (mesh.vertices[v] - p).squaredNorm();
    if (d < bestDistance) {
      bestDistance = d;
      best = v;
    }
  }
  return region.empty() ? -1 : region[best];
}

void appendAll(std::vector<Polyline>& to, std::vector<Polyline> from) {
  to.insert(to.end(), std::make_move_iterator(from.begin()), std::make_move_iterator(from.end()));
}

/// Per connected region of the layer: a whole number of rings of one width within the allowed
/// range (computeRegionRings), iso-lines of the region alone at its values, its narrow strips at
/// its width, fitted into `beads` with that width. Returns every region's values (ascending).
std::vector<double> LayerDrafter::fitAdaptiveRegions(const SurfaceGeodesicResult& gdtc,
                                                     const std::vector<Polyline>& curves,
                                                     const SurfaceQuery& query,
                                                     const Progress& progress, PlanLayer& layer,
                                                     std::vector<RawBead>& beads,
                                                     std::size_t& dropped, LevelFit& fit) {
  std::int32_t regionCount = 0;
  const std::vector<std::int32_t> region = labelMeshRegions(gdtc.mesh, regionCount);
  std::vector<double> halfWidth(regionCount, 0.0);
  for (std::size_t v = 0; v < gdtc.distance.size(); ++v) {
    if (std::isfinite(gdtc.distance[v])) {
      halfWidth[region[v]] = std::max(halfWidth[region[v]], gdtc.distance[v]);
    }
  }
  const IsoValueStart start =
      fromBoundary_ ? IsoValueStart::Boundary : IsoValueStart::InteriorCurve;
  const auto normalOf = [&](const ClosestPoint& c) { return query.normalAt(c); };
  std::vector<double> allValues;
  std::vector<double> field(gdtc.distance.size());
  for (std::int32_t r = 0; r < regionCount; ++r) {
    const RegionRings rings =
        computeRegionRings(halfWidth[r], s_, options_.widthMin, options_.widthMax, start);
    if (rings.values.empty()) continue;
    noteClampedWidth(rings, halfWidth[r], layer);
    for (std::size_t v = 0; v < field.size(); ++v) {
      field[v] = region[v] == r ? gdtc.distance[v] : kInf;
    }
    std::vector<Polyline> regionCurves;
    for (const Polyline& c : curves) {
      if (!c.points.empty() && regionNear(gdtc.mesh, region, c.points.front()) == r) {
        regionCurves.push_back(c);
      }
    }
    std::vector<std::vector<Polyline>> levelLines =
        extractRegionLevelLines(gdtc.mesh, field, regionCurves, rings.values);
    if (fromBoundary_) appendAll(fit.shortRings, copyShortRings(levelLines, stages_.minLength));
    if (options_.narrowStrips == NarrowStripMode::CentreBead) {
      resolveRegionNarrowStrips(gdtc.mesh, field, rings.values, rings.width, levelLines, layer);
    }
    if (fromBoundary_) appendAll(fit.fitWouldDrop, takeShortRings(levelLines, stages_.minLength));
    const std::size_t first = beads.size();
    for (std::size_t k = 0; k < levelLines.size(); ++k) {
      tail_->fit(levelLines[k], query.bvh, normalOf, beads, dropped);
      fit.beadLevels.resize(beads.size(), static_cast<int>(k));
      progress.check();
    }
    for (std::size_t b = first; b < beads.size(); ++b) {
      beads[b].widths.assign(beads[b].line.points.size(), rings.width);
    }
    allValues.insert(allValues.end(), rings.values.begin(), rings.values.end());
  }
  std::sort(allValues.begin(), allValues.end());
  return allValues;
}

/// A layer note where a region's whole number of beads would need a width outside the range.
void LayerDrafter::noteClampedWidth(const RegionRings& rings, double halfWidth, PlanLayer& layer) {
  if (!rings.widthClamped) return;
  layer.warnings.push_back(
      "adaptive bead width: a region reaching " + formatNumber(halfWidth) +
      " mm from its initial curve needs beads " + formatNumber(rings.wholeWidth) +
      " mm wide for a whole number of rings, outside the range " +
      formatNumber(options_.widthMin * s_) + "–" + formatNumber(options_.widthMax * s_) + " mm; " +
      formatNumber(rings.width) + " mm used");
}

/// extractLevelLines for one region: `field` is the GDTC inside the region, +inf elsewhere;
/// value 0 is the region's initial curves.
std::vector<std::vector<Polyline>> LayerDrafter::extractRegionLevelLines(
    const TriMesh& mesh, const std::vector<double>& field, const std::vector<Polyline>& curves,
    const std::vector<double>& values) {
  return timer().run(kIso, [&] {
    std::vector<double> positive;
    for (const double value : values) {
      if (value > 0.0) positive.push_back(value);
    }
    std::vector<std::vector<Polyline>> lines = extractIsoLines(mesh, field, positive);
    if (positive.size() < values.size()) lines.insert(lines.begin(), curves);
    return lines;
  });
}

/// resolveNarrowStripsOf for one region at its bead width: paths of one level closer than
/// 0.95·w' become one centre bead.
void LayerDrafter::resolveRegionNarrowStrips(const TriMesh& mesh, const std::vector<double>& field,
                                             const std::vector<double>& values, double width,
                                             std::vector<std::vector<Polyline>>& levelLines,
                                             PlanLayer& layer) {
  std::vector<double> edgeValues;
  for (const double value : values) {
    edgeValues.push_back(value + 0.5 * width + narrowStrips_.innerEdgeOffset);
  }
  const std::vector<std::vector<Polyline>> innerEdges =
      timer().run(kIso, [&] { return extractIsoLines(mesh, field, edgeValues); });
  NarrowStripResult strips = timer().run(kIso, [&] {
    return resolveNarrowStrips(levelLines, values, width, narrowStrips_, innerEdges);
  });
  reportNarrowStrips(strips, layer.warnings);
  levelLines = std::move(strips.levels);
}

void LayerPlanner::finish() {
  finishStats(result_, timer_);
  if (result_.plan.pathCount() > 0) return;
  if (widest_ > 0.0 && widest_ < (fromBoundary_ ? 0.5 * s_ : s_)) {
    throw InvalidInput("bead spacing is wider than every layer: " + formatNumber(s_) +
                       " mm, the layers reach at most " + formatNumber(widest_) +
                       " mm from their initial curves; choose a bead spacing below " +
                       formatNumber(fromBoundary_ ? 2.0 * widest_ : widest_) + " mm" +
                       (fromBoundary_ ? " (or a minimum feature width below " +
                                            formatNumber(2.0 * widest_) + " mm for centre beads)"
                                      : std::string()));
  }
  throw InvalidInput("no layer got a path: " + firstReason_ +
                     "; change the initial curve or the bead spacing");
}

/// The progress of layer `li` of `count` within the whole plan.
Progress layerProgressOf(const Progress& progress, std::size_t li, std::size_t count) {
  return progress.sub(static_cast<double>(li) / count, static_cast<double>(li + 1) / count);
}

/// One layer after the other on the calling thread (progress within every stage).
void planLayersInTurn(const std::vector<LayerSurface>& layers, const PlannerOptions& options,
                      LayerPlanner& planner, const Progress& progress, Plan& plan) {
  for (std::size_t li = 0; li < layers.size(); ++li) {
    const Progress layerProgress = layerProgressOf(progress, li, layers.size());
    LayerDraft draft = LayerDrafter(options).draft(li, layers[li], layerProgress);
    plan.layers.push_back(planner.completeLayer(std::move(draft), layerProgress));
    layerProgress.report(1.0, kStages[kDeposition]);
  }
}

/// Layers drafted on `threads` threads (the calling thread and threads − 1 helpers) and
/// completed in order on the calling thread, as a pipeline: a thread takes the next layer to
/// draft while the drafts ahead of the next layer to complete stay within a window of 4 per thread
/// (their surfaces' indices held at once); the calling thread completes the next layer as soon as
/// its draft is there and drafts itself while it waits, so both cores stay busy through the
/// layer-by-layer stages. Progress is reported and a draft's error rethrown on the calling thread
/// where the layer-by-layer run would have done so. The plan is the same as planLayersInTurn's: a
/// draft depends on its layer alone, and completion runs in layer order.
class LayerPipeline {
 public:
  LayerPipeline(const std::vector<LayerSurface>& layers, const PlannerOptions& options, int threads)
      : layers_(layers),
        options_(options),
        window_(4 * static_cast<std::size_t>(threads)),
        drafts_(layers.size()),
        errors_(layers.size()),
        ready_(layers.size(), 0) {
    try {
      for (int t = 1; t < threads; ++t) helpers_.emplace_back([this] { helpDraft(); });
    } catch (...) {
      stopHelpers();
      throw;
    }
  }
  ~LayerPipeline() { stopHelpers(); }
  LayerPipeline(const LayerPipeline&) = delete;
  LayerPipeline& operator=(const LayerPipeline&) = delete;

  /// Layer li's draft (li = 0, 1, … in turn), drafting other layers while it is not ready;
  /// rethrows the error of its draft. Layers before li count as completed.
  LayerDraft take(std::size_t li) {
    std::unique_lock<std::mutex> lock(mutex_);
    completed_ = li;
    changed_.notify_all();  // the window moved on
    while (!ready_[li]) {
      if (canClaim()) {
        const std::size_t k = next_++;
        lock.unlock();
        draftLayer(k);
        lock.lock();
        continue;
      }
      changed_.wait(lock, [&] { return ready_[li] || canClaim(); });
    }
    if (errors_[li]) std::rethrow_exception(errors_[li]);
    LayerDraft draft = std::move(*drafts_[li]);
    drafts_[li].reset();
    return draft;
  }

 private:
  void stopHelpers() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
    for (std::thread& t : helpers_) t.join();
  }
  bool canClaim() const { return next_ < layers_.size() && next_ < completed_ + window_; }

  void helpDraft() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      changed_.wait(lock, [&] { return stop_ || canClaim(); });
      if (stop_) return;
      const std::size_t k = next_++;
      lock.unlock();
      draftLayer(k);
      lock.lock();
    }
  }

  /// Drafts layer k (no progress: a helper must not report) and hands it, or its error, over.
  void draftLayer(std::size_t k) {
    std::optional<LayerDraft> draft;
    std::exception_ptr error;
    try {
      draft.emplace(LayerDrafter(options_).draft(k, layers_[k], Progress()));
    } catch (...) {
      error = std::current_exception();
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (draft) drafts_[k].emplace(std::move(*draft));
      errors_[k] = error;
      ready_[k] = 1;
    }
    changed_.notify_all();
  }

  const std::vector<LayerSurface>& layers_;
  const PlannerOptions& options_;
  const std::size_t window_;
  std::mutex mutex_;  // guards everything below but the helpers
  std::condition_variable changed_;
  std::vector<std::optional<LayerDraft>> drafts_;
  std::vector<std::exception_ptr> errors_;
  std::vector<char> ready_;
  std::size_t next_ = 0;       // the next layer to draft
  std::size_t completed_ = 0;  // layers completed (the window starts there)
  bool stop_ = false;
  std::vector<std::thread> helpers_;  // last: started once the rest is set up
};

void planLayersInParallel(const std::vector<LayerSurface>& layers, const PlannerOptions& options,
                          int threads, LayerPlanner& planner, const Progress& progress,
                          Plan& plan) {
  planner.setCoverageThreads(1);  // the other threads are drafting
  LayerPipeline pipeline(layers, options, threads);
  for (std::size_t li = 0; li < layers.size(); ++li) {
    LayerDraft draft = pipeline.take(li);
    const Progress layerProgress = layerProgressOf(progress, li, layers.size());
    plan.layers.push_back(planner.completeLayer(std::move(draft), layerProgress));
    layerProgress.report(1.0, kStages[kDeposition]);
  }
}

// ---- thin wall ----

/// The boundary loop the wall grows from: the lowest along the axis, or the nearest to the point.
std::size_t chooseWallEdge(const std::vector<Polyline>& loops, const ThinWallOptions& options) {
  std::size_t edge = 0;
  double bestKey = kInf;
  const Vec3 axis = options.axis.normalized();
  for (std::size_t i = 0; i < loops.size(); ++i) {
    double key = kInf;
    if (options.edge == WallEdgeKind::LowestAlongAxis) {
      for (const Vec3& p : loops[i].points) key = std::min(key, p.dot(axis));
    } else {
      key = closestPointOnPolyline(loops[i], options.point).distance;
    }
    if (key < bestKey) {
      bestKey = key;
      edge = i;
    }
  }
  return edge;
}

/// The loop's points are mesh vertices: they are the sources as they are (nothing to insert).
SurfaceGeodesicResult computeWallGeodesic(const TriMesh& surface, const Polyline& edge,
                                          const ThinWallOptions& options, StageTimer& timer,
                                          const Progress& progress) {
  std::map<std::array<double, 3>, std::int32_t> vertexAt;
  for (std::size_t v = 0; v < surface.vertexCount(); ++v) {
    const Vec3& p = surface.vertices[v];
    vertexAt.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, static_cast<std::int32_t>(v));
  }
  std::vector<std::int32_t> sources;
  for (const Vec3& p : edge.points) {
    const auto it = vertexAt.find({p.x(), p.y(), p.z()});
    if (it != vertexAt.end()) sources.push_back(it->second);
  }
  return timer.run(kGeodesic, [&] {
    return sources.size() == edge.points.size()
               ? computeSurfaceGeodesicFromVertices(surface, sources, {}, options.geodesic,
                                                    progress.sub(0.0, 0.5))
               : computeSurfaceGeodesic(surface, {edge}, options.geodesic, progress.sub(0.0, 0.5));
  });
}

/// The wall's bead values (GDTC from the edge), s apart; throws when there is none.
std::vector<double> computeWallIsoValues(const SurfaceGeodesicResult& gdtc, double s) {
  const double maxDistance = largestFiniteDistance(gdtc);
  std::vector<double> values = computeIsoValues(s, maxDistance, IsoValueStart::InteriorCurve);
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return v <= 0.0; }),
               values.end());
  if (values.empty()) {
    throw InvalidInput("thin wall is lower than one bead: it reaches " + formatNumber(maxDistance) +
                       " mm from its edge, the bead spacing is " + formatNumber(s) +
                       " mm; choose a smaller bead spacing");
  }
  return values;
}

/// Growth direction of a wall bead: the GDTC gradient on the triangle under the point.
struct WallGrowth {
  const SurfaceGeodesicResult& gdtc;

  Vec3 operator()(const ClosestPoint& c) const {
    const Vec3i& t = gdtc.mesh.triangles[c.triangle];
    const Vec3 a = gdtc.mesh.vertices[t[0]], b = gdtc.mesh.vertices[t[1]],
               d = gdtc.mesh.vertices[t[2]];
    const double fa = gdtc.distance[t[0]], fb = gdtc.distance[t[1]], fd = gdtc.distance[t[2]];
    const Vec3 n = (b - a).cross(d - a);
    const double area2 = n.squaredNorm();
    if (!(area2 > 0.0) || !std::isfinite(fa + fb + fd)) {
      return n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3(Vec3::UnitZ());
    }
    // Gradient of the linear interpolant: Σ f_i (n × e_i) / |n|², e_i the edge opposite i.
    const Vec3 g = (fa * n.cross(d - b) + fb * n.cross(a - d) + fd * n.cross(b - a)) / area2;
    return g.norm() > 0.0 ? Vec3(g.normalized()) : Vec3(n.normalized());
  }
};

/// The polylines of a layer's paths (the deposited beads the next wall bead rests on).
std::vector<Polyline> pathLines(const PlanLayer& layer) {
  std::vector<Polyline> lines;
  for (const PlanPath& p : layer.paths) {
    Polyline line;
    line.closed = p.closed;
    for (const PathPoint& q : p.points) line.points.push_back(q.position);
    lines.push_back(std::move(line));
  }
  return lines;
}

/// The substrate a wall grown from its lowest edge stands on: the plane through the edge's
/// lowest point normal to the axis, as a square reaching a surface's size beyond it on every
/// side (the wall's beads find their nearest plate point inside it). Empty for an edge chosen
/// by a point, whose substrate is not known.
TriMesh wallSubstrate(const TriMesh& surface, const Polyline& edge,
                      const ThinWallOptions& options) {
  TriMesh plate;
  if (options.edge != WallEdgeKind::LowestAlongAxis) return plate;
  const Vec3 axis = options.axis.normalized();
  double level = kInf;
  for (const Vec3& p : edge.points) level = std::min(level, p.dot(axis));
  const Vec3 e1 = axis.unitOrthogonal();
  const Vec3 e2 = axis.cross(e1);
  double lo1 = kInf, hi1 = -kInf, lo2 = kInf, hi2 = -kInf;
  for (const Vec3& p : surface.vertices) {
    lo1 = std::min(lo1, p.dot(e1)), hi1 = std::max(hi1, p.dot(e1));
    lo2 = std::min(lo2, p.dot(e2)), hi2 = std::max(hi2, p.dot(e2));
  }
  const double margin = std::max({hi1 - lo1, hi2 - lo2, 1.0});
  lo1 -= margin, hi1 += margin, lo2 -= margin, hi2 += margin;
  const auto at = [&](double u, double v) { return Vec3(level * axis + u * e1 + v * e2); };
  plate.vertices = {at(lo1, lo2), at(hi1, lo2), at(hi1, hi2), at(lo1, hi2)};
  plate.triangles = {Vec3i(0, 1, 2), Vec3i(0, 2, 3)};
  return plate;
}

/// One bead of the wall (a plan layer) from its iso-lines: fit, order, deposition on the beads
/// before it.
PlanLayer planWallBead(std::size_t k, double value, const std::vector<Polyline>& lines,
                       const TriangleBvh& bvh, const WallGrowth& growthDirection,
                       const ThinWallOptions& options, const TriangleBvh& substrate,
                       LayerTail& tail, std::vector<Polyline>& previousBeads) {
  PlanLayer layer;
  layer.index = static_cast<int>(k);
  layer.height = value;
  std::vector<RawBead> beads;
  std::size_t dropped = 0;
  tail.fit(lines, bvh, growthDirection, beads, dropped);
  tail.countDropped(dropped);
  if (beads.empty()) {
    layer.warnings.push_back("no room for a bead at " + formatNumber(value) +
                             " mm from the edge: every curve is shorter than " +
                             formatNumber(tail.minLength()) + " mm; no paths");
  } else if (dropped > 0) {
    layer.warnings.push_back(tail.droppedNote(dropped));
  }
  tail.order(beads, layer);
  DepositionSupport dep;
  dep.curves = previousBeads;
  dep.earlierBeads = true;
  dep.surface = &substrate;
  dep.surfaceIsSubstrate = true;
  dep.substrateMargin = 0.5 * options.beadSpacing;
  tail.deposit(dep, options.deposition, layer);
  if (!layer.paths.empty()) previousBeads = pathLines(layer);
  return layer;
}

}  // namespace

PlanResult planLayers(const std::vector<LayerSurface>& layers, const TriMesh& startSurface,
                      const PlannerOptions& options, Progress progress) {
  validatePlannerOptions(options);
  if (layers.empty()) {
    throw InvalidInput("no layer surfaces to plan: 0 layers; run the layer job first");
  }
  PlanResult result;
  LayerPlanner planner(startSurface, options, result);
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  if (threads <= 1 || layers.size() < 2) {
    planLayersInTurn(layers, options, planner, progress, result.plan);
  } else {
    planLayersInParallel(layers, options, threads, planner, progress, result.plan);
  }
  planner.finish();
  return result;
}

PlanResult planThinWall(const TriMesh& surface, const ThinWallOptions& options, Progress progress) {
  validateThinWallOptions(options);
  if (surface.empty()) {
    throw InvalidInput("thin-wall surface has no triangles: 0; pass the wall's surface mesh");
  }
  const PathStages stages(options);
  PlanResult result;
  Plan& plan = result.plan;
  stages.record(options, plan.parameters);
  plan.parameters.layerThickness = options.beadSpacing;
  StageTimer timer(result.stats);
  // ---- initial curves: the edge ----
  progress.report(0.0, kStages[kCurves]);
  const std::vector<Polyline> loops =
      timer.run(kCurves, [&] { return extractBoundaryLoops(surface); });
  if (loops.empty()) {
    throw InvalidInput(
        "thin-wall surface has no boundary edge: 0 loops; pass an open surface "
        "whose edge lies on the substrate");
  }
  const Polyline& edge = loops[chooseWallEdge(loops, options)];
  plan.parameters.initialCurve = options.edge == WallEdgeKind::LowestAlongAxis
                                     ? "thin-wall:lowest:" + formatVec(options.axis)
                                     : "thin-wall:nearest:" + formatVec(options.point);
  const SurfaceGeodesicResult gdtc = computeWallGeodesic(surface, edge, options, timer, progress);
  const std::vector<double> values = computeWallIsoValues(gdtc, options.beadSpacing);
  const TriangleBvh bvh = timer.run(kIndex, [&] { return TriangleBvh(gdtc.mesh); });
  // Every bead's iso-line in one pass over the surface.
  const std::vector<std::vector<Polyline>> levelLines =
      timer.run(kIso, [&] { return extractIsoLines(gdtc.mesh, gdtc.distance, values); });
  const TriangleBvh substrate(wallSubstrate(surface, edge, options));
  LayerTail tail(stages, result.stats, timer, "bead");
  std::vector<Polyline> previousBeads = {edge};
  for (std::size_t k = 0; k < values.size(); ++k) {
    const Progress beadProgress =
        progress.sub(0.5 + 0.5 * k / values.size(), 0.5 + 0.5 * (k + 1) / values.size());
    beadProgress.report(0.0, kStages[kIso]);
    plan.layers.push_back(planWallBead(k, values[k], levelLines[k], bvh, WallGrowth{gdtc}, options,
                                       substrate, tail, previousBeads));
    beadProgress.report(1.0, kStages[kDeposition]);
  }
  finishStats(result, timer);
  if (plan.pathCount() == 0) {
    throw InvalidInput("no bead of the thin wall is long enough: every curve is shorter than " +
                       formatNumber(stages.minLength) +
                       " mm; choose a smaller bead spacing or path length");
  }
  return result;
}

}  // namespace curvedslicer
