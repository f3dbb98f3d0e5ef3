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

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "layers/layer_internal.hpp"

namespace curvedslicer {
namespace {

using namespace layers_detail;

std::string formatNumber(double x) {
  std::ostringstream s;
  s.precision(10);
  s << x;
  return s.str();
}

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

/// Eq. 13: S_i = {P : i·h − L/2 ≤ t_P ≤ i·h + L/2}, i = 1..layerCount.
std::vector<VoxelLayerSet> collectVoxelSets(const DistanceField& field, double h, int layerCount,
                                            const Progress& progress) {
  const GridGeometry& g = field.geometry;
  const double halfL = 0.5 * g.voxelSize;
  const auto planes = static_cast<std::size_t>(g.dims.x());
  constexpr std::size_t kBlock = 8;  // x planes per block (fixed: deterministic order)
  const std::size_t blocks = (planes + kBlock - 1) / kBlock;
  const auto count = static_cast<std::size_t>(layerCount);
  std::vector<std::vector<std::vector<std::size_t>>> perBlock(blocks);
  runChunked(blocks, progress, "voxel sets", [&](std::size_t b) {
    auto& lists = perBlock[b];
    lists.resize(count);
    const std::size_t begin = b * kBlock * g.strideX();
    const std::size_t end = std::min(planes, (b + 1) * kBlock) * g.strideX();
    const double levels = layerCount;
    for (std::size_t n = begin; n < end; ++n) {
      const float value = field.distance[n];
      if (!(value < kInfF)) continue;
      const double t = value;
      // Candidates widened by one against rounding; the test below is the definition.
      const auto lo =
          static_cast<int>(std::clamp(std::ceil((t - halfL) / h) - 1.0, 1.0, levels + 1));
      const auto hi = static_cast<int>(std::clamp(std::floor((t + halfL) / h) + 1.0, 0.0, levels));
      for (int i = lo; i <= hi; ++i) {
        const double level = i * h;
        if (level - halfL <= t && t <= level + halfL) lists[i - 1].push_back(n);
      }
    }
  });
  std::vector<VoxelLayerSet> sets(count);
  for (std::size_t i = 0; i < count; ++i) {
    sets[i].index = static_cast<int>(i) + 1;
    sets[i].level = static_cast<double>(i + 1) * h;
    std::size_t total = 0;
    for (const auto& lists : perBlock) total += lists[i].size();
    sets[i].cells.reserve(total);
    for (auto& lists : perBlock) {
      sets[i].cells.insert(sets[i].cells.end(), lists[i].begin(), lists[i].end());
      std::vector<std::size_t>().swap(lists[i]);
    }
  }
  return sets;
}

}  // namespace

LayersResult extractLayers(const DistanceField& field, const VoxelGrid& grid, const TriMesh& model,
                           const TriMesh& source, const LayerOptions& options, Progress progress) {
  const auto start = std::chrono::steady_clock::now();
  checkInputs(field, grid, model, options);
  const double h = options.layerThickness;
  const FieldSummary summary = summarise(field);
  const int layerCount = countLayers(summary.maxDistance, options);
  progress.check();

  LayersResult result;
  LayerExtractionStats& stats = result.stats;
  if (layerCount == 0) {  // the solid is thinner than one layer
    progress.report(1.0, "voxel sets");
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }

  // ---- extending field ----
  FieldExtensionStats extension;
  std::vector<TriMesh> surfaces;
  {
    const std::vector<float> extended =
        extendField(field, grid, extension, progress.sub(0.0, 0.15));
    stats.extendedCells = extension.extendedCells;
    stats.partialFits = extension.partialFits;
    stats.nearestFallbacks = extension.nearestFallbacks;

    // ---- marching tetrahedra / merging layers ----
    surfaces =
        extractIsoSurfaces(extended, field.geometry, h, layerCount, progress.sub(0.15, 0.55));
  }

  // ---- clipping layers ----
  const auto count = static_cast<std::size_t>(layerCount);
  result.surfaces.resize(count);
  {
    const TriangleBvh modelBvh = options.clipToSolid ? TriangleBvh(model) : TriangleBvh();
    const std::vector<std::uint8_t> surfaceCells =
        options.clipToSolid ? markSurfaceCells(model, grid.geometry) : std::vector<std::uint8_t>{};
    std::vector<ClipStats> clipStats(count);
    runChunked(count, progress.sub(0.55, 0.8), "clipping layers", [&](std::size_t i) {
      LayerSurface& layer = result.surfaces[i];
      layer.index = static_cast<int>(i) + 1;
      layer.level = static_cast<double>(i + 1) * h;
      if (options.clipToSolid) {
        layer.mesh = clipSurfaceToSolid(surfaces[i], modelBvh, grid, surfaceCells, clipStats[i]);
      } else {
        layer.mesh = std::move(surfaces[i]);
        removeDegenerateAndUnused(layer.mesh);
      }
      surfaces[i] = TriMesh{};  // release the unclipped surface
      layer.area = surfaceArea(layer.mesh);
      layer.components = countEdgeComponents(layer.mesh);
    });
    for (const ClipStats& c : clipStats) {
      stats.exactDistanceQueries += c.exactQueries;
      stats.rimVertices += c.rimVertices;
    }
  }

  // ---- measuring thickness ----
  if (options.thicknessSamples >= 0) {
    const TriangleBvh sourceBvh(source);
    runChunked(count, progress.sub(0.8, 0.95), "measuring thickness", [&](std::size_t i) {
      LayerSurface& layer = result.surfaces[i];
      if (layer.mesh.vertices.empty()) return;
      if (i == 0) {
        layer.thicknessToPrevious =
            measureThickness(layer.mesh, sourceBvh, options.thicknessSamples);
      } else {
        // Queries come with hints, so the k-d tree would not pay for itself.
        const TriangleBvh previous(result.surfaces[i - 1].mesh, TriangleBvhOptions{false});
        layer.thicknessToPrevious =
            measureThickness(layer.mesh, previous, options.thicknessSamples);
      }
    });
  }

  // ---- voxel sets ----
  result.voxelSets = collectVoxelSets(field, h, layerCount, progress.sub(0.95, 1.0));
  progress.report(1.0, "voxel sets");
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace curvedslicer
