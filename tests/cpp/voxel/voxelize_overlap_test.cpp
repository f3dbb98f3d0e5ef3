// Overlapping and nested closed shells: filled by the non-zero winding rule as their
// union, with the voxels inside two or more shells counted; surfaces whose edges do not cancel
// fall back to parity.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <utility>

#include "common/shapes.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace curvedslicer::testing {
namespace {

VoxelizeOptions modelAligned(double voxelSize) {
  VoxelizeOptions options;
  options.voxelSize = voxelSize;
  options.alignment = GridAlignment::Model;
  return options;
}

/// `a` and `b` as one triangle soup (b's vertices renumbered).
TriMesh combined(const TriMesh& a, const TriMesh& b) {
  TriMesh out = a;
  const int offset = static_cast<int>(a.vertices.size());
  out.vertices.insert(out.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const Vec3i& t : b.triangles) out.triangles.push_back(t + Vec3i::Constant(offset));
  out.faceIds.clear();
  return out;
}

TriMesh inverted(TriMesh mesh) {
  for (Vec3i& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

TEST(VoxelizeOverlap, OverlappingBoxesGiveTheirUnionAndCountTheOverlap) {
  // 20 x 30 x 20 = 12,000 voxels each, overlapping in 15 x 30 x 20 = 9,000: union 15,000.
  const TriMesh a = makeBox(Vec3(0, 0, 0), Vec3(20, 30, 20));
  const TriMesh b = makeBox(Vec3(5, 0, 0), Vec3(25, 30, 20));
  const VoxelizeResult result = voxelize(combined(a, b), modelAligned(1.0));
  EXPECT_EQ(result.stats.fillRule, FillRule::NonZeroWinding);
  EXPECT_EQ(result.grid.insideCount, 15000u);
  EXPECT_EQ(result.stats.overlapVoxels, 9000u);
  EXPECT_EQ(result.stats.oddColumns, 0u);
  // Where: the overlap's voxel centres span x 5.5..19.5, y 0.5..29.5, z 0.5..19.5 (part frame).
  EXPECT_TRUE(result.stats.overlapBounds.min.isApprox(Vec3(5.5, 0.5, 0.5), 1e-12))
      << result.stats.overlapBounds.min.transpose();
  EXPECT_TRUE(result.stats.overlapBounds.max.isApprox(Vec3(19.5, 29.5, 19.5), 1e-12))
      << result.stats.overlapBounds.max.transpose();
  const GridGeometry& g = result.grid.geometry;
  for (int i = 0; i < g.dims.x(); ++i) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int k = 0; k < g.dims.z(); ++k) {
        const Vec3 c = g.centerInGrid(Vec3i(i, j, k));
        const bool want =
            c.x() > 0 && c.x() < 25 && c.y() > 0 && c.y() < 30 && c.z() > 0 && c.z() < 20;
        ASSERT_EQ(result.grid.isInside(i, j, k), want) << c.transpose();
      }
    }
  }
}

TEST(VoxelizeOverlap, ASingleShellCountsNoOverlap) {
  const VoxelizeResult result =
      voxelize(makeBox(Vec3(0, 0, 0), Vec3(20, 30, 20)), modelAligned(1.0));
  EXPECT_EQ(result.stats.fillRule, FillRule::NonZeroWinding);
  EXPECT_EQ(result.grid.insideCount, 12000u);
  EXPECT_EQ(result.stats.overlapVoxels, 0u);
  EXPECT_TRUE(result.stats.overlapBounds.empty());
}

TEST(VoxelizeOverlap, NestedShellsAreAUnionButAnInvertedInnerShellIsACavity) {
  const TriMesh outer = makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10));
  const TriMesh inner = makeBox(Vec3(2, 2, 2), Vec3(6, 6, 6));
  const VoxelizeResult nested = voxelize(combined(outer, inner), modelAligned(1.0));
  EXPECT_EQ(nested.grid.insideCount, 1000u);
  EXPECT_EQ(nested.stats.overlapVoxels, 64u);
  const VoxelizeResult cavity = voxelize(combined(outer, inverted(inner)), modelAligned(1.0));
  EXPECT_EQ(cavity.stats.fillRule, FillRule::NonZeroWinding);
  EXPECT_EQ(cavity.grid.insideCount, 1000u - 64u);
  EXPECT_EQ(cavity.stats.overlapVoxels, 0u);
  // An inside-out model is still filled (non-zero, not positive, winding).
  const VoxelizeResult insideOut = voxelize(inverted(outer), modelAligned(1.0));
  EXPECT_EQ(insideOut.grid.insideCount, 1000u);
}

TEST(VoxelizeOverlap, EdgesThatDoNotCancelFallBackToParity) {
  // One flipped triangle: no winding number; parity makes the overlap a hole, as before.
  TriMesh soup =
      combined(makeBox(Vec3(0, 0, 0), Vec3(20, 30, 20)), makeBox(Vec3(5, 0, 0), Vec3(25, 30, 20)));
  std::swap(soup.triangles[0][1], soup.triangles[0][2]);
  const VoxelizeResult result = voxelize(soup, modelAligned(1.0));
  EXPECT_EQ(result.stats.fillRule, FillRule::Parity);
  EXPECT_EQ(result.grid.insideCount, 15000u - 9000u);
  EXPECT_EQ(result.stats.overlapVoxels, 0u);
  EXPECT_EQ(toString(FillRule::Parity), "parity");
  EXPECT_EQ(toString(FillRule::NonZeroWinding), "nonzero");
}

TEST(VoxelizeOverlap, BudgetBeyondTheCellLimitIsRefusedBeforeAllocating) {
  VoxelizeOptions options = modelAligned(0.01);
  options.memoryBudgetBytes = 1e36;
  try {
    (void)planGrid(makeBox(Vec3(0, 0, 0), Vec3(20, 30, 20)), options);
    ADD_FAILURE() << "no ResourceLimit";
  } catch (const ResourceLimit& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("2,147,483,647 cells in all"), std::string::npos) << message;
    EXPECT_NE(message.find("use a voxel size of at least"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace curvedslicer::testing
