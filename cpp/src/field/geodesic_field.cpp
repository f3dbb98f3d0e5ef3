// Entry point of the geodesic volume field (GDTS): seeds, method dispatch, unreached report.
#include "curvedslicer/field/geodesic_field.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <sstream>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "field_internal.hpp"

namespace curvedslicer {

std::string_view toString(GeodesicMethod method) {
  switch (method) {
    case GeodesicMethod::AnyAngle:
      return "anyangle";
    case GeodesicMethod::Paper:
      return "paper";
  }
  return "unknown";
}

GeodesicMethod parseGeodesicMethod(std::string_view name) {
  std::string s(name);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  if (s == "anyangle" || s == "any-angle" || s == "exact" || s == "default")
    return GeodesicMethod::AnyAngle;
  if (s == "paper") return GeodesicMethod::Paper;
  throw InvalidInput("unknown geodesic method: '" + std::string(name) +
                     "'; choose 'anyangle' (accurate default, also 'exact') or 'paper'");
}

namespace detail {

std::vector<Triangle> toCellCoordinates(const GridGeometry& g, const TriMesh& source) {
  std::vector<Triangle> out;
  out.reserve(source.triangles.size());
  for (std::size_t t = 0; t < source.triangles.size(); ++t) {
    Triangle tri;
    for (int k = 0; k < 3; ++k)
      tri[k] = (g.frame.toFrame(source.corner(t, k)) - g.corner) / g.voxelSize;
    if ((tri[1] - tri[0]).cross(tri[2] - tri[0]).squaredNorm() <= 0.0) continue;
    out.push_back(tri);
  }
  return out;
}

std::vector<std::uint32_t> placeSeeds(const VoxelGrid& grid, const std::vector<Triangle>& source,
                                      double band, std::vector<float>& dist,
                                      std::vector<std::int32_t>* parent, const TriMesh& sourceMm) {
  const GridGeometry& g = grid.geometry;
  for (std::size_t t = 0; t < source.size(); ++t) {
    const Triangle& tri = source[t];
    const Vec3 lo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]).array() - band;
    const Vec3 hi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]).array() + band;
    // Cells whose centre c+½ lies in [lo, hi].
    const Vec3i c0 = (lo.array() - 0.5).ceil().cast<int>().max(0);
    const Vec3i c1 = (hi.array() - 0.5).floor().cast<int>().min(g.dims.array() - 1);
    if ((c0.array() > c1.array()).any()) continue;
    const Vec3 n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalized();
    const double offset = n.dot(tri[0]);
    for (int i = c0.x(); i <= c1.x(); ++i)
      for (int j = c0.y(); j <= c1.y(); ++j) {
        const std::size_t base = g.index(i, j, 0);
        for (int k = c0.z(); k <= c1.z(); ++k) {
          const std::size_t idx = base + k;
          if (!grid.inside[idx]) continue;
          const Vec3 x = cellCentre(Vec3i(i, j, k));
          if (std::abs(n.dot(x) - offset) > band) continue;
          const double d = pointTriangleDistance(x, tri[0], tri[1], tri[2]);
          if (d <= band && d < dist[idx]) {
            dist[idx] = static_cast<float>(d);
            if (parent) (*parent)[idx] = triangleParent(t);
          }
        }
      }
  }
  std::vector<std::uint32_t> seeds;
  for (std::size_t idx = 0; idx < dist.size(); ++idx)
    if (dist[idx] < kInfF) seeds.push_back(static_cast<std::uint32_t>(idx));
  if (seeds.empty()) {
    // Say how far apart they are: the gap between the surface's box and the solid's inside cells.
    Aabb solid;
    for (std::size_t idx = 0; idx < grid.inside.size(); ++idx)
      if (grid.inside[idx]) solid.extend(g.centerInPart(idx));
    const Aabb surf = sourceMm.bounds();
    const Vec3 gap = (surf.min - solid.max).cwiseMax(solid.min - surf.max).cwiseMax(0.0);
    std::ostringstream msg;
    msg.precision(4);
    msg << "the start surface does not touch the solid: no inside voxel centre lies within "
        << band * g.voxelSize << " mm of it";
    if (gap.norm() > 0) msg << " (their bounding boxes are " << gap.norm() << " mm apart)";
    msg << "; move the start surface onto the part (check units and position) or pick faces of "
           "the model";
    throw InvalidInput(msg.str());
  }
  return seeds;
}

namespace {

UnreachedVoxels reportUnreached(const VoxelGrid& grid, const std::vector<float>& dist) {
  UnreachedVoxels out;
  const GridGeometry& g = grid.geometry;
  std::vector<std::uint8_t> seen(grid.inside.size(), 0);
  std::vector<std::size_t> stack;
  const auto& offsets = neighbourOffsets26();
  for (std::size_t idx = 0; idx < grid.inside.size(); ++idx) {
    if (!grid.inside[idx] || dist[idx] < kInfF || seen[idx]) continue;
    if (out.count == 0) out.example = g.centerInPart(idx);
    ++out.components;
    seen[idx] = 1;
    stack.push_back(idx);
    while (!stack.empty()) {
      const std::size_t n = stack.back();
      stack.pop_back();
      ++out.count;
      out.bounds.extend(g.centerInPart(n));
      const Vec3i c = g.cell(n);
      for (const Vec3i& o : offsets) {
        const Vec3i m = c + o;
        if (!g.contains(m)) continue;
        const std::size_t mi = g.index(m);
        if (grid.inside[mi] && dist[mi] == kInfF && !seen[mi]) {
          seen[mi] = 1;
          stack.push_back(mi);
        }
      }
    }
  }
  return out;
}

}  // namespace
}  // namespace detail

