#include "curvedslicer/paths/coverage.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <optional>
#include <string>
#include <unordered_map>

#include <omp.h>

#include "curvedslicer/core/error.hpp"
#include "paths_internal.hpp"

namespace curvedslicer {

namespace {

using paths_detail::formatNumber;

/// One segment of a bead's centre line with its arc-length positions and widths at both ends.
struct BeadSegment {
  Vec3 a, b;
  double arcA = 0.0, arcB = 0.0;      ///< mm along the path
  double widthA = 0.0, widthB = 0.0;  ///< mm
  int path = 0;
  Vec3 ab = Vec3::Zero();  ///< b − a
  double len2 = 0.0;       ///< |b − a|²
};

/// What the overlap test needs of a path: its length and whether it closes.
struct BeadPath {
  double length = 0.0;
  bool closed = false;
};

double widthOf(const PathPoint& p, double s) {
  if (!(p.width >= 0.0) || !std::isfinite(p.width)) {
    throw InvalidInput("bead width must be a finite number of mm, not negative: " +
                       formatNumber(p.width) + "; pass 0 for the bead spacing or a width in mm");
  }
  return p.width > 0.0 ? p.width : s;
}

// ---- beads ----

/// Every path's segments (closing segment included); a path of one point is one degenerate
/// segment (a disc).
std::vector<BeadSegment> collectSegments(const std::vector<PlanPath>& paths, double s,
                                         std::vector<BeadPath>& beadPaths) {
  std::vector<BeadSegment> segments;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    const std::vector<PathPoint>& pts = paths[k].points;
    BeadPath info;
    info.closed = paths[k].closed && pts.size() >= 3;
    const std::size_t n = pts.size();
    const std::size_t count = n == 1 ? 1 : (info.closed ? n : n - 1);
    for (std::size_t i = 0; i < count && n > 0; ++i) {
      const PathPoint& p = pts[i];
      const PathPoint& q = pts[n == 1 ? 0 : (i + 1) % n];
      BeadSegment seg{p.position,    q.position,    info.length,        0.0,
                      widthOf(p, s), widthOf(q, s), static_cast<int>(k)};
      info.length += (q.position - p.position).norm();
      seg.arcB = info.length;
      seg.ab = seg.b - seg.a;
      seg.len2 = seg.ab.squaredNorm();
      segments.push_back(seg);
    }
    beadPaths.push_back(info);
  }
  return segments;
}

/// A dense grid of cells; each cell lists the segments whose reach (box grown by half the larger
/// end width) touches it, so every bead that can cover a point is listed in the point's cell.
class SegmentCells {
 public:
  SegmentCells(const std::vector<BeadSegment>& segments, double cell) {
    if (segments.empty()) return;
    Aabb box;
    for (const BeadSegment& g : segments) box.extend(reachOf(g));
    origin_ = box.min;
    cell_ = cell;
    // Keep the grid within a few million cells (a huge layer with narrow beads).
    constexpr double kMaxCells = 4.0e6;
    const Vec3 size = box.size();
    const auto cellsFor = [&](double c) {
      return (std::floor(size.x() / c) + 1) * (std::floor(size.y() / c) + 1) *
             (std::floor(size.z() / c) + 1);
    };
    while (cellsFor(cell_) > kMaxCells) cell_ *= 1.5;
    for (int d = 0; d < 3; ++d) dims_[d] = static_cast<int>(std::floor(size[d] / cell_)) + 1;
    fill(segments);
  }

  /// The segment indices of the cell holding `p` (empty outside the grid).
  std::pair<const int*, const int*> near(const Vec3& p) const {
    if (start_.empty()) return {nullptr, nullptr};
    std::array<int, 3> c{};
    for (int d = 0; d < 3; ++d) {
      c[d] = static_cast<int>(std::floor((p[d] - origin_[d]) / cell_));
      if (c[d] < 0 || c[d] >= dims_[d]) return {nullptr, nullptr};
    }
    const std::size_t i = index(c[0], c[1], c[2]);
    return {ids_.data() + start_[i], ids_.data() + start_[i + 1]};
  }

