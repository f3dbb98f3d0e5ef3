// Tests of planGrid and voxelize (voxelize.hpp): analytic volumes, exact results when rays pass
// through vertices and edges, watertightness on the bundled models, holes, flipped and duplicated
// triangles, bad input, memory budget, cancellation, determinism and throughput.
#include <gtest/gtest.h>

#include <omp.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/shapes.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace curvedslicer::testing {
namespace {

TriMesh loadModel(const std::string& name) {
  return cleanMesh(readMesh(modelPath(name))).mesh;
}

VoxelizeOptions modelAligned(double voxelSize) {
  VoxelizeOptions options;
  options.voxelSize = voxelSize;
  options.alignment = GridAlignment::Model;
  return options;
}

/// Expects the inside cells to be exactly those whose grid-frame centre satisfies `expected`.
template <class Predicate>
void expectInsideSet(const VoxelGrid& grid, Predicate expected) {
  const GridGeometry& g = grid.geometry;
  std::size_t mismatches = 0, expectedCount = 0;
  for (int i = 0; i < g.dims.x(); ++i) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int k = 0; k < g.dims.z(); ++k) {
        const Vec3 c = g.centerInGrid(Vec3i(i, j, k));
        const bool want = expected(c);
        expectedCount += want ? 1 : 0;
        if (want != grid.isInside(i, j, k)) {
          if (++mismatches <= 5) {
            ADD_FAILURE() << "cell centre (" << c.transpose() << ") should be "
                          << (want ? "inside" : "outside");
          }
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(grid.insideCount, expectedCount);
}

TEST(Voxelize, SphereVolumeWithinHalfPercent) {
  const double R = 10.0;
  VoxelizeOptions options;
  options.voxelSize = 2.0 * R / 128.0;
  const TriMesh sphere = makeSphere(Vec3(3.0, -2.0, 1.0), R, 6);
  const VoxelizeResult result = voxelize(sphere, options);
  const double analytic = 4.0 / 3.0 * std::numbers::pi * R * R * R;
  EXPECT_NEAR(result.grid.insideVolume() / analytic, 1.0, 0.005);
  EXPECT_NEAR(result.grid.insideVolume() / signedVolume(sphere), 1.0, 0.002);
  EXPECT_EQ(result.stats.oddColumns, 0u);
  EXPECT_EQ(result.stats.columns, static_cast<std::size_t>(result.grid.geometry.dims.x()) *
                                      result.grid.geometry.dims.y());
}

TEST(Voxelize, TorusVolumeWithinHalfPercent) {
  const double R = 10.0, r = 4.0;
  VoxelizeOptions options;
  options.voxelSize = 2.0 * (R + r) / 128.0;
  const TriMesh torus = makeTorus(Vec3(0.0, 0.0, 5.0), R, r, 256, 128);
  const VoxelizeResult result = voxelize(torus, options);
  const double analytic = 2.0 * std::numbers::pi * std::numbers::pi * R * r * r;
  EXPECT_NEAR(result.grid.insideVolume() / analytic, 1.0, 0.005);
  EXPECT_EQ(result.stats.oddColumns, 0u);
  // The hole of the torus is outside.
  const GridGeometry& g = result.grid.geometry;
  EXPECT_FALSE(result.grid.isInside(g.cellOf(Vec3(0.0, 0.0, 5.0))));
  EXPECT_TRUE(result.grid.isInside(g.cellOf(Vec3(R, 0.0, 5.0))));
}

TEST(Voxelize, SphericalShellCavityIsOutside) {
  const double r1 = 6.0, r2 = 10.0;
  VoxelizeOptions options;
  options.voxelSize = 2.0 * r2 / 128.0;
  const TriMesh shell = makeSphericalShell(Vec3::Zero(), r1, r2, 5);
  const VoxelizeResult result = voxelize(shell, options);
  EXPECT_NEAR(result.grid.insideVolume() / signedVolume(shell), 1.0, 0.005);
  EXPECT_FALSE(result.grid.isInside(result.grid.geometry.cellOf(Vec3::Zero())));
}

TEST(Voxelize, BoxOnVoxelCentreColumnsIsExact) {
  // Every vertex (x, y) lies on a voxel-centre column (centres at (m + ½)·L in model axes), so
  // z rays pass exactly through vertices and along the diagonals of the subdivided faces.
  for (const double L : {1.0, 0.25}) {
    SCOPED_TRACE("L = " + std::to_string(L));
    const Vec3 lo = Vec3(0.5, 1.5, 0.5) * L, hi = Vec3(8.5, 5.5, 4.5) * L;
    const VoxelizeResult result = voxelize(makeSubdividedBox(lo, hi, 4), modelAligned(L));
    EXPECT_EQ(result.stats.oddColumns, 0u);
    // Ray point perturbed to (x + ε, y + ε²); centres on the z faces count from the bottom face
    // up to, but excluding, the top face.
    expectInsideSet(result.grid, [&](const Vec3& c) {
      return (c.array() >= lo.array()).all() && (c.array() < hi.array()).all();
    });
    EXPECT_EQ(result.grid.insideCount, 8u * 4u * 4u);
  }
}

TEST(Voxelize, DiamondPrismOnVoxelCentreColumnsIsExact) {
  // Square rotated by 45° with corners (and a fan centre) on voxel-centre columns: every edge of
  // the caps runs through columns.
  TriMesh prism;
  const std::vector<Vec3> ring = {Vec3(3.5, 0.5, 0), Vec3(6.5, 3.5, 0), Vec3(3.5, 6.5, 0),
                                  Vec3(0.5, 3.5, 0)};
  const double z0 = 0.25, z1 = 2.75;
  for (const double z : {z0, z1}) {
    for (const Vec3& p : ring) prism.vertices.push_back(Vec3(p.x(), p.y(), z));
    prism.vertices.push_back(Vec3(3.5, 3.5, z));
  }
  for (int s = 0; s < 4; ++s) {
    const int a = s, b = (s + 1) % 4;
    prism.triangles.emplace_back(4, b, a);          // bottom fan, facing down
    prism.triangles.emplace_back(9, 5 + a, 5 + b);  // top fan, facing up
    prism.triangles.emplace_back(a, b, 5 + b);      // sides
    prism.triangles.emplace_back(a, 5 + b, 5 + a);
  }
  ASSERT_GT(signedVolume(prism), 0.0);
  const VoxelizeResult result = voxelize(prism, modelAligned(1.0));
  EXPECT_EQ(result.stats.oddColumns, 0u);
  // The perturbed point (x + ε, y + ε²) against the four edge lines y − x = ±3, x + y = 4, 10.
  expectInsideSet(result.grid, [&](const Vec3& c) {
    const double d = c.y() - c.x(), s = c.x() + c.y();
    return d > -3.0 && d <= 3.0 && s >= 4.0 && s < 10.0 && c.z() > z0 && c.z() < z1;
  });
  EXPECT_EQ(result.grid.insideCount, 18u * 3u);  // the square's area, on 3 layers
}

TEST(Voxelize, RotatedBoxWithPcaGridIsExact) {
  // In the PCA frame (origin at the centroid) the box faces lie on cell faces, so every centre
  // is clearly inside or outside.
  const Vec3 lo(0, 0, 0), hi(30, 20, 10);
  const Mat3 R = Eigen::AngleAxisd(0.9, Vec3(-1.0, 0.5, 2.0).normalized()).toRotationMatrix();
  const TriMesh box = rotated(makeSubdividedBox(lo, hi, 3), R, Vec3(4, 5, 6));
  VoxelizeOptions options;
  options.voxelSize = 1.0;
  const VoxelizeResult result = voxelize(box, options);
  EXPECT_EQ(result.grid.insideCount, 6000u);
  // Faces on cell faces up to round-off: at most one spare cell on each side.
  const Vec3i dims = result.grid.geometry.dims;
  EXPECT_TRUE((dims.array() >= Vec3i(34, 24, 14).array()).all()) << dims.transpose();
  EXPECT_TRUE((dims.array() <= Vec3i(36, 26, 16).array()).all()) << dims.transpose();
  EXPECT_EQ(result.stats.oddColumns, 0u);
}

TEST(Voxelize, PlanGridCoversTheModelWithPadding) {
  const TriMesh bunny = loadModel("bunny_closed_low_res.stl");
  for (const GridAlignment alignment : {GridAlignment::Pca, GridAlignment::Model}) {
    VoxelizeOptions options;
    options.voxelSize = 1.7;
    options.padding = 3;
    options.alignment = alignment;
    const GridGeometry g = planGrid(bunny, options);
    if (alignment == GridAlignment::Model) {
      EXPECT_EQ(g.frame.rotation, Mat3::Identity());
      EXPECT_EQ(g.frame.origin, Vec3::Zero());
    }
    Aabb box;
    for (const Vec3& p : bunny.vertices) box.extend(g.frame.toFrame(p));
    const Vec3 innerLo = g.corner + Vec3::Constant(options.padding * options.voxelSize);
    const Vec3 innerHi =
        g.corner + (g.dims.cast<double>().array() - options.padding).matrix() * options.voxelSize;
    EXPECT_TRUE((box.min.array() >= innerLo.array()).all());
    EXPECT_TRUE((box.max.array() <= innerHi.array()).all());
    // At most one spare cell per axis beyond ceil(extent / L) + 2·padding.
    for (int a = 0; a < 3; ++a) {
      const int minimal =
          static_cast<int>(std::ceil(box.size()[a] / options.voxelSize)) + 2 * options.padding;
      EXPECT_GE(g.dims[a], minimal);
      EXPECT_LE(g.dims[a], minimal + 1);
    }
  }
}

TEST(Voxelize, BundledModelsHaveNoOddColumns) {
  std::size_t models = 0;
  for (const auto& entry : std::filesystem::directory_iterator(modelPath(""))) {
    if (entry.path().extension() != ".stl") continue;
    SCOPED_TRACE(entry.path().filename().string());
    ++models;
    const TriMesh raw = readMesh(entry.path());
    const TriMesh mesh = cleanMesh(raw).mesh;
    VoxelizeOptions options;
    options.voxelSize = mesh.bounds().size().maxCoeff() / 128.0;
    const VoxelizeResult result = voxelize(mesh, options);
    EXPECT_EQ(result.stats.oddColumns, 0u);
    // Flat faces parallel to a grid plane quantize by up to L/2 each (the thin overhang coin
    // shows ±4 % at 128 cells), hence a tolerance of half a voxel layer over the whole surface.
    const double tolerance = 0.5 * surfaceArea(mesh) * options.voxelSize / signedVolume(mesh);
    EXPECT_NEAR(result.grid.insideVolume() / signedVolume(mesh), 1.0, tolerance);
    // The raw triangle soup (unwelded STL) gives the same cells.
    const VoxelizeResult soup = voxelize(raw, options);
    EXPECT_EQ(soup.grid.inside, result.grid.inside);
  }
  EXPECT_GE(models, 6u);
}

TEST(Voxelize, HolesAreResolvedByCrossRays) {
  const TriMesh bunny = loadModel("bunny_closed_low_res.stl");
  const TriMesh holed = deleteTriangles(bunny, 0.02);
  ASSERT_LT(holed.triangleCount(), bunny.triangleCount());
  for (const GridAlignment alignment : {GridAlignment::Pca, GridAlignment::Model}) {
    VoxelizeOptions options;
    options.voxelSize = 1.0;
    options.alignment = alignment;
    const VoxelizeResult intact = voxelize(bunny, options);
    const VoxelizeResult broken = voxelize(holed, options);
    EXPECT_EQ(intact.stats.oddColumns, 0u);
    EXPECT_GT(broken.stats.oddColumns, 0u);
    EXPECT_GT(broken.stats.resolvedVoxels, 0u);
    EXPECT_LT(broken.stats.unresolvedVoxels, broken.stats.resolvedVoxels / 50);
    EXPECT_NEAR(broken.grid.insideVolume() / intact.grid.insideVolume(), 1.0, 0.02);
    if (alignment == GridAlignment::Model) {
      // Same grid (the PCA frame moves when triangles go missing): compare cell by cell.
      ASSERT_EQ(intact.grid.geometry.dims, broken.grid.geometry.dims);
      std::size_t differ = 0;
      for (std::size_t n = 0; n < intact.grid.inside.size(); ++n) {
        differ += intact.grid.inside[n] != broken.grid.inside[n] ? 1 : 0;
      }
      EXPECT_LT(static_cast<double>(differ), 0.005 * static_cast<double>(intact.grid.insideCount));
      std::cout << "[ holes    ] odd columns " << broken.stats.oddColumns << ", resolved voxels "
                << broken.stats.resolvedVoxels << ", unresolved " << broken.stats.unresolvedVoxels
                << ", cells differing from the intact model " << differ << " of "
                << intact.grid.insideCount << " inside\n";
    }
  }
}

TEST(Voxelize, FlippedAndDuplicatedTrianglesDoNotChangeTheResult) {
  const TriMesh bunny = loadModel("bunny_closed_low_res.stl");
  TriMesh messy = bunny;
  for (std::size_t t = 0; t < messy.triangles.size(); t += 7) {
    std::swap(messy.triangles[t][1], messy.triangles[t][2]);
  }
  for (std::size_t t = 0; t < bunny.triangles.size(); t += 5) {
    Vec3i copy = bunny.triangles[t];
    if (t % 2 == 0) copy = Vec3i(copy[2], copy[1], copy[0]);  // some copies flipped as well
    messy.triangles.push_back(copy);
    if (t % 3 == 0) messy.triangles.push_back(bunny.triangles[t]);  // and some triplicated
  }
  messy.faceIds.clear();
  VoxelizeOptions options;
  options.voxelSize = 1.5;
  const VoxelizeResult clean = voxelize(bunny, options);
  const VoxelizeResult result = voxelize(messy, options);
  EXPECT_EQ(result.stats.oddColumns, 0u);
  EXPECT_EQ(result.grid.insideCount, clean.grid.insideCount);
  EXPECT_EQ(result.grid.inside, clean.grid.inside);
}

TEST(Voxelize, IgnoresUnusedVertices) {
  const TriMesh box = makeBox(Vec3(0.5, 0.5, 0.5), Vec3(4.5, 3.5, 2.5));
  TriMesh extra = box;
  extra.vertices.push_back(Vec3(1e300, -1e300, 0.0));
  extra.vertices.push_back(Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (const GridAlignment alignment : {GridAlignment::Pca, GridAlignment::Model}) {
    VoxelizeOptions options = modelAligned(0.5);
    options.alignment = alignment;
    const VoxelizeResult a = voxelize(box, options);
    const VoxelizeResult b = voxelize(extra, options);
    EXPECT_EQ(a.grid.geometry.dims, b.grid.geometry.dims);
    EXPECT_EQ(a.grid.inside, b.grid.inside);
    EXPECT_EQ(b.grid.insideCount, 8u * 6u * 4u);
  }
}

TEST(Voxelize, RejectsBadParameters) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10));
  auto expectInvalid = [&](const TriMesh& mesh, const VoxelizeOptions& options,
                           const std::string& fragment) {
    try {
      voxelize(mesh, options);
      ADD_FAILURE() << "expected InvalidInput containing '" << fragment << "'";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  VoxelizeOptions options;
  options.voxelSize = 0.0;
  expectInvalid(box, options, "voxel size must be a positive, finite length: 0 mm");
  options.voxelSize = -1.5;
  expectInvalid(box, options, "-1.5 mm");
  options.voxelSize = std::numeric_limits<double>::quiet_NaN();
  expectInvalid(box, options, "nan mm");
  options.voxelSize = std::numeric_limits<double>::infinity();
  expectInvalid(box, options, "inf mm");
  options.voxelSize = 1.0;
  options.padding = 0;
  expectInvalid(box, options, "padding");
  options.padding = 2;
  options.bytesPerCell = 0.0;
  expectInvalid(box, options, "bytes per cell");
  options.bytesPerCell = 16.0;
  options.memoryBudgetBytes = -1.0;
  expectInvalid(box, options, "memory budget");
  options.memoryBudgetBytes = 0.0;

  expectInvalid(TriMesh{}, options, "empty mesh");
  TriMesh nan = box;
  nan.vertices[5].z() = std::numeric_limits<double>::quiet_NaN();
  expectInvalid(nan, options, "non-finite coordinate");
  TriMesh badIndex = box;
  badIndex.triangles[0][0] = -1;
  expectInvalid(badIndex, options, "vertex index -1");
  EXPECT_THROW(planGrid(nan, options), InvalidInput);
}

TEST(Voxelize, MemoryBudgetSuggestsAVoxelSizeThatFits) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(100, 80, 60));
  VoxelizeOptions options;
  options.voxelSize = 0.25;
  options.alignment = GridAlignment::Model;
  options.memoryBudgetBytes = 2e8;
  std::string message;
  try {
    planGrid(box, options);
    FAIL() << "expected ResourceLimit";
  } catch (const ResourceLimit& e) {
    message = e.what();
  }
  // 401+4 x 321+4 x 241+4 cells.
  EXPECT_NE(message.find("grid 405 x 325 x 245 = 32,248,125 cells"), std::string::npos) << message;
  EXPECT_NE(message.find("516.0 MB at 16 bytes per cell"), std::string::npos) << message;
  EXPECT_NE(message.find("memory budget of 200.0 MB"), std::string::npos) << message;
  const std::string marker = "use a voxel size of at least ";
  const auto at = message.find(marker);
  ASSERT_NE(at, std::string::npos) << message;
  const double suggested = std::stod(message.substr(at + marker.size()));
  EXPECT_GT(suggested, options.voxelSize);
  // The suggestion fits, and the next smaller two-digit size does not.
  options.voxelSize = suggested;
  const GridGeometry g = planGrid(box, options);
  EXPECT_LE(static_cast<double>(g.cellCount()) * options.bytesPerCell, options.memoryBudgetBytes);
  const double step = std::pow(10.0, std::floor(std::log10(suggested)) - 1.0);
  options.voxelSize = suggested - step;
  EXPECT_THROW(planGrid(box, options), ResourceLimit);
  std::cout << "[ budget   ] " << message << "\n";

