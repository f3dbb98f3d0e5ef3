#include "curvedslicer/pipeline/layer_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include <sys/resource.h>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace {

using Clock = std::chrono::steady_clock;

std::string formatNumber(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

void requirePositiveLength(double value, const char* what, const char* example) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw InvalidInput(std::string(what) + " must be a positive number of millimetres: " +
                       formatNumber(value) + "; pass a value such as " + example);
  }
}

/// Times one stage and records it under `name`.
class StageClock {
 public:
  explicit StageClock(std::vector<StageTime>& times) : times_(times) {}
  void start(std::string name) {
    name_ = std::move(name);
    begin_ = Clock::now();
  }
  void stop() {
    times_.push_back({std::move(name_),
                      std::chrono::duration<double>(Clock::now() - begin_).count(),
                      peakResidentMemoryBytes()});
  }

 private:
  std::vector<StageTime>& times_;
  std::string name_;
  Clock::time_point begin_;
};

std::string describeBox(const Aabb& box) {
  const Vec3 s = box.size();
  return formatNumber(s.x()) + " x " + formatNumber(s.y()) + " x " + formatNumber(s.z()) + " mm";
}

/// The model must enclose a volume: |V| tiny against the cube of the box diagonal means a flat
/// or sheet-like mesh.
void validateModel(const MeshReport& report) {
  if (report.triangles == 0) {
    throw InvalidInput(
        "model has no triangles left after cleaning (all were degenerate or duplicates): 0 "
        "triangles; check the file, it must describe a closed solid");
  }
  const double diagonal = report.bounds.diagonal();
  const double tiny = 1e-6 * diagonal * diagonal * diagonal;
  if (!(std::abs(report.volume) > tiny)) {
    throw InvalidInput("model encloses no volume: " + formatNumber(report.volume) +
                       " mm^3 inside a bounding box of " + describeBox(report.bounds) +
                       "; the model must be a closed solid, not a flat or sheet-like surface");
  }
}

/// "x 0..20, y 0..16, z 10..10 mm" (part frame), for saying where something lies.
std::string describeRegion(const Aabb& box) {
  if (box.empty()) return "(nowhere)";
  std::string text;
  const char* const axes[] = {"x ", ", y ", ", z "};
  for (int a = 0; a < 3; ++a) {
    text += axes[a] + formatNumber(box.min[a]) + ".." + formatNumber(box.max[a]);
  }
  return text + " mm";
}

std::string openModelAdvice(bool capHoles) {
  return capHoles ? "repair the mesh into a watertight solid"
                  : "pass --cap-holes (CapHoles) or close the model";
}

/// Warnings for geometry the voxelizer had to interpret (report.json "warnings", stderr): an open
/// model, a surface filled by parity, shells that overlap — each with where it lies.
std::vector<std::string> geometryWarnings(const VoxelizeStats& stats, const MeshReport& report,
                                          bool capHoles) {
  std::vector<std::string> warnings;
  if (!report.closed()) {
    warnings.push_back(
        "the model is open: " + std::to_string(report.openEdges) + " boundary edges and " +
        std::to_string(report.nonManifoldEdges) + " non-manifold edges around " +
        describeRegion(report.defectBounds) + "; inside was decided by crossing parity (" +
        std::to_string(stats.oddColumns) +
        " columns voxel by voxel), so the part may differ from the intended solid there: " +
        openModelAdvice(capHoles));
  } else if (stats.fillRule == FillRule::Parity) {
    warnings.push_back(
        "the model's surface is inconsistently oriented: " +
        std::to_string(report.inconsistentEdges) +
        " edges where neighbouring triangles disagree, around " +
        describeRegion(report.defectBounds) +
        "; inside was decided by crossing parity, so the part may differ from the intended "
        "solid there: orient those triangles consistently (outward normals)");
  }
  if (stats.overlapVoxels > 0) {
    warnings.push_back(std::to_string(stats.overlapVoxels) +
                       " voxels lie inside two or more shells of the model (overlapping or nested "
                       "bodies) around " +
                       describeRegion(stats.overlapBounds) +
                       "; they were filled as the union of the shells: check that the bodies are "
                       "meant to be one part");
  }
  return warnings;
}

