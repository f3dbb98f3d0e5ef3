// Exact Euclidean distance transform of the outside cells (see clearance.hpp).
//
// Squared distances are computed by three separable 1D passes (Felzenszwalb & Huttenlocher 2012,
// "Distance Transforms of Sampled Functions", Theory of Computing 8):
//   z pass  distance along z to the nearest outside cell (two scans);
//   y pass  lower envelope of the parabolas f(j') + (j − j')² along every y line;
//   x pass  the same along every x line.
// The grid is surrounded by virtual outside cells: each 1D pass adds zero-height sites at
// positions −1 and n, which is exact because the nearest virtual cell of a cell always lies
// straight across the nearest grid face. Squared distances are integers, stored in the output
// floats between passes; they are exact while below 2^24 (clearance < 4096 L, far beyond any grid
// that fits in memory at this resolution) — larger intermediate values only belong to candidates
// that cannot win against a value below 2^24, so the final result stays exact.
//
// The y and x passes gather blocks of 64 neighbouring z lines (contiguous in the grid) within the
// bounding box of the slab's or row's inside cells into a buffer, transform them and scatter them
// back; each line is transformed run by run between its outside cells (a site beyond the nearest
// zero never wins). Each pass is parallel over slabs.
#include "curvedslicer/voxel/clearance.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "voxel/grid_memory.hpp"
#include "voxel/parallel_chunks.hpp"

namespace curvedslicer {
namespace {

using voxel_internal::chunksForCells;
using voxel_internal::runChunked;

constexpr int kBlock = 64;  ///< z lines transformed together in the y and x passes

/// Per-thread buffers of the lower-envelope transform.
struct EnvelopeBuffers {
  std::vector<double> line;      ///< n rows of kBlock values: line c is line[m·kBlock + c]
  std::vector<int> site;         ///< positions of the envelope's parabolas
  std::vector<double> height;    ///< their heights f(site)
  std::vector<double> boundary;  ///< left boundaries of the parabolas' intervals

  void reserve(int n) {
    line.resize(static_cast<std::size_t>(n) * kBlock);
    site.resize(static_cast<std::size_t>(n) + 2);
    height.resize(static_cast<std::size_t>(n) + 2);
    boundary.resize(static_cast<std::size_t>(n) + 3);
  }
};

/// In place: f(q) <- min over p in {−1, 0..n−1, n} of f(p) + (q − p)², with f(−1) = f(n) = 0;
/// f(q) is stored at f[q·stride].
void transformLine(double* f, int n, std::size_t stride, EnvelopeBuffers& b) {
  int* v = b.site.data();
  double* h = b.height.data();
  double* z = b.boundary.data();
  int k = 0;
  v[0] = -1;
  h[0] = 0.0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  for (int q = 0; q <= n; ++q) {
    const double hq = q < n ? f[q * stride] : 0.0;
    const double dq = static_cast<double>(q);
    double s = 0.0;
    for (;;) {
      const double dv = static_cast<double>(v[k]);
      s = ((hq + dq * dq) - (h[k] + dv * dv)) / (2.0 * (dq - dv));
      if (s > z[k]) break;
      --k;  // never below 0: z[0] = −∞
    }
    ++k;
    v[k] = q;
    h[k] = hq;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < static_cast<double>(q)) ++k;
    const double d = static_cast<double>(q - v[k]);
    f[q * stride] = d * d + h[k];
  }
}

/// transformLine on each run of non-zero values separately: a site beyond the nearest zero on
/// either side of q can never beat that zero, so every run is bounded by zero sites (or the
/// virtual outside cells), and runs of zeros stay zero.
void transformRuns(double* f, int n, std::size_t stride, EnvelopeBuffers& b) {
  int q = 0;
  while (q < n) {
    while (q < n && f[q * stride] == 0.0) ++q;
    const int start = q;
    while (q < n && f[q * stride] != 0.0) ++q;
    if (q > start) transformLine(f + start * stride, q - start, stride, b);
  }
}

void validateGrid(const VoxelGrid& grid) {
  const Vec3i& dims = grid.geometry.dims;
  if ((dims.array() < 0).any()) {
    throw InvalidInput("grid dimensions must not be negative: " + std::to_string(dims.x()) + " x " +
                       std::to_string(dims.y()) + " x " + std::to_string(dims.z()) +
                       "; pass a grid produced by voxelize");
  }
  if (grid.inside.size() != grid.geometry.cellCount()) {
    throw InvalidInput(
        "grid mask size does not match its dimensions: " + std::to_string(grid.inside.size()) +
        " values for " + std::to_string(grid.geometry.cellCount()) +
        " cells; pass a grid produced by voxelize");
  }
}

}  // namespace