  // The default budget is 80 % of the physical memory.
  EXPECT_GT(physicalMemoryBytes(), 1e8);
  options.memoryBudgetBytes = 0.0;
  options.voxelSize = 1e-3;  // 1e14 cells
  try {
    planGrid(box, options);
    FAIL() << "expected ResourceLimit";
  } catch (const ResourceLimit& e) {
    std::ostringstream budget;
    budget << std::fixed << std::setprecision(1) << 0.8 * physicalMemoryBytes() / 1e9 << " GB";
    EXPECT_NE(std::string(e.what()).find(budget.str()), std::string::npos) << e.what();
  }
}

TEST(Voxelize, CancellationThrowsCancelled) {
  const TriMesh sphere = makeSphere(Vec3::Zero(), 10.0, 4);
  VoxelizeOptions options;
  options.voxelSize = 0.05;  // 64 M cells: progress is reported in 15 chunks
  int calls = 0;
  EXPECT_THROW(voxelize(sphere, options, Progress([&](double, std::string_view) {
                          return ++calls < 5;  // cancel in the middle of the z rays
                        })),
               Cancelled);
  EXPECT_EQ(calls, 5);
  // Cancelling the resolution of odd columns.
  options.voxelSize = 0.2;
  const TriMesh holed = deleteTriangles(sphere, 0.05);
  bool sawResolve = false;
  EXPECT_THROW(voxelize(holed, options, Progress([&](double, std::string_view stage) {
                          sawResolve = sawResolve || stage == "resolve odd columns";
                          return !sawResolve;
                        })),
               Cancelled);
  EXPECT_TRUE(sawResolve);
}