/// Inside voxels the field cannot reach from the start surface get no layer. Where the model is
/// several bodies (surface components) and they make up 1 % of the inside voxels or more, that is
/// an error: a body that neither touches the start surface nor joins the rest (a detached body,
/// two bodies meeting at a point) would be left out of the plan. Otherwise a warning says where:
/// on one body they are cut off by the voxel grid (a neck narrower than a voxel).
void checkReached(const UnreachedVoxels& unreached, std::size_t inside, std::size_t bodies,
                  const std::string& start, std::vector<std::string>& warnings) {
  if (unreached.count == 0) return;
  const double share = static_cast<double>(unreached.count) / static_cast<double>(inside);
  const std::string what =
      std::to_string(unreached.count) + " of " + std::to_string(inside) + " inside voxels (" +
      formatNumber(100.0 * share) + " %), in " + std::to_string(unreached.components) +
      " piece(s) around " + describeRegion(unreached.bounds) +
      ", are not connected to the start surface (" + start + ") through the part";
  if (bodies > 1 && share >= 0.01) {
    throw InvalidInput("part not reachable from the start surface: " + what + " (the model is " +
                       std::to_string(bodies) +
                       " separate bodies), so no layer would cover them; give each body a start "
                       "surface of its own (e.g. --start faces:... naming faces on every body), "
                       "plan the bodies as separate Jobs, or join them with material");
  }
  warnings.push_back(what + ": no layer covers them; " +
                     (bodies > 1 ? std::string("the model is ") + std::to_string(bodies) +
                                       " separate bodies: give each a start surface of its own"
                                 : std::string("the voxel grid cuts them off from the rest (a "
                                               "neck narrower than a voxel): use a smaller voxel "
                                               "size")));
}

/// A voxel size giving roughly `cells` inside voxels for a solid of `volume` mm³.
double voxelSizeForCells(double volume, double cells) {
  return std::cbrt(volume / cells);
}

void validateGrid(const VoxelizeResult& vox, const MeshReport& report,
                  const HoleCappingResult& capping, const LayerJobOptions& options) {
  const std::size_t inside = vox.grid.insideCount;
  const std::size_t unresolved = vox.stats.unresolvedVoxels;
  const double L = vox.grid.geometry.voxelSize;
  const bool openBeyondRepair =
      unresolved > 0 &&
      (inside == 0 || static_cast<double>(unresolved) > options.maxUnresolvedFraction * inside);
  if (openBeyondRepair) {
    throw InvalidInput(
        "model is open beyond repair: " + std::to_string(unresolved) +
        " voxels could not be classified as inside or outside (" + std::to_string(inside) +
        " inside voxels; the mesh has " + std::to_string(report.openEdges) + " open and " +
        std::to_string(report.nonManifoldEdges) + " non-manifold edges); " +
        (options.capHoles
             ? std::to_string(capping.openBoundaryEdges) +
                   " boundary edges could not be capped (pinched holes) or the caps intersect the "
                   "mesh: repair the mesh into a watertight solid"
             : std::string("close the holes of the mesh or enable hole capping (--cap-holes)")));
  }
  if (inside < options.minInsideVoxels && !report.closed()) {
    // An open surface (a tube, a sheet cup) encloses nothing at any voxel size.
    throw InvalidInput("the model is open: " + std::to_string(report.openEdges) +
                       " boundary edges around " + describeRegion(report.defectBounds) +
                       ", and only " + std::to_string(inside) + " voxels at " + formatNumber(L) +
                       " mm are inside it; " + openModelAdvice(options.capHoles));
  }
  if (inside < options.minInsideVoxels) {
    // Aim for about a thousand inside voxels; never suggest anything coarser than half of L.
    const double suggestion = std::min(voxelSizeForCells(std::abs(report.volume), 1000.0), 0.5 * L);
    throw InvalidInput("voxel size too coarse for the model: " + formatNumber(L) + " mm gives " +
                       std::to_string(inside) + " inside voxels (at least " +
                       std::to_string(options.minInsideVoxels) +
                       " needed); use a voxel size of about " + formatNumber(suggestion) +
                       " mm or smaller");
  }
}

}  // namespace