std::vector<float> computeClearance(const VoxelGrid& grid, Progress progress) {
  validateGrid(grid);
  const GridGeometry& g = grid.geometry;
  const int nx = g.dims.x(), ny = g.dims.y(), nz = g.dims.z();
  std::vector<float> d;
  voxel_internal::assignZeroed(d, g.cellCount());
  if (d.empty()) return d;
  const std::size_t sx = g.strideX();
  const std::uint8_t* inside = grid.inside.data();
  float* out = d.data();
  const int chunks = chunksForCells(static_cast<double>(g.cellCount()));

  // Bounding box of the inside cells of every x slab (j and k) and, derived from those, a
  // bounding box of every y row (i and k): cells outside them are outside cells, which every pass
  // leaves at 0, so the y and x passes only visit the boxes.
  struct Box {
    int mLo = std::numeric_limits<int>::max(), mHi = -1;  // along the line
    int kLo = std::numeric_limits<int>::max(), kHi = -1;
    bool empty() const { return mHi < 0; }
  };
  std::vector<Box> slabBoxes(static_cast<std::size_t>(nx));

  // ---- clearance: z pass (distance along z to the nearest outside cell) -------------------------
  runChunked(nx, chunks, progress.sub(0.0, 0.3), "clearance", [&](int i, int) {
    Box& box = slabBoxes[i];
    for (int j = 0; j < ny; ++j) {
      const std::size_t base = static_cast<std::size_t>(i) * sx + static_cast<std::size_t>(j) * nz;
      for (int k = 0; k < nz;) {
        if (!inside[base + k]) {
          ++k;
          continue;
        }
        const int start = k;  // a run of inside cells [start, k), outside (or beyond) around it
        while (k < nz && inside[base + k]) ++k;
        for (int r = start; r < k; ++r) {
          const float along = static_cast<float>(std::min(r - start + 1, k - r));
          out[base + r] = along * along;
        }
        box.mLo = std::min(box.mLo, j);
        box.mHi = j;
        box.kLo = std::min(box.kLo, start);
        box.kHi = std::max(box.kHi, k - 1);
      }
    }
  });
  std::vector<Box> rowBoxes(static_cast<std::size_t>(ny));
  for (int i = 0; i < nx; ++i) {
    const Box& slab = slabBoxes[i];
    for (int j = slab.mLo; j <= slab.mHi; ++j) {
      Box& row = rowBoxes[j];
      row.mLo = std::min(row.mLo, i);
      row.mHi = i;
      row.kLo = std::min(row.kLo, slab.kLo);
      row.kHi = std::max(row.kHi, slab.kHi);
    }
  }

  const int threads = omp_get_max_threads();
  std::vector<EnvelopeBuffers> buffers(static_cast<std::size_t>(threads));
  for (EnvelopeBuffers& b : buffers) b.reserve(std::max(nx, ny));

  // Transforms the lines through (first + m·stride + k) for m and k in `box`, a block of k at a
  // time (rows of the block are contiguous in the grid); the last pass writes square roots.
  auto transformBlocks = [&](std::size_t first, std::size_t stride, const Box& box, bool takeRoot,
                             EnvelopeBuffers& b) {
    if (box.empty()) return;
    const int n = box.mHi - box.mLo + 1;
    first += static_cast<std::size_t>(box.mLo) * stride;
    for (int k0 = box.kLo; k0 <= box.kHi; k0 += kBlock) {
      const int width = std::min(kBlock, box.kHi + 1 - k0);
      double* rows = b.line.data();
      for (int m = 0; m < n; ++m) {
        const float* src = out + first + static_cast<std::size_t>(m) * stride + k0;
        double* row = rows + static_cast<std::size_t>(m) * kBlock;
        for (int c = 0; c < width; ++c) row[c] = src[c];
      }
      for (int c = 0; c < width; ++c) transformRuns(rows + c, n, kBlock, b);
      for (int m = 0; m < n; ++m) {
        float* dst = out + first + static_cast<std::size_t>(m) * stride + k0;
        const double* row = rows + static_cast<std::size_t>(m) * kBlock;
        for (int c = 0; c < width; ++c) {
          dst[c] = static_cast<float>(takeRoot ? std::sqrt(row[c]) : row[c]);
        }
      }
    }
  };

  // ---- clearance: y pass (per x slab) ----------------------------------------------------------
  runChunked(nx, chunks, progress.sub(0.3, 0.6), "clearance", [&](int i, int thread) {
    transformBlocks(static_cast<std::size_t>(i) * sx, static_cast<std::size_t>(nz), slabBoxes[i],
                    false, buffers[thread]);
  });

  // ---- clearance: x pass (per y row) and square root -------------------------------------------
  runChunked(ny, chunks, progress.sub(0.6, 1.0), "clearance", [&](int j, int thread) {
    transformBlocks(static_cast<std::size_t>(j) * nz, sx, rowBoxes[j], true, buffers[thread]);
  });
  return d;
}

}  // namespace curvedslicer