 private:
  static Aabb reachOf(const BeadSegment& g) {
    const double r = 0.5 * std::max(g.widthA, g.widthB);
    Aabb b;
    b.extend(g.a.cwiseMin(g.b) - Vec3::Constant(r));
    b.extend(g.a.cwiseMax(g.b) + Vec3::Constant(r));
    return b;
  }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * dims_[1] + j) * dims_[0] + i;
  }
  template <typename F>
  void forEachCell(const BeadSegment& g, F&& f) const {
    const Aabb b = reachOf(g);
    std::array<int, 3> lo{}, hi{};
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::clamp(static_cast<int>(std::floor((b.min[d] - origin_[d]) / cell_)), 0,
                         dims_[d] - 1);
      hi[d] = std::clamp(static_cast<int>(std::floor((b.max[d] - origin_[d]) / cell_)), 0,
                         dims_[d] - 1);
    }
    for (int k = lo[2]; k <= hi[2]; ++k) {
      for (int j = lo[1]; j <= hi[1]; ++j) {
        for (int i = lo[0]; i <= hi[0]; ++i) f(index(i, j, k));
      }
    }
  }
  /// Counting sort of (cell, segment) pairs into the compressed lists.
  void fill(const std::vector<BeadSegment>& segments) {
    start_.assign(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
    for (const BeadSegment& g : segments) forEachCell(g, [&](std::size_t c) { ++start_[c + 1]; });
    std::partial_sum(start_.begin(), start_.end(), start_.begin());
    ids_.resize(start_.back());
    std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
    for (std::size_t s = 0; s < segments.size(); ++s) {
      forEachCell(segments[s], [&](std::size_t c) { ids_[next[c]++] = static_cast<int>(s); });
    }
  }

  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1.0;
  std::array<int, 3> dims_{0, 0, 0};
  std::vector<std::uint32_t> start_;
  std::vector<int> ids_;
};

// ---- samples ----

enum class SampleCover { Void, Once, Overlap };

/// A bead covering a sample: which path, where along it, and its width there.
struct BeadHit {
  int path;
  double arc;
  double width;
};

/// Classifies samples; one per thread (its hit buffer), sharing the segments and their cells.
class SampleClassifier {
 public:
  SampleClassifier(const std::vector<BeadSegment>& segments, const std::vector<BeadPath>& paths,
                   const SegmentCells& cells)
      : segments_(segments), paths_(paths), cells_(cells) {}

  /// Overlap as soon as a bead far apart from one found before covers p.
  SampleCover classify(const Vec3& p) {
    hits_.clear();
    const auto [begin, end] = cells_.near(p);
    for (const int* it = begin; it != end; ++it) {
      const std::optional<BeadHit> hit = hitOf(p, segments_[*it]);
      if (!hit) continue;
      for (const BeadHit& earlier : hits_) {
        if (farApart(earlier, *hit)) return SampleCover::Overlap;
      }
      hits_.push_back(*hit);
    }
    return hits_.empty() ? SampleCover::Void : SampleCover::Once;
  }

