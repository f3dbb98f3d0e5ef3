// Tests of computeClearance (clearance.hpp): exact agreement with brute force on random grids
// (cells beyond the grid count as outside), the line-of-sight guarantee of the header, bad input,
// cancellation and run time on a model-sized grid.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "common/shapes.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/voxel/clearance.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace curvedslicer::testing {
namespace {

VoxelGrid makeRandomGrid(const Vec3i& dims, double insideProbability, unsigned seed) {
  VoxelGrid grid;
  grid.geometry.dims = dims;
  grid.inside.resize(grid.geometry.cellCount());
  std::mt19937 rng(seed);
  std::bernoulli_distribution inside(insideProbability);
  for (auto& cell : grid.inside) {
    cell = inside(rng) ? 1 : 0;
    grid.insideCount += cell;
  }
  return grid;
}

/// Squared distance (cells) from each cell to the nearest outside cell centre, including the
/// virtual outside cells around the grid, by exhaustive search.
std::vector<long> bruteForceSquared(const VoxelGrid& grid) {
  const GridGeometry& g = grid.geometry;
  std::vector<Vec3i> outside;
  for (int i = -1; i <= g.dims.x(); ++i) {
    for (int j = -1; j <= g.dims.y(); ++j) {
      for (int k = -1; k <= g.dims.z(); ++k) {
        if (!grid.isInside(i, j, k)) outside.emplace_back(i, j, k);
      }
    }
  }
  std::vector<long> result(g.cellCount());
  for (std::size_t n = 0; n < result.size(); ++n) {
    const Vec3i c = g.cell(n);
    long best = std::numeric_limits<long>::max();
    for (const Vec3i& o : outside) {
      const Vec3i d = c - o;
      best = std::min(best, static_cast<long>(d.squaredNorm()));
    }
    result[n] = best;
  }
  return result;
}

TEST(Clearance, MatchesBruteForceOnRandomGrids) {
  const std::vector<Vec3i> shapes = {Vec3i(1, 1, 1),   Vec3i(1, 1, 17), Vec3i(19, 1, 1),
                                     Vec3i(1, 13, 1),  Vec3i(7, 9, 5),  Vec3i(12, 10, 14),
                                     Vec3i(23, 6, 17), Vec3i(3, 31, 20)};
  unsigned seed = 1;
  for (const Vec3i& dims : shapes) {
    for (const double p : {0.0, 0.6, 0.97, 1.0}) {
      SCOPED_TRACE(::testing::Message() << "dims " << dims.transpose() << ", p " << p);
      const VoxelGrid grid = makeRandomGrid(dims, p, seed++);
      const std::vector<float> clearance = computeClearance(grid);
      const std::vector<long> expected = bruteForceSquared(grid);
      ASSERT_EQ(clearance.size(), expected.size());
      std::size_t mismatches = 0;
      for (std::size_t n = 0; n < expected.size(); ++n) {
        const float want = std::sqrt(static_cast<float>(expected[n]));
        if (std::abs(clearance[n] - want) > 1e-6f * std::max(1.0f, want)) ++mismatches;
        if (!grid.inside[n]) {
          EXPECT_EQ(clearance[n], 0.0f);
        }
      }
      EXPECT_EQ(mismatches, 0u);
    }
  }
}

TEST(Clearance, FullGridIsDistanceToItsBorder) {
  VoxelGrid grid;
  grid.geometry.dims = Vec3i(40, 25, 60);
  grid.inside.assign(grid.geometry.cellCount(), 1);
  const std::vector<float> clearance = computeClearance(grid);
  const Vec3i& n = grid.geometry.dims;
  for (int i = 0; i < n.x(); ++i) {
    for (int j = 0; j < n.y(); ++j) {
      for (int k = 0; k < n.z(); ++k) {
        const int border = std::min({i + 1, n.x() - i, j + 1, n.y() - j, k + 1, n.z() - k});
        ASSERT_EQ(clearance[grid.geometry.index(i, j, k)], static_cast<float>(border));
      }
    }
  }
}

TEST(Clearance, BallAroundACellWithinClearanceIsInside) {
  // clearance.hpp: |x − c| < clearance(c)·L − (√3/2)·L implies x lies in an inside cell.
  VoxelizeOptions options;
  options.voxelSize = 0.35;
  const VoxelizeResult voxels = voxelize(makeTorus(Vec3::Zero(), 10.0, 4.0, 96, 48), options);
  const VoxelGrid& grid = voxels.grid;
  const std::vector<float> clearance = computeClearance(grid);
  const GridGeometry& g = grid.geometry;
  std::vector<std::size_t> insideCells;
  for (std::size_t n = 0; n < grid.inside.size(); ++n) {
    if (grid.inside[n]) insideCells.push_back(n);
  }
  ASSERT_FALSE(insideCells.empty());
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, insideCells.size() - 1);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double L = g.voxelSize;
  int tested = 0;
  for (int sample = 0; sample < 200000; ++sample) {
    const std::size_t c = insideCells[pick(rng)];
    const double radius = (clearance[c] - std::sqrt(3.0) / 2.0) * L;
    if (radius <= 0.0) continue;
    const Vec3 direction = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Vec3 x = g.centerInPart(c) + direction * radius * (1.0 - 1e-9) * std::cbrt(unit(rng));
    ASSERT_TRUE(grid.isInside(g.cellOf(x))) << "cell " << g.cell(c).transpose();
    ++tested;
  }
  EXPECT_GT(tested, 100000);
  // Clearance of an outside cell is zero, of inside cells at least 1.
  for (std::size_t n = 0; n < grid.inside.size(); ++n) {
    ASSERT_EQ(clearance[n] >= 1.0f, grid.inside[n] != 0);
  }
}