TEST(Voxelize, ProgressIsMonotoneAndOnTheCallingThread) {
  const TriMesh holed = deleteTriangles(makeSphere(Vec3::Zero(), 10.0, 4), 0.05);
  VoxelizeOptions options;
  options.voxelSize = 0.25;
  const auto caller = std::this_thread::get_id();
  double last = -1.0;
  int calls = 0;
  bool otherThread = false, backwards = false;
  const VoxelizeResult result =
      voxelize(holed, options, Progress([&](double fraction, std::string_view) {
                 ++calls;
                 otherThread = otherThread || std::this_thread::get_id() != caller;
                 backwards = backwards || fraction < last;
                 last = fraction;
                 return true;
               }));
  EXPECT_GT(result.stats.oddColumns, 0u);
  EXPECT_GE(calls, 5);  // plan grid, z rays, x rays, y rays, done
  EXPECT_FALSE(otherThread);
  EXPECT_FALSE(backwards);
  EXPECT_DOUBLE_EQ(last, 1.0);
}

TEST(Voxelize, DeterministicAcrossRunsAndThreadCounts) {
  const TriMesh holed = deleteTriangles(loadModel("bunny_closed_low_res.stl"), 0.02);
  VoxelizeOptions options;
  options.voxelSize = 1.0;
  const int threads = omp_get_max_threads();
  const VoxelizeResult a = voxelize(holed, options);
  const VoxelizeResult b = voxelize(holed, options);
  omp_set_num_threads(1);
  const VoxelizeResult c = voxelize(holed, options);
  omp_set_num_threads(threads);
  EXPECT_EQ(a.grid.inside, b.grid.inside);
  EXPECT_EQ(a.grid.inside, c.grid.inside);
  EXPECT_EQ(a.stats.oddColumns, c.stats.oddColumns);
  EXPECT_EQ(a.stats.resolvedVoxels, c.stats.resolvedVoxels);
  EXPECT_EQ(a.grid.geometry.corner, c.grid.geometry.corner);
}