 private:
  static std::optional<BeadHit> hitOf(const Vec3& p, const BeadSegment& g) {
    const Vec3& ab = g.ab;
    const double len2 = g.len2;
    const double t = len2 > 0.0 ? std::clamp((p - g.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const double width = g.widthA + t * (g.widthB - g.widthA);
    if ((g.a + t * ab - p).squaredNorm() > 0.25 * width * width) return std::nullopt;
    return BeadHit{g.path, g.arcA + t * (g.arcB - g.arcA), width};
  }
  /// Two beads overlap at a point: different paths, or one path more than a bead width apart.
  bool farApart(const BeadHit& x, const BeadHit& y) const {
    if (x.path != y.path) return true;
    const BeadPath& path = paths_[x.path];
    double d = std::abs(x.arc - y.arc);
    if (path.closed) d = std::min(d, path.length - d);
    return d > std::max(x.width, y.width);
  }

  const std::vector<BeadSegment>& segments_;
  const std::vector<BeadPath>& paths_;
  const SegmentCells& cells_;
  std::vector<BeadHit> hits_;
};

/// A 64-bit mix (splitmix64's finaliser): deterministic pseudo-random bits from a key.
std::uint64_t mixBits(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

/// Two numbers in [0, 1) from a key (53 bits each).
std::array<double, 2> unitPair(std::uint64_t key) {
  const std::uint64_t x = mixBits(key), y = mixBits(x ^ 0x5851f42d4c957f2dull);
  constexpr double kScale = 1.0 / 9007199254740992.0;  // 2^-53
  return {static_cast<double>(x >> 11) * kScale, static_cast<double>(y >> 11) * kScale};
}

/// A point uniformly placed in the triangle (o, o + u, o + v) by the unit pair r.
Vec3 pointInTriangle(const Vec3& o, const Vec3& u, const Vec3& v, std::array<double, 2> r) {
  if (r[0] + r[1] > 1.0) r = {1.0 - r[0], 1.0 - r[1]};
  return o + r[0] * u + r[1] * v;
}

/// Calls f(point, area) for the n² sub-triangles of triangle t (n from the sample spacing h), one
/// sample per sub-triangle at a position jittered inside it (stratified sampling). The offsets
/// come from a hash of the triangle and sub-triangle indices: deterministic and independent of
/// the thread count, and not aligned with the regular mesh (bead edges and small gaps between
/// beads parallel to the mesh lines would alias with a fixed pattern).
template <typename F>
void forEachSample(const TriMesh& mesh, std::size_t t, double spacing, F&& f) {
  const Vec3 a = mesh.corner(t, 0), b = mesh.corner(t, 1), c = mesh.corner(t, 2);
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing)));
  const double area = mesh.triangleArea(t) / (static_cast<double>(n) * n);
  const Vec3 u = (b - a) / n, v = (c - a) / n;
  std::uint64_t key = static_cast<std::uint64_t>(t) << 32;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; i + j < n; ++j) {
      const Vec3 corner = a + i * u + j * v;
      f(pointInTriangle(corner, u, v, unitPair(key++)), area);  // upward sub-triangle
      if (i + j < n - 1) {  // downward sub-triangle (corner + u + v, corner + v, corner + u)
        f(pointInTriangle(corner + u + v, -u, -v, unitPair(key++)), area);
      }
    }
  }
}

// ---- void patches ----

/// Union-find over grid cells.
int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

/// The void samples grouped into patches: cells of size `cell` holding samples, joined with their
/// 26 neighbours. Returns the patch index of every sample; `patchCount` is set.
std::vector<int> clusterSamples(const std::vector<Vec3>& points, double cell, int& patchCount) {
  const auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
    const auto u = [](std::int64_t v) { return static_cast<std::uint64_t>(v) & 0x1fffffu; };
    return (u(i) << 42) | (u(j) << 21) | u(k);
  };
  std::unordered_map<std::uint64_t, int> cellIndex;
  cellIndex.reserve(points.size() / 4 + 16);
  std::vector<std::array<std::int64_t, 3>> cellAt;
  std::vector<int> sampleCell(points.size());
  std::uint64_t lastKey = 0;
  int lastCell = -1;  // consecutive samples (one triangle's) mostly share a cell
  for (std::size_t s = 0; s < points.size(); ++s) {
    std::array<std::int64_t, 3> c{};
    for (int d = 0; d < 3; ++d) c[d] = static_cast<std::int64_t>(std::floor(points[s][d] / cell));
    const std::uint64_t k = key(c[0], c[1], c[2]);
    if (lastCell < 0 || k != lastKey) {
      const auto [it, added] = cellIndex.emplace(k, static_cast<int>(cellAt.size()));
      if (added) cellAt.push_back(c);
      lastKey = k;
      lastCell = it->second;
    }
    sampleCell[s] = lastCell;
  }
  std::vector<int> parent(cellAt.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t i = 0; i < cellAt.size(); ++i) {
    const auto& c = cellAt[i];
    // The 13 neighbours after the cell in (x, y, z) order: each pair of neighbours once.
    for (int dx = 0; dx <= 1; ++dx) {
      for (int dy = dx == 0 ? 0 : -1; dy <= 1; ++dy) {
        for (int dz = dx == 0 && dy == 0 ? 1 : -1; dz <= 1; ++dz) {
          const auto it = cellIndex.find(key(c[0] + dx, c[1] + dy, c[2] + dz));
          if (it == cellIndex.end()) continue;
          const int a = findRoot(parent, static_cast<int>(i)), b = findRoot(parent, it->second);
          if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
      }
    }
  }
  std::vector<int> patchOfRoot(cellAt.size(), -1);
  patchCount = 0;
  std::vector<int> patch(points.size());
  for (std::size_t s = 0; s < points.size(); ++s) {
    const int root = findRoot(parent, sampleCell[s]);
    if (patchOfRoot[root] < 0) patchOfRoot[root] = patchCount++;
    patch[s] = patchOfRoot[root];
  }
  return patch;
}

