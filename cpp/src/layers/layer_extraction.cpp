// extractLayers: field extension, marching tetrahedra, clipping, statistics, voxel sets
// (paper §2.3, eq. 13). Phases are named as the progress stages.
#include "curvedslicer/layers/layer_extraction.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "layers/layer_internal.hpp"

namespace curvedslicer {
namespace {

using namespace layers_detail;

std::string describeDims(const Vec3i& d) {
  return std::to_string(d.x()) + "×" + std::to_string(d.y()) + "×" + std::to_string(d.z());
}

void checkInputs(const DistanceField& field, const VoxelGrid& grid, const TriMesh& model,
                 const LayerOptions& options) {
  const double h = options.layerThickness;
  if (!(h > 0.0) || !std::isfinite(h)) {
    throw InvalidInput("layer thickness must be positive: " + formatNumber(h) +
                       " mm; pass a finite value such as 1.5");
  }
  const GridGeometry& f = field.geometry;
  const GridGeometry& g = grid.geometry;
  const double tol = 1e-9 * g.voxelSize;
  if (f.dims != g.dims || f.voxelSize != g.voxelSize || (f.corner - g.corner).norm() > tol ||
      (f.frame.origin - g.frame.origin).norm() > tol ||
      (f.frame.rotation - g.frame.rotation).norm() > 1e-9) {
    throw InvalidInput("distance field geometry does not match the voxel grid: field " +
                       describeDims(f.dims) + " cells of " + formatNumber(f.voxelSize) +
                       " mm, grid " + describeDims(g.dims) + " cells of " +
                       formatNumber(g.voxelSize) + " mm; compute the field from this grid");
  }
  if (field.distance.size() != g.cellCount() || grid.inside.size() != g.cellCount()) {
    throw InvalidInput("distance field or inside mask has the wrong size: " +
                       std::to_string(field.distance.size()) + " distances and " +
                       std::to_string(grid.inside.size()) + " mask entries for " +
                       std::to_string(g.cellCount()) + " cells; compute both from one grid");
  }
  resolveLayerTolerance(options.simplification, g.voxelSize);  // throws on a bad tolerance
  if (options.clipToSolid && model.empty()) {
    throw InvalidInput(
        "model surface for clipping is empty: 0 triangles; pass the solid's surface mesh or set "
        "clipToSolid = false");
  }
}

struct FieldSummary {
  std::size_t reached = 0;
  double maxDistance = -kInf;
};

FieldSummary summarise(const DistanceField& field) {
  const std::size_t n = field.distance.size();
  FieldSummary s;
  std::size_t nanCount = 0, firstNan = n;
  for (std::size_t c = 0; c < n; ++c) {
    const float d = field.distance[c];
    if (std::isnan(d)) {
      ++nanCount;
      firstNan = std::min(firstNan, c);
    } else if (d < kInfF) {
      ++s.reached;
      s.maxDistance = std::max(s.maxDistance, static_cast<double>(d));
    }
  }
  if (nanCount > 0) {
    throw InvalidInput("distance field has NaN values: " + std::to_string(nanCount) +
                       " cells, first at cell " + std::to_string(firstNan) +
                       "; use +inf for cells without a distance");
  }
  if (s.reached == 0) {
    throw InvalidInput("distance field has no reached voxels: 0 of " + std::to_string(n) +
                       " cells; compute the field from a start surface that touches the solid");
  }
  return s;
}

/// Number of levels i·h (i ≥ 1) not above `maxDistance`; throws if more than maxLayers.
int countLayers(double maxDistance, const LayerOptions& options) {
  const double h = options.layerThickness;
  if (maxDistance < h) return 0;
  const double estimate = std::floor(maxDistance / h);
  const auto limit = static_cast<double>(std::max(0, options.maxLayers));
  auto tooMany = [&](double count) {
    std::ostringstream msg;
    msg.precision(10);
    msg << "layer thickness gives too many layers: " << h << " mm over a maximum distance of "
        << maxDistance << " mm gives " << count
        << " layers, more than maxLayers = " << options.maxLayers
        << "; increase the layer thickness to at least " << maxDistance / std::max(1.0, limit)
        << " mm (or raise maxLayers)";
    return InvalidInput(msg.str());
  };
  if (estimate > limit + 1.0) throw tooMany(estimate);
  auto n = static_cast<long long>(estimate);
  while (static_cast<double>(n + 1) * h <= maxDistance) ++n;
  while (n > 0 && static_cast<double>(n) * h > maxDistance) --n;
  if (static_cast<double>(n) > limit) throw tooMany(static_cast<double>(n));
  return static_cast<int>(n);
}

/// Distances from vertices of `layer` to the reference surface: all of them if maxSamples == 0 or
/// the layer has no more vertices, else at most maxSamples in evenly spaced runs of kRun
/// consecutive vertices (consecutive vertices are neighbours, so each search starts from the
/// previous answer as a tight hint).
ThicknessStats measureThickness(const TriMesh& layer, const TriangleBvh& reference,
                                int maxSamples) {
  ThicknessStats stats;
  const std::size_t nv = layer.vertices.size();
  if (nv == 0 || reference.empty()) return stats;
  const std::size_t cap = maxSamples > 0 ? static_cast<std::size_t>(maxSamples) : nv;
  constexpr std::size_t kRun = 64;
  const std::size_t runs = std::max<std::size_t>(1, cap / kRun);
  const std::size_t spacing = cap >= nv ? nv : std::max(kRun, nv / runs);
  const std::size_t run = cap >= nv ? nv : kRun;
  double sum = 0.0;
  stats.min = kInf;
  stats.max = 0.0;
  ClosestPoint hint;
  for (std::size_t first = 0; first < nv && stats.samples < cap; first += spacing) {
    for (std::size_t v = first; v < std::min(nv, first + run) && stats.samples < cap; ++v) {
      hint = reference.closestPoint(layer.vertices[v], hint);
      const double d = hint.distance;
      stats.min = std::min(stats.min, d);
      stats.max = std::max(stats.max, d);
      sum += d;
      ++stats.samples;
    }
  }
  stats.mean = sum / static_cast<double>(stats.samples);
  return stats;
}

/// Candidate levels of eq. 13 for a value t: [lo, hi] (widened by one against rounding; the test
/// in `inSet` is the definition).
struct LevelRange {
  int lo = 1, hi = 0;
};
LevelRange candidateLevels(double t, double h, double halfL, int layerCount) {
  const double levels = layerCount;
  return {static_cast<int>(std::clamp(std::ceil((t - halfL) / h) - 1.0, 1.0, levels + 1)),
          static_cast<int>(std::clamp(std::floor((t + halfL) / h) + 1.0, 0.0, levels))};
}
bool inSet(double t, int i, double h, double halfL) {
  const double level = i * h;
  return level - halfL <= t && t <= level + halfL;
}

constexpr std::size_t kSetBlock = 8;  // x planes per block of the eq. 13 scans (fixed)

/// |S_i| for i = 1..layerCount from the field before its extension (cells with a value).
std::vector<std::size_t> countVoxelSets(const std::vector<float>& values, const GridGeometry& g,
                                        double h, int layerCount, const Progress& progress) {
  const double halfL = 0.5 * g.voxelSize;
  const auto planes = static_cast<std::size_t>(g.dims.x());
  const std::size_t blocks = (planes + kSetBlock - 1) / kSetBlock;
  const auto count = static_cast<std::size_t>(layerCount);
  std::vector<std::vector<std::size_t>> perBlock(blocks);
  runChunked(blocks, progress, "voxel sets", [&](std::size_t b) {
    std::vector<std::size_t>& sizes = perBlock[b];
    sizes.assign(count, 0);
    const std::size_t begin = b * kSetBlock * g.strideX();
    const std::size_t end = std::min(planes, (b + 1) * kSetBlock) * g.strideX();
    for (std::size_t n = begin; n < end; ++n) {
      const float value = values[n];
      if (!(value < kInfF)) continue;
      const double t = value;
      const LevelRange r = candidateLevels(t, h, halfL, layerCount);
      for (int i = r.lo; i <= r.hi; ++i) {
        if (inSet(t, i, h, halfL)) ++sizes[static_cast<std::size_t>(i - 1)];
      }
    }
  });
  std::vector<std::size_t> sizes(count, 0);
  for (const auto& block : perBlock) {
    for (std::size_t i = 0; i < count; ++i) sizes[i] += block[i];
  }
  return sizes;
}

/// Eq. 13: S_i = {P : i·h − L/2 ≤ t_P ≤ i·h + L/2}, i = levelBegin..levelEnd, cells in increasing
/// order. `values` is the extended field; the cells listed in `extended` (increasing) had no
/// value before the extension and belong to no set.
std::vector<VoxelLayerSet> collectVoxelSets(const std::vector<float>& values,
                                            const std::vector<std::size_t>& extended,
                                            const GridGeometry& g, double h, int layerCount,
                                            int levelBegin, int levelEnd,
                                            const Progress& progress) {
  const double halfL = 0.5 * g.voxelSize;
  const auto planes = static_cast<std::size_t>(g.dims.x());
  const std::size_t blocks = (planes + kSetBlock - 1) / kSetBlock;
  const auto count = static_cast<std::size_t>(levelEnd - levelBegin + 1);
  const double lowest = levelBegin * h - halfL, highest = levelEnd * h + halfL;
  std::vector<std::vector<std::vector<std::size_t>>> perBlock(blocks);
  runChunked(blocks, progress, "voxel sets", [&](std::size_t b) {
    auto& lists = perBlock[b];
    lists.resize(count);
    const std::size_t begin = b * kSetBlock * g.strideX();
    const std::size_t end = std::min(planes, (b + 1) * kSetBlock) * g.strideX();
    auto skip = std::lower_bound(extended.begin(), extended.end(), begin);
    for (std::size_t n = begin; n < end; ++n) {
      const float value = values[n];
      if (!(value < kInfF)) continue;
      const double t = value;
      if (t < lowest - h || t > highest + h) continue;  // no level of this batch is near
      while (skip != extended.end() && *skip < n) ++skip;
      if (skip != extended.end() && *skip == n) continue;
      const LevelRange r = candidateLevels(t, h, halfL, layerCount);
      for (int i = std::max(r.lo, levelBegin); i <= std::min(r.hi, levelEnd); ++i) {
        if (inSet(t, i, h, halfL)) lists[static_cast<std::size_t>(i - levelBegin)].push_back(n);
      }
    }
  });
  std::vector<VoxelLayerSet> sets(count);
  for (std::size_t q = 0; q < count; ++q) {
    sets[q].index = levelBegin + static_cast<int>(q);
    sets[q].level = static_cast<double>(sets[q].index) * h;
    std::size_t total = 0;
    for (const auto& lists : perBlock) total += lists[q].size();
    sets[q].cells.reserve(total);
    for (auto& lists : perBlock) {
      sets[q].cells.insert(sets[q].cells.end(), lists[q].begin(), lists[q].end());
      std::vector<std::size_t>().swap(lists[q]);
    }
  }
  return sets;
}

/// Consecutive level ranges [first, last] whose crossed cubes add up to at most `budget` (a level
/// above it alone is a batch of its own).
std::vector<std::pair<int, int>> planBatches(const std::vector<std::uint64_t>& crossings,
                                             std::size_t budget) {
  std::vector<std::pair<int, int>> batches;
  std::uint64_t sum = 0;
  for (std::size_t q = 0; q < crossings.size(); ++q) {
    const int level = static_cast<int>(q) + 1;
    if (batches.empty() || sum + crossings[q] > budget) {
      batches.emplace_back(level, level);
      sum = crossings[q];
    } else {
      batches.back().second = level;
      sum += crossings[q];
    }
  }
  return batches;
}

LayerSummary summarizeLayer(const LayerSurface& layer, std::size_t voxelSetSize,
                            std::size_t fullResolutionTriangles) {
  LayerSummary s;
  s.index = layer.index;
  s.level = layer.level;
  s.vertices = layer.mesh.vertexCount();
  s.triangles = layer.mesh.triangleCount();
  s.fullResolutionTriangles = fullResolutionTriangles;
  s.area = layer.area;
  s.components = layer.components;
  s.thicknessToPrevious = layer.thicknessToPrevious;
  s.voxelSetSize = voxelSetSize;
  return s;
}

/// Adds the batch's clipping counts to the statistics.
void addClipStats(const std::vector<ClipStats>& clipStats, LayerExtractionStats& stats) {
  for (const ClipStats& c : clipStats) {
    stats.exactDistanceQueries += c.exactQueries;
    stats.rimVertices += c.rimVertices;
  }
}

/// Simplifies the batch's clipped surfaces in place (when on) and measures their area and
/// components; returns their triangle counts before simplification and adds to the statistics.
std::vector<std::size_t> simplifyBatch(std::vector<LayerSurface>& layers,
                                       const LayerOptions& options, double voxelSize,
                                       const Progress& progress, LayerExtractionStats& stats) {
  const auto start = std::chrono::steady_clock::now();
  const bool simplify = options.simplification.enabled;
  const double tolerance =
      simplify ? resolveLayerTolerance(options.simplification, voxelSize) : 0.0;
  std::vector<std::size_t> before(layers.size());
  std::vector<char> keptFull(layers.size(), 0);
  runChunked(layers.size(), progress, "simplifying layers", [&](std::size_t q) {
    LayerSurface& layer = layers[q];
    before[q] = layer.mesh.triangleCount();
    if (simplify) {
      SimplifiedSurface simplified =
          simplifyLayerSurface(layer.mesh, tolerance, kDefaultLayerMaxEdgeVoxels * voxelSize);
      keptFull[q] = simplified.keptFull ? 1 : 0;
      layer.mesh = std::move(simplified.mesh);
    }
    layer.area = surfaceArea(layer.mesh);
    layer.components = countEdgeComponents(layer.mesh);
  });
  stats.simplificationTolerance = tolerance;
  for (std::size_t q = 0; q < layers.size(); ++q) {
    stats.layersKeptFull += keptFull[q] != 0 ? 1 : 0;
    stats.fullResolutionTriangles += before[q];
    stats.simplifiedTriangles += layers[q].mesh.triangleCount();
  }
  if (simplify) {
    stats.simplificationSeconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return before;
}

/// Collects everything (extractLayers).
class CollectingSink final : public LayerSink {
 public:
  explicit CollectingSink(LayersResult& result) : result_(result) {}
  void begin(int layerCount, const std::vector<std::size_t>&, const GridGeometry&) override {
    result_.surfaces.reserve(static_cast<std::size_t>(layerCount));
    result_.voxelSets.reserve(static_cast<std::size_t>(layerCount));
  }
  void acceptSurface(LayerSurface&& surface) override {
    result_.surfaces.push_back(std::move(surface));
  }
  void acceptVoxelSet(VoxelLayerSet&& set, const std::vector<float>&) override {
    result_.voxelSets.push_back(std::move(set));
  }

 private:
  LayersResult& result_;
};

/// The work shared by extractLayers and streamLayers, on the field's values (extended in place).
/// Inputs are checked; `layerCount` ≥ 1.
void extractInBatches(std::vector<float>& values, const VoxelGrid& grid, const TriMesh& model,
                      const TriMesh& source, LayerSink& sink, const LayerOptions& options,
                      int layerCount, const Progress& progress, LayersResult& result) {
  const GridGeometry& geometry = grid.geometry;
  const double h = options.layerThickness;
  LayerExtractionStats& stats = result.stats;
  const auto count = static_cast<std::size_t>(layerCount);

  // ---- voxel sets (sizes) ----
  const std::vector<std::size_t> setSizes =
      countVoxelSets(values, geometry, h, layerCount, progress.sub(0.0, 0.02));

  // ---- extending field ----
  FieldExtensionStats extension;
  const std::vector<std::size_t> extended =
      extendFieldInPlace(values, grid, extension, progress.sub(0.02, 0.12));
  stats.extendedCells = extension.extendedCells;
  stats.partialFits = extension.partialFits;
  stats.nearestFallbacks = extension.nearestFallbacks;

  // ---- counting crossings ----
  const IsoSurfacePlan plan =
      planIsoSurfaces(values, geometry, h, layerCount, progress.sub(0.12, 0.17));
  const std::size_t budget =
      options.batchCrossings > 0
          ? options.batchCrossings
          : std::max(kMinBatchCrossings, geometry.cellCount() / kCellsPerBatchCrossing);
  const std::vector<std::pair<int, int>> batches = planBatches(plan.crossingCubes, budget);
  std::uint64_t totalCrossings = 0;
  for (std::uint64_t c : plan.crossingCubes) totalCrossings += c;
  result.batches = batches.size();

  sink.begin(layerCount, setSizes, geometry);
  result.summaries.reserve(count);

  const TriangleBvh modelBvh = options.clipToSolid ? TriangleBvh(model) : TriangleBvh();
  const std::vector<std::uint8_t> surfaceCells =
      options.clipToSolid ? markSurfaceCells(model, geometry) : std::vector<std::uint8_t>{};
  const bool measure = options.thicknessSamples >= 0;
  const TriangleBvh sourceBvh = measure ? TriangleBvh(source) : TriangleBvh();
  TriMesh previous;  // the last layer of the previous batch (thickness reference)

  // Each batch gets a share of [0.17, 1] in proportion to its levels and crossings.
  const double weightPerLevel =
      totalCrossings > 0 ? static_cast<double>(totalCrossings) / static_cast<double>(count) : 1.0;
  const double totalWeight = static_cast<double>(totalCrossings) + weightPerLevel * count;
  double done = 0.0;
  for (const auto& [first, last] : batches) {
    std::uint64_t crossings = 0;
    for (int level = first; level <= last; ++level) {
      crossings += plan.crossingCubes[static_cast<std::size_t>(level - 1)];
    }
    result.largestBatchCrossings =
        std::max(result.largestBatchCrossings, static_cast<std::size_t>(crossings));
    const double weight = static_cast<double>(crossings) + weightPerLevel * (last - first + 1);
    const Progress batch =
        progress.sub(0.17 + 0.83 * done / totalWeight, 0.17 + 0.83 * (done + weight) / totalWeight);
    done += weight;
    const auto size = static_cast<std::size_t>(last - first + 1);

    // ---- marching tetrahedra / merging layers ----
    std::vector<TriMesh> surfaces =
        extractIsoSurfaces(values, geometry, plan, first, last, batch.sub(0.0, 0.5));

    // ---- clipping layers ----
    std::vector<LayerSurface> layers(size);
    std::vector<ClipStats> clipStats(size);
    // `first` by an init-capture: clang before 16 cannot capture a structured binding.
    runChunked(size, batch.sub(0.5, 0.65), "clipping layers", [&, level0 = first](std::size_t q) {
      LayerSurface& layer = layers[q];
      layer.index = level0 + static_cast<int>(q);
      layer.level = static_cast<double>(layer.index) * h;
      if (options.clipToSolid) {
        layer.mesh = clipSurfaceToSolid(surfaces[q], modelBvh, grid, surfaceCells, clipStats[q]);
      } else {
        layer.mesh = std::move(surfaces[q]);
        removeDegenerateAndUnused(layer.mesh);
      }
      surfaces[q] = TriMesh{};  // release the unclipped surface
    });
    std::vector<TriMesh>().swap(surfaces);
    addClipStats(clipStats, stats);

    // ---- simplifying layers ----
    const std::vector<std::size_t> fullTriangles =
        simplifyBatch(layers, options, geometry.voxelSize, batch.sub(0.65, 0.8), stats);

    // ---- measuring thickness ----
    if (measure) {
      runChunked(size, batch.sub(0.8, 0.95), "measuring thickness", [&](std::size_t q) {
        LayerSurface& layer = layers[q];
        if (layer.mesh.vertices.empty()) return;
        if (layer.index == 1) {
          layer.thicknessToPrevious =
              measureThickness(layer.mesh, sourceBvh, options.thicknessSamples);
        } else {
          // Queries come with hints, so the k-d tree would not pay for itself.
          const TriMesh& before = q == 0 ? previous : layers[q - 1].mesh;
          const TriangleBvh reference(before, TriangleBvhOptions{false});
          layer.thicknessToPrevious =
              measureThickness(layer.mesh, reference, options.thicknessSamples);
        }
      });
      if (last < layerCount) previous = layers.back().mesh;
    }

    // Hand the surfaces over in order.
    for (LayerSurface& layer : layers) {
      const auto q = static_cast<std::size_t>(layer.index - first);
      result.summaries.push_back(summarizeLayer(
          layer, setSizes[static_cast<std::size_t>(layer.index - 1)], fullTriangles[q]));
      sink.acceptSurface(std::move(layer));
    }
    std::vector<LayerSurface>().swap(layers);

    // ---- voxel sets ----
    std::vector<VoxelLayerSet> sets = collectVoxelSets(values, extended, geometry, h, layerCount,
                                                       first, last, batch.sub(0.95, 1.0));
    for (VoxelLayerSet& set : sets) sink.acceptVoxelSet(std::move(set), values);
  }
  progress.report(1.0, "voxel sets");
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

LayersResult extractLayers(const DistanceField& field, const VoxelGrid& grid, const TriMesh& model,
                           const TriMesh& source, const LayerOptions& options, Progress progress) {
  const auto start = std::chrono::steady_clock::now();
  checkInputs(field, grid, model, options);
  const FieldSummary summary = summarise(field);
  const int layerCount = countLayers(summary.maxDistance, options);
  progress.check();

  LayersResult result;
  if (layerCount == 0) {  // the solid is thinner than one layer
    progress.report(1.0, "voxel sets");
    result.stats.seconds = secondsSince(start);
    return result;
  }
  std::vector<float> values = field.distance;
  CollectingSink sink(result);
  extractInBatches(values, grid, model, source, sink, options, layerCount, progress, result);
  result.stats.seconds = secondsSince(start);
  return result;
}

LayersResult streamLayers(DistanceField&& field, const VoxelGrid& grid, const TriMesh& model,
                          const TriMesh& source, LayerSink& sink, const LayerOptions& options,
                          Progress progress) {
  const auto start = std::chrono::steady_clock::now();
  checkInputs(field, grid, model, options);
  const FieldSummary summary = summarise(field);
  const int layerCount = countLayers(summary.maxDistance, options);
  progress.check();

  LayersResult result;
  std::vector<float> values = std::move(field.distance);
  field.distance = {};
  if (layerCount == 0) {
    sink.begin(0, {}, grid.geometry);
    progress.report(1.0, "voxel sets");
    result.stats.seconds = secondsSince(start);
    return result;
  }
  extractInBatches(values, grid, model, source, sink, options, layerCount, progress, result);
  result.stats.seconds = secondsSince(start);
  return result;
}

}  // namespace curvedslicer