void measureBunny(double voxelSize) {
  const TriMesh bunny = loadModel("bunny_closed_low_res.stl");
  VoxelizeOptions options;
  options.voxelSize = voxelSize;
  const VoxelizeResult result = voxelize(bunny, options);
  const std::size_t cells = result.grid.geometry.cellCount();
  EXPECT_EQ(result.stats.oddColumns, 0u);
  EXPECT_NEAR(result.grid.insideVolume() / signedVolume(bunny), 1.0, 0.002);
  std::cout << "[ bunny    ] L = " << voxelSize << " mm: grid " << result.grid.geometry.dims.x()
            << " x " << result.grid.geometry.dims.y() << " x " << result.grid.geometry.dims.z()
            << " = " << cells << " cells in " << result.stats.seconds
            << " s = " << static_cast<double>(cells) / result.stats.seconds / 1e6 << " M cells/s ("
            << omp_get_max_threads() << " threads)\n";
}

TEST(Voxelize, BunnyIsWatertightAndPrintsThroughput) {
  measureBunny(0.5);
}

// 400 M cells (400 MB); run with --gtest_also_run_disabled_tests.
TEST(Voxelize, DISABLED_BunnyFineIsWatertightAndPrintsThroughput) {
  measureBunny(0.25);
}

}  // namespace
}  // namespace curvedslicer::testing