/// The largest distance between two of `points` (two farthest-point sweeps from `from`).
double estimateExtent(const std::vector<Vec3>& points, const std::vector<int>& members,
                      const Vec3& from) {
  const auto farthest = [&](const Vec3& q) {
    int best = members.front();
    for (const int m : members) {
      if ((points[m] - q).squaredNorm() > (points[best] - q).squaredNorm()) best = m;
    }
    return points[best];
  };
  const Vec3 a = farthest(from);
  return (farthest(a) - a).norm();
}

std::vector<CoverageVoid> describeVoids(const std::vector<Vec3>& points,
                                        const std::vector<double>& areas, double spacing,
                                        std::size_t maxVoids) {
  if (points.empty() || maxVoids == 0) return {};
  int patchCount = 0;
  // Cells of two sample spacings: samples closer than one spacing (neighbours on the surface)
  // always fall in the same or neighbouring cells.
  const std::vector<int> patch = clusterSamples(points, 2.0 * spacing, patchCount);
  std::vector<CoverageVoid> voids(patchCount);
  std::vector<std::vector<int>> members(patchCount);
  for (std::size_t s = 0; s < points.size(); ++s) {
    voids[patch[s]].area += areas[s];
    voids[patch[s]].centre += areas[s] * points[s];
    members[patch[s]].push_back(static_cast<int>(s));
  }
  std::vector<int> order(patchCount);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int x, int y) { return voids[x].area > voids[y].area; });
  order.resize(std::min<std::size_t>(order.size(), maxVoids));
  std::vector<CoverageVoid> largest;
  for (const int k : order) {
    CoverageVoid v = voids[k];
    v.centre /= v.area;
    v.size = estimateExtent(points, members[k], v.centre) + spacing;
    largest.push_back(v);
  }
  return largest;
}

/// The samples of a block of triangles: areas by cover, and the void samples.
struct SampleBlock {
  double area = 0.0, voidArea = 0.0, overlapArea = 0.0;
  std::vector<Vec3> voidPoints;
  std::vector<double> voidAreas;

  void add(const Vec3& p, double a, SampleCover cover) {
    area += a;
    if (cover == SampleCover::Overlap) overlapArea += a;
    if (cover != SampleCover::Void) return;
    voidArea += a;
    voidPoints.push_back(p);
    voidAreas.push_back(a);
  }
};

