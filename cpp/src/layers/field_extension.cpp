// Field extension beyond the solid (see layer_internal.hpp).
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "layers/layer_internal.hpp"

namespace curvedslicer::layers_detail {
namespace {

bool isReached(float d) {
  return d < kInfF;
}

enum class FitKind { Full, Partial, Nearest };

// The (2·kFitRadius + 1)³ box of offsets with their weights and moments, nearest first (so the
// first reached sample is a nearest one).
struct FitOffset {
  Vec3i offset;
  double w = 0.0, r2 = 0.0;
  Vec3 wo;                    // w·o
  std::array<double, 6> woo;  // w·o·oᵀ: xx, xy, xz, yy, yz, zz
};

const std::vector<FitOffset>& fitOffsets() {
  static const std::vector<FitOffset> offsets = [] {
    std::vector<FitOffset> list;
    const int r = kFitRadius;
    for (int a = -r; a <= r; ++a) {
      for (int b = -r; b <= r; ++b) {
        for (int c = -r; c <= r; ++c) {
          if (a == 0 && b == 0 && c == 0) continue;
          FitOffset f;
          f.offset = Vec3i(a, b, c);
          const Vec3 o(a, b, c);
          f.r2 = o.squaredNorm();
          f.w = 1.0 / f.r2;
          f.wo = f.w * o;
          f.woo = {f.w * a * a, f.w * a * b, f.w * a * c, f.w * b * b, f.w * b * c, f.w * c * c};
          list.push_back(f);
        }
      }
    }
    std::stable_sort(list.begin(), list.end(),
                     [](const FitOffset& x, const FitOffset& y) { return x.r2 < y.r2; });
    return list;
  }();
  return offsets;
}

// Weighted least-squares value at cell (i, j, k) from the reached cells around it. Offsets are in
// cells, values in mm.
double fitValue(const std::vector<float>& d, const GridGeometry& g, int i, int j, int k,
                FitKind& kind) {
  double W = 0.0, Sd = 0.0;
  Vec3 So = Vec3::Zero(), Sod = Vec3::Zero();
  std::array<double, 6> Soo{};
  bool haveNearest = false;
  double nearestValue = 0.0;
  const int r = kFitRadius;
  const bool interior =
      i >= r && j >= r && k >= r && i + r < g.dims.x() && j + r < g.dims.y() && k + r < g.dims.z();
  const auto sx = static_cast<std::ptrdiff_t>(g.strideX());
  const auto sy = static_cast<std::ptrdiff_t>(g.strideY());
  const auto centre = static_cast<std::ptrdiff_t>(g.index(i, j, k));
  for (const FitOffset& f : fitOffsets()) {
    const Vec3i& o = f.offset;
    if (!interior && !g.contains(i + o.x(), j + o.y(), k + o.z())) continue;
    const float value = d[static_cast<std::size_t>(centre + o.x() * sx + o.y() * sy + o.z())];
    if (!isReached(value)) continue;
    const double v = value;
    W += f.w;
    Sd += f.w * v;
    So += f.wo;
    Sod += v * f.wo;
    for (int q = 0; q < 6; ++q) Soo[q] += f.woo[q];
    if (!haveNearest) {
      haveNearest = true;
      nearestValue = v;
    }
  }
  // W > 0: the caller only asks for cells within kExtensionBand <= kFitRadius of a reached cell.
  const Vec3 mean = So / W;
  const double dMean = Sd / W;
  Mat3 C;
  C << Soo[0], Soo[1], Soo[2], Soo[1], Soo[3], Soo[4], Soo[2], Soo[4], Soo[5];
  C = C / W - mean * mean.transpose();
  const Vec3 b = Sod / W - mean * dMean;
  Eigen::SelfAdjointEigenSolver<Mat3> eigen;
  eigen.computeDirect(C);
  Vec3 gradient = Vec3::Zero();
  int rank = 0;
  for (int e = 0; e < 3; ++e) {
    const double lambda = eigen.eigenvalues()[e];
    if (lambda < kMinVariance) continue;
    const Vec3 u = eigen.eigenvectors().col(e);
    gradient += (u.dot(b) / lambda) * u;
    ++rank;
  }
  if (rank == 0) {
    kind = FitKind::Nearest;
    return nearestValue;
  }
  kind = rank == 3 ? FitKind::Full : FitKind::Partial;
  return dMean - gradient.dot(mean);  // value at offset 0
}

}  // namespace

std::vector<std::size_t> extendFieldInPlace(std::vector<float>& values, const VoxelGrid& grid,
                                            FieldExtensionStats& stats, const Progress& progress) {
  const GridGeometry& g = grid.geometry;
  const std::vector<float>& d = values;  // read-only until the final write-back
  const int nx = g.dims.x(), ny = g.dims.y(), nz = g.dims.z();
  std::array<std::ptrdiff_t, 26> linearOffsets{};
  for (std::size_t q = 0; q < 26; ++q) {
    const Vec3i& o = neighbourOffsets26()[q];
    linearOffsets[q] = o.x() * static_cast<std::ptrdiff_t>(g.strideX()) +
                       o.y() * static_cast<std::ptrdiff_t>(g.strideY()) + o.z();
  }
  // One bit per cell: the cell gets an extended value.
  std::vector<std::uint64_t> marks((g.cellCount() + 63) / 64, 0);
  auto isMarked = [&](std::size_t n) { return ((marks[n >> 6] >> (n & 63)) & 1u) != 0; };

  // ---- extending field: mark ----
  // Every outside, unreached cell within Chebyshev distance kExtensionBand of a reached cell is
  // within that distance of a reached cell that has an unreached 26-neighbour (step from any
  // reached cell towards the target until that holds), so only such boundary cells spread marks.
  runChunked(static_cast<std::size_t>(nx), progress.sub(0.0, 0.3), "extending field",
             [&](std::size_t plane) {
               const int i = static_cast<int>(plane);
               for (int j = 0; j < ny; ++j) {
                 for (int k = 0; k < nz; ++k) {
                   const std::size_t n = g.index(i, j, k);
                   if (!isReached(d[n])) continue;
                   bool boundary = false;
                   const bool interior =
                       i > 0 && j > 0 && k > 0 && i < nx - 1 && j < ny - 1 && k < nz - 1;
                   for (std::size_t q = 0; q < 26 && !boundary; ++q) {
                     if (interior) {
                       boundary = !isReached(d[n + linearOffsets[q]]);
                     } else {
                       const Vec3i c = Vec3i(i, j, k) + neighbourOffsets26()[q];
                       boundary = g.contains(c) && !isReached(d[g.index(c)]);
                     }
                   }
                   if (!boundary) continue;
                   const int e = kExtensionBand;
                   for (int a = std::max(0, i - e); a <= std::min(nx - 1, i + e); ++a) {
                     for (int b = std::max(0, j - e); b <= std::min(ny - 1, j + e); ++b) {
                       for (int c = std::max(0, k - e); c <= std::min(nz - 1, k + e); ++c) {
                         const std::size_t m = g.index(a, b, c);
                         if (isReached(d[m]) || grid.inside[m] != 0) continue;
                         std::atomic_ref<std::uint64_t>(marks[m >> 6])
                             .fetch_or(std::uint64_t{1} << (m & 63), std::memory_order_relaxed);
                       }
                     }
                   }
                 }
               }
             });

  // ---- extending field: fit ----
  struct PlaneFits {
    std::vector<std::size_t> cells;
    std::vector<float> values;
    std::size_t partial = 0, nearest = 0;
  };
  std::vector<PlaneFits> fits(static_cast<std::size_t>(nx));
  runChunked(static_cast<std::size_t>(nx), progress.sub(0.3, 1.0), "extending field",
             [&](std::size_t plane) {
               const int i = static_cast<int>(plane);
               PlaneFits& out = fits[plane];
               for (int j = 0; j < ny; ++j) {
                 for (int k = 0; k < nz; ++k) {
                   const std::size_t n = g.index(i, j, k);
                   if (!isMarked(n)) continue;
                   FitKind kind = FitKind::Full;
                   out.cells.push_back(n);
                   out.values.push_back(static_cast<float>(fitValue(d, g, i, j, k, kind)));
                   if (kind == FitKind::Partial) ++out.partial;
                   if (kind == FitKind::Nearest) ++out.nearest;
                 }
               }
             });
  std::vector<std::uint64_t>().swap(marks);
  std::size_t total = 0;
  for (const PlaneFits& f : fits) total += f.cells.size();
  std::vector<std::size_t> extended;
  extended.reserve(total);
  for (PlaneFits& f : fits) {
    for (std::size_t q = 0; q < f.cells.size(); ++q) values[f.cells[q]] = f.values[q];
    extended.insert(extended.end(), f.cells.begin(), f.cells.end());
    stats.extendedCells += f.cells.size();
    stats.partialFits += f.partial;
    stats.nearestFallbacks += f.nearest;
    f = PlaneFits{};
  }
  return extended;
}

std::vector<float> extendField(const DistanceField& field, const VoxelGrid& grid,
                               FieldExtensionStats& stats, const Progress& progress) {
  std::vector<float> values = field.distance;
  (void)extendFieldInPlace(values, grid, stats, progress);
  return values;
}

}  // namespace curvedslicer::layers_detail