void validateLayerJobOptions(const LayerJobOptions& options) {
  requirePositiveLength(options.layers.layerThickness, "layer thickness", "1.5");
  requirePositiveLength(options.voxelize.voxelSize, "voxel size", "0.5");
  const double budget = options.voxelize.memoryBudgetBytes;
  if (!std::isfinite(budget) || budget < 0.0) {
    throw InvalidInput("memory budget must be zero (automatic) or positive: " +
                       formatNumber(budget) + " bytes; pass a positive size or 0");
  }
  // below a megabyte no grid and no plan fits; advice computed from such a budget is absurd
  if (budget > 0.0 && budget < kMinMemoryBudgetBytes) {
    throw InvalidInput("memory budget must be 0 (automatic) or at least 1 MB: " +
                       formatNumber(budget) + " bytes; pass 0 or e.g. 4096 MB");
  }
  if (options.voxelize.padding < 1) {
    throw InvalidInput("grid padding must be at least one cell: " +
                       std::to_string(options.voxelize.padding) + "; pass 1 or more");
  }
  if (!std::isfinite(options.geodesic.seedBand)) {
    throw InvalidInput("seed band must be finite: " + formatNumber(options.geodesic.seedBand) +
                       " mm; pass 0 for the default (sqrt(3)·L)");
  }
  if (!std::isfinite(options.geodesic.paperSearchRadius)) {
    throw InvalidInput(
        "paper search radius must be finite: " + formatNumber(options.geodesic.paperSearchRadius) +
        "; pass 0 for the paper's 2·sqrt(3)");
  }
  if (options.layers.maxLayers < 1) {
    throw InvalidInput("layer limit must be at least 1: " +
                       std::to_string(options.layers.maxLayers) + "; pass a positive limit");
  }
  if (!(options.maxUnresolvedFraction >= 0.0)) {
    throw InvalidInput("unresolved-voxel fraction must not be negative: " +
                       formatNumber(options.maxUnresolvedFraction) + "; pass e.g. 0.01");
  }
}

namespace {

/// The stages up to and including the field (shared by both forms of runLayerJob).
void runStagesUpToField(const TriMesh& rawModel, const LayerJobOptions& options,
                        const Progress& progress, LayerJobResult& result, StageClock& clock) {
  validateLayerJobOptions(options);
  if (rawModel.empty()) {
    throw InvalidInput("model has no triangles: 0; pass a closed triangle mesh of the part");
  }

  // ---- clean ---------------------------------------------------------------------------------
  progress.report(0.0, "clean");
  clock.start("clean");
  result.clean = cleanMesh(rawModel, options.clean);
  // A closed, consistently oriented surface whose triangles all face inward (saved inside out,
  // or a reversed CAD solid: negative volume) is turned to face outward before anything reads
  // its orientation: start surfaces chosen by face direction, the layers' normals, the side of
  // a layer's boundary the beads keep to.
  double inwardVolume = 0.0;
  if (signedVolume(result.clean.mesh) < 0.0) {
    const MeshReport cleaned = analyzeMesh(result.clean.mesh);
    if (cleaned.closed() && cleaned.consistentlyOriented()) {
      for (Vec3i& t : result.clean.mesh.triangles) std::swap(t[1], t[2]);
      inwardVolume = cleaned.volume;
    }
  }
  clock.stop();

  // ---- start surface -------------------------------------------------------------------------
  progress.report(0.005, "start surface");
  clock.start("start surface");
  result.startDescription = options.start.describe();
  result.source = resolveStartSurface(result.clean.mesh, options.start);
  clock.stop();

  // ---- cap holes -----------------------------------------------------------------------------
  if (options.capHoles) {
    progress.report(0.008, "cap holes");
    clock.start("cap holes");
    const double L = options.voxelize.voxelSize;
    result.capping = capHoles(result.clean.mesh, result.source, {L, 0.25 * L});
    result.clean.mesh = std::move(result.capping.mesh);
    result.capping.mesh = TriMesh{};
    clock.stop();
  }
  const TriMesh& model = result.clean.mesh;

  // ---- analyze -------------------------------------------------------------------------------
  progress.report(0.01, "analyze");
  clock.start("analyze");
  result.meshReport = analyzeMesh(model);
  validateModel(result.meshReport);
  // Fails with ResourceLimit before anything large is allocated.
  (void)planGrid(model, options.voxelize);
  clock.stop();

  // ---- voxelize ------------------------------------------------------------------------------
  progress.report(0.02, "voxelize");
  clock.start("voxelize");
  result.voxelization = voxelize(model, options.voxelize, progress.sub(0.02, 0.2));
  validateGrid(result.voxelization, result.meshReport, result.capping, options);
  result.warnings =
      geometryWarnings(result.voxelization.stats, result.meshReport, options.capHoles);
  if (inwardVolume < 0.0) {
    result.warnings.insert(
        result.warnings.begin(),
        "the model's triangles all face inward (a signed volume of " + formatNumber(inwardVolume) +
            " mm^3: the surface was saved inside out); they were turned to face outward, so the "
            "part is the solid they enclose: check the normals of the program that wrote it");
  }
  clock.stop();

  // ---- field ---------------------------------------------------------------------------------
  progress.report(0.2, "field");
  clock.start("field");
  // With the model surface: exact line of sight and pivots on its concave edges.
  result.field = computeGeodesicField(result.voxelization.grid, model, result.source,
                                      options.geodesic, progress.sub(0.2, 0.8));
  checkReached(result.field.unreached, result.voxelization.grid.insideCount,
               result.meshReport.components, result.startDescription, result.warnings);
  clock.stop();
  const double h = options.layers.layerThickness;
  if (!(result.field.maxDistance >= h)) {
    throw InvalidInput(
        "layer thickness exceeds the part's extent from the start surface: h = " + formatNumber(h) +
        " mm, largest distance " + formatNumber(result.field.maxDistance) +
        " mm; use a layer thickness below the largest distance");
  }
}

void requireLayers(const LayersResult& layers, const LayerJobResult& result,
                   const LayerJobOptions& options) {
  if (layers.summaries.empty()) {
    throw InvalidInput("no layer surface lies inside the part: 0 layers at h = " +
                       formatNumber(options.layers.layerThickness) + " mm (largest distance " +
                       formatNumber(result.field.maxDistance) +
                       " mm); use a smaller layer thickness or voxel size");
  }
}

}  // namespace