namespace {

GeodesicResult computeField(const VoxelGrid& grid, const TriMesh* model, const TriMesh& source,
                            const GeodesicOptions& options, Progress progress) {
  const GridGeometry& g = grid.geometry;
  if (g.cellCount() == 0 || grid.inside.size() != g.cellCount()) {
    throw InvalidInput("the voxel grid is empty or inconsistent; voxelize the model first");
  }
  if (g.cellCount() >= static_cast<std::size_t>(INT32_MAX)) {
    throw ResourceLimit("the grid has " + std::to_string(g.cellCount()) +
                        " cells, more than the geodesic field supports (2^31); use a larger "
                        "voxel size");
  }
  for (int a = 0; a < 3; ++a) {
    for (int side = 0; side < 2; ++side) {
      const int fixed = side ? g.dims[a] - 1 : 0;
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      for (int u = 0; u < g.dims[b]; ++u)
        for (int v = 0; v < g.dims[c]; ++v) {
          Vec3i cell;
          cell[a] = fixed;
          cell[b] = u;
          cell[c] = v;
          if (grid.inside[g.index(cell)]) {
            throw InvalidInput(
                "the voxel grid has inside cells on its border; voxelize with a "
                "padding of at least 1 cell");
          }
        }
    }
  }
  const double L = g.voxelSize;
  const double band = options.seedBand > 0 ? options.seedBand / L : std::sqrt(3.0);
  if (!std::isfinite(band)) {
    throw InvalidInput("seed band must be finite: " + std::to_string(options.seedBand) + " mm");
  }

  GeodesicResult result;
  result.method = options.method;
  const std::vector<detail::Triangle> tris = detail::toCellCoordinates(g, source);
  if (tris.empty()) {
    throw InvalidInput("the start surface has no triangle with non-zero area; give a real surface");
  }

  detail::MethodStats stats;
  std::vector<float> dist;
  if (options.method == GeodesicMethod::AnyAngle) {
    // The clearance first: its float transform is freed before the parent array exists, which
    // keeps the peak at 11 bytes per grid cell (see docs/METHODS.md).
    progress.report(0.0, "geodesic field: clearance");
    std::vector<std::uint8_t> clearance =
        detail::computeClearanceCells(grid, progress.sub(0.0, 0.08));
    dist.assign(g.cellCount(), kInfF);
    std::vector<std::int32_t> parent(g.cellCount(), detail::kNoParent);
    progress.report(0.08, "geodesic field: seeds");
    const auto seeds = detail::placeSeeds(grid, tris, band, dist, &parent, source);
    result.seedCount = seeds.size();
    stats = detail::propagateAnyAngle(grid, model, tris, seeds, band, std::move(clearance), dist,
                                      parent, progress.sub(0.1, 1.0));
  } else {
    dist.assign(g.cellCount(), kInfF);
    progress.report(0.0, "geodesic field: seeds");
    const double radius =
        options.paperSearchRadius > 0 ? options.paperSearchRadius : 2.0 * std::sqrt(3.0);
    if (!std::isfinite(radius) || radius < std::sqrt(3.0)) {
      throw InvalidInput("paper search radius must be at least sqrt(3) voxels: " +
                         std::to_string(radius) + "; use the default 2*sqrt(3)");
    }
    const auto seeds = detail::placeSeeds(grid, tris, band, dist, nullptr, source);
    result.seedCount = seeds.size();
    stats = detail::propagatePaper(grid, seeds, radius, dist, progress.sub(0.02, 1.0));
  }
  result.lineOfSightTests = stats.lineOfSightTests;
  result.lineOfSightFailures = stats.lineOfSightFailures;
  result.paperOuterIterations = stats.outerIterations;
  result.paperCorrectionRounds = stats.correctionRounds;
  result.edgePivots = stats.edgePivots;

  result.unreached = detail::reportUnreached(grid, dist);
  double maxD = 0.0;
  std::size_t reached = 0;
  for (std::size_t idx = 0; idx < dist.size(); ++idx) {
    if (dist[idx] < kInfF) {
      dist[idx] = static_cast<float>(dist[idx] * L);
      maxD = std::max(maxD, static_cast<double>(dist[idx]));
      ++reached;
    }
  }
  result.reachedCount = reached;
  result.maxDistance = maxD;
  result.field.geometry = g;
  result.field.distance = std::move(dist);
  progress.report(1.0, "geodesic field");
  return result;
}

}  // namespace

GeodesicResult computeGeodesicField(const VoxelGrid& grid, const TriMesh& source,
                                    const GeodesicOptions& options, Progress progress) {
  return computeField(grid, nullptr, source, options, progress);
}

GeodesicResult computeGeodesicField(const VoxelGrid& grid, const TriMesh& model,
                                    const TriMesh& source, const GeodesicOptions& options,
                                    Progress progress) {
  if (model.triangles.empty()) {
    throw InvalidInput("the model surface has no triangles; pass the solid's mesh");
  }
  return computeField(grid, &model, source, options, progress);
}

}  // namespace curvedslicer