TEST(Clearance, DeterministicAcrossThreadCounts) {
  const VoxelGrid grid = makeRandomGrid(Vec3i(37, 29, 41), 0.9, 11);
  const int threads = omp_get_max_threads();
  const std::vector<float> a = computeClearance(grid);
  omp_set_num_threads(1);
  const std::vector<float> b = computeClearance(grid);
  omp_set_num_threads(threads);
  EXPECT_EQ(a, b);
}

TEST(Clearance, RejectsAMaskOfTheWrongSize) {
  VoxelGrid grid;
  grid.geometry.dims = Vec3i(4, 5, 6);
  grid.inside.assign(100, 1);
  try {
    computeClearance(grid);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("100 values for 120 cells"), std::string::npos)
        << e.what();
  }
  VoxelGrid empty;
  EXPECT_TRUE(computeClearance(empty).empty());
}

TEST(Clearance, CancellationThrowsCancelled) {
  const VoxelGrid grid = makeRandomGrid(Vec3i(64, 64, 64), 0.95, 3);
  int calls = 0;
  EXPECT_THROW(computeClearance(grid, Progress([&](double, std::string_view stage) {
                                  EXPECT_EQ(stage, "clearance");
                                  return ++calls < 2;  // after the z pass
                                })),
               Cancelled);
  EXPECT_EQ(calls, 2);
}

TEST(Clearance, BunnyGridRunTime) {
  const TriMesh bunny = readMesh(modelPath("bunny_closed_low_res.stl"));
  VoxelizeOptions options;
  options.voxelSize = 0.5;
  const VoxelGrid grid = voxelize(bunny, options).grid;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<float> clearance = computeClearance(grid);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const float deepest = *std::max_element(clearance.begin(), clearance.end());
  EXPECT_GT(deepest, 10.0f);
  std::cout << "[ bunny    ] clearance of " << grid.geometry.cellCount() << " cells in " << seconds
            << " s = " << static_cast<double>(grid.geometry.cellCount()) / seconds / 1e6
            << " M cells/s; deepest " << deepest << " L\n";
}

}  // namespace
}  // namespace curvedslicer::testing