LayerJobResult runLayerJob(const TriMesh& rawModel, const LayerJobOptions& options,
                           Progress progress) {
  const auto jobBegin = Clock::now();
  LayerJobResult result;
  StageClock clock(result.stageTimes);
  runStagesUpToField(rawModel, options, progress, result, clock);

  // ---- layers --------------------------------------------------------------------------------
  progress.report(0.8, "layers");
  clock.start("layers");
  result.layers = extractLayers(result.field.field, result.voxelization.grid, result.clean.mesh,
                                result.source, options.layers, progress.sub(0.8, 1.0));
  clock.stop();
  requireLayers(result.layers, result, options);
  progress.report(1.0, "layers");

  result.totalSeconds = std::chrono::duration<double>(Clock::now() - jobBegin).count();
  result.peakMemoryBytes = peakResidentMemoryBytes();
  return result;
}

LayerJobResult runLayerJob(const TriMesh& rawModel, const LayerJobOptions& options, LayerSink& sink,
                           Progress progress) {
  const auto jobBegin = Clock::now();
  LayerJobResult result;
  StageClock clock(result.stageTimes);
  runStagesUpToField(rawModel, options, progress, result, clock);

  // ---- layers --------------------------------------------------------------------------------
  progress.report(0.8, "layers");
  clock.start("layers");
  {
    // The field moves into the extraction, which extends it in place and frees it at the end.
    DistanceField field = std::move(result.field.field);
    result.field.field = DistanceField{};
    result.field.field.geometry = field.geometry;
    result.layers = streamLayers(std::move(field), result.voxelization.grid, result.clean.mesh,
                                 result.source, sink, options.layers, progress.sub(0.8, 1.0));
  }
  // No later stage needs the inside mask.
  std::vector<std::uint8_t>().swap(result.voxelization.grid.inside);
  clock.stop();
  requireLayers(result.layers, result, options);
  progress.report(1.0, "layers");

  result.totalSeconds = std::chrono::duration<double>(Clock::now() - jobBegin).count();
  result.peakMemoryBytes = peakResidentMemoryBytes();
  return result;
}

std::size_t peakResidentMemoryBytes() {
  struct rusage usage {};
  if (::getrusage(RUSAGE_SELF, &usage) != 0 || usage.ru_maxrss < 0) return 0;
  // Linux reports kilobytes.
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024u;
}

}  // namespace curvedslicer