LayerCoverage combineBlocks(const std::vector<SampleBlock>& blocks, std::size_t arcStarts,
                            double beadSpacing, double spacing, std::size_t maxVoids) {
  LayerCoverage result;
  result.measured = true;
  result.beadWidth = beadSpacing;
  result.arcStarts = arcStarts;
  double voidArea = 0.0, overlapArea = 0.0;
  std::vector<Vec3> voidPoints;
  std::vector<double> voidAreas;
  for (const SampleBlock& b : blocks) {
    result.area += b.area;
    voidArea += b.voidArea;
    overlapArea += b.overlapArea;
    voidPoints.insert(voidPoints.end(), b.voidPoints.begin(), b.voidPoints.end());
    voidAreas.insert(voidAreas.end(), b.voidAreas.begin(), b.voidAreas.end());
  }
  if (result.area > 0.0) {
    result.voidShare = voidArea / result.area;
    result.overlapShare = overlapArea / result.area;
  }
  result.voids = describeVoids(voidPoints, voidAreas, spacing, maxVoids);
  return result;
}

}  // namespace

LayerCoverage computeLayerCoverage(const TriMesh& layerSurface, const std::vector<PlanPath>& paths,
                                   double beadSpacing, const CoverageOptions& options) {
  if (!std::isfinite(beadSpacing) || beadSpacing <= 0.0) {
    throw InvalidInput("bead spacing must be a positive number of mm: " +
                       formatNumber(beadSpacing) + "; pass a value such as 3.7");
  }
  if (options.threads < 0) {
    throw InvalidInput("coverage threads must be 0 or more: " + std::to_string(options.threads) +
                       "; pass 0 for OpenMP's default");
  }
  const double spacing = options.sampleSpacing < 0.0 ? 0.1 * beadSpacing : options.sampleSpacing;
  if (!std::isfinite(spacing) || spacing <= 0.0) {
    throw InvalidInput("coverage sample spacing must be a positive number of mm: " +
                       formatNumber(spacing) + "; pass a value such as 0.37, or < 0 for s/10");
  }
  std::vector<BeadPath> beadPaths;
  const std::vector<BeadSegment> segments = collectSegments(paths, beadSpacing, beadPaths);
  double widest = beadSpacing;
  for (const BeadSegment& g : segments) widest = std::max({widest, g.widthA, g.widthB});
  const SegmentCells cells(segments, 0.5 * widest);
  // A fixed partition of the triangles (independent of the thread count), blocks summed in
  // order: the result is the same on any number of threads.
  const std::size_t count = layerSurface.triangleCount();
  const std::size_t blockCount = std::min<std::size_t>(64, std::max<std::size_t>(count, 1));
  std::vector<SampleBlock> blocks(blockCount);
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (std::ptrdiff_t b = 0; b < static_cast<std::ptrdiff_t>(blockCount); ++b) {
    SampleClassifier classifier(segments, beadPaths, cells);
    const std::size_t begin = count * b / blockCount, end = count * (b + 1) / blockCount;
    for (std::size_t t = begin; t < end; ++t) {
      forEachSample(layerSurface, t, spacing, [&](const Vec3& p, double area) {
        blocks[b].add(p, area, classifier.classify(p));
      });
    }
  }
  return combineBlocks(blocks, paths.size(), beadSpacing, spacing, options.maxVoids);
}

PlanCoverageSummary summarizeCoverage(const Plan& plan, std::size_t worst) {
  PlanCoverageSummary s;
  double voidArea = 0.0, overlapArea = 0.0;
  std::vector<int> voided;
  for (const PlanLayer& layer : plan.layers) {
    s.arcStarts += layer.paths.size();
    const LayerCoverage& c = layer.coverage;
    if (!c.measured) continue;
    ++s.measuredLayers;
    s.area += c.area;
    voidArea += c.voidShare * c.area;
    overlapArea += c.overlapShare * c.area;
    if (c.voidShare > 0.0) voided.push_back(static_cast<int>(&layer - plan.layers.data()));
  }
  if (s.area > 0.0) {
    s.voidShare = voidArea / s.area;
    s.overlapShare = overlapArea / s.area;
  }
  std::stable_sort(voided.begin(), voided.end(), [&](int a, int b) {
    return plan.layers[a].coverage.voidShare > plan.layers[b].coverage.voidShare;
  });
  voided.resize(std::min(voided.size(), worst));
  s.worstLayers = std::move(voided);
  return s;
}

}  // namespace curvedslicer
