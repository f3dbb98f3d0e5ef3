// Tests of analyzeMesh (mesh_report.hpp) on analytic meshes and the bundled models.
#include "curvedslicer/mesh/mesh_report.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <numbers>
#include <utility>

#include "common/shapes.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"

namespace curvedslicer {
namespace {

using testing::makeBox;
using testing::makeSphere;

TEST(MeshReport, ClosedBox) {
  const MeshReport r = analyzeMesh(makeBox(Vec3(-1, 0, 1), Vec3(1, 3, 5)));
  EXPECT_EQ(r.vertices, 8u);
  EXPECT_EQ(r.triangles, 12u);
  EXPECT_EQ(r.openEdges, 0u);
  EXPECT_EQ(r.nonManifoldEdges, 0u);
  EXPECT_EQ(r.inconsistentEdges, 0u);
  EXPECT_EQ(r.degenerateTriangles, 0u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.consistentlyOriented());
  EXPECT_NEAR(r.volume, 2 * 3 * 4, 1e-12);
  EXPECT_NEAR(r.area, 2 * (2 * 3 + 3 * 4 + 2 * 4), 1e-12);
  EXPECT_EQ(r.bounds.min, Vec3(-1, 0, 1));
  EXPECT_EQ(r.bounds.max, Vec3(1, 3, 5));
}

TEST(MeshReport, MissingTriangleLeavesThreeOpenEdges) {
  TriMesh box = makeBox(Vec3::Zero(), Vec3::Ones());
  box.triangles.erase(box.triangles.begin() + 7);
  const MeshReport r = analyzeMesh(box);
  EXPECT_EQ(r.openEdges, 3u);
  EXPECT_EQ(r.nonManifoldEdges, 0u);
  EXPECT_EQ(r.inconsistentEdges, 0u);
  EXPECT_FALSE(r.closed());
  EXPECT_EQ(r.components, 1u);
}

TEST(MeshReport, FlippedTriangleGivesInconsistentEdges) {
  TriMesh box = makeBox(Vec3::Zero(), Vec3::Ones());
  std::swap(box.triangles[4][1], box.triangles[4][2]);
  const MeshReport r = analyzeMesh(box);
  EXPECT_EQ(r.inconsistentEdges, 3u);
  EXPECT_FALSE(r.consistentlyOriented());
  EXPECT_TRUE(r.closed());
  // The flipped triangle's cone to the centre now counts negatively: 1 - 2·(1/12).
  EXPECT_NEAR(r.volume, 1.0 - 2.0 / 12.0, 1e-12);
}

TEST(MeshReport, DefectBoundsBoxTheOpenAndInconsistentEdges) {
  EXPECT_TRUE(analyzeMesh(makeBox(Vec3::Zero(), Vec3::Ones())).defectBounds.empty());
  // Without the two top triangles (z = 1) the open edges are the top square's rim.
  TriMesh open = makeBox(Vec3::Zero(), Vec3(2, 3, 4));
  const auto top = [&open](const Vec3i& t) {
    return open.vertices[t[0]].z() == 4 && open.vertices[t[1]].z() == 4 &&
           open.vertices[t[2]].z() == 4;
  };
  open.triangles.erase(std::remove_if(open.triangles.begin(), open.triangles.end(), top),
                       open.triangles.end());
  const MeshReport r = analyzeMesh(open);
  EXPECT_EQ(r.openEdges, 4u);
  EXPECT_EQ(r.defectBounds.min, Vec3(0, 0, 4));
  EXPECT_EQ(r.defectBounds.max, Vec3(2, 3, 4));
  // One flipped triangle: the box of its three edges, i.e. of the triangle.
  TriMesh flipped = makeBox(Vec3::Zero(), Vec3::Ones());
  std::swap(flipped.triangles[4][1], flipped.triangles[4][2]);
  Aabb triangle;
  for (int k = 0; k < 3; ++k) triangle.extend(flipped.vertices[flipped.triangles[4][k]]);
  const MeshReport f = analyzeMesh(flipped);
  EXPECT_EQ(f.defectBounds.min, triangle.min);
  EXPECT_EQ(f.defectBounds.max, triangle.max);
}

TEST(MeshReport, InwardOrientationGivesNegativeVolume) {
  TriMesh sphere = makeSphere(Vec3(3, 2, 1), 2, 3);
  for (Vec3i& t : sphere.triangles) std::swap(t[1], t[2]);
  const MeshReport r = analyzeMesh(sphere);
  EXPECT_TRUE(r.consistentlyOriented());
  EXPECT_NEAR(r.volume, -4.0 / 3.0 * std::numbers::pi * 8, 0.02 * 4.0 / 3.0 * std::numbers::pi * 8);
}

TEST(MeshReport, NonManifoldEdge) {
  // A fin: one extra triangle hinged on a box edge makes that edge used three times.
  TriMesh box = makeBox(Vec3::Zero(), Vec3::Ones());
  int a = -1, b = -1;
  for (int i = 0; i < 8; ++i) {
    if (box.vertices[i] == Vec3(1, 1, 0)) a = i;
    if (box.vertices[i] == Vec3(1, 1, 1)) b = i;
  }
  ASSERT_GE(a, 0);
  ASSERT_GE(b, 0);
  box.vertices.push_back(Vec3(2, 2, 0.5));
  box.triangles.emplace_back(a, b, 8);
  const MeshReport r = analyzeMesh(box);
  EXPECT_EQ(r.nonManifoldEdges, 1u);
  EXPECT_EQ(r.openEdges, 2u);  // the fin's free edges
  EXPECT_FALSE(r.closed());
  EXPECT_EQ(r.components, 1u);

  // Two boxes touching along an edge (after welding): that edge has four triangles.
  TriMesh pair = makeBox(Vec3::Zero(), Vec3::Ones());
  appendMesh(pair, makeBox(Vec3(1, 1, 0), Vec3(2, 2, 1)));
  const MeshReport touching = analyzeMesh(cleanMesh(pair).mesh);
  EXPECT_EQ(touching.nonManifoldEdges, 1u);
  EXPECT_EQ(touching.openEdges, 0u);
}

TEST(MeshReport, DegenerateTriangles) {
  TriMesh box = makeBox(Vec3::Zero(), Vec3::Ones());
  const int origin = static_cast<int>(
      std::find(box.vertices.begin(), box.vertices.end(), Vec3(0, 0, 0)) - box.vertices.begin());
  ASSERT_LT(origin, 8);
  box.vertices.push_back(Vec3(0.5, 0.5, 0.5));
  box.vertices.push_back(Vec3(0.5, 0.5, 0.5 + 1e-9));
  box.triangles.emplace_back(8, 8, 9);       // repeated index
  box.triangles.emplace_back(8, 9, origin);  // area ~ 0.35e-9 mm², above 1e-12·3 = 3e-12
  box.vertices.push_back(Vec3(0.25, 0.25, 0.25));
  box.triangles.emplace_back(origin, 8, 10);  // collinear: exactly or nearly zero area
  const MeshReport r = analyzeMesh(box);
  EXPECT_EQ(r.degenerateTriangles, 2u);
}

TEST(MeshReport, CountsComponents) {
  TriMesh two = makeBox(Vec3::Zero(), Vec3::Ones());
  appendMesh(two, makeBox(Vec3(3, 0, 0), Vec3(4, 1, 1)));
  EXPECT_EQ(analyzeMesh(two).components, 2u);
  const TriMesh shell = testing::makeSphericalShell(Vec3::Zero(), 1, 2, 2);
  const MeshReport r = analyzeMesh(shell);
  EXPECT_EQ(r.components, 2u);
  EXPECT_TRUE(r.closed());
  EXPECT_TRUE(r.consistentlyOriented());
  EXPECT_GT(r.volume, 0.0);
  // Touching at a single vertex only: still two edge-connected components.
  TriMesh corner = makeBox(Vec3::Zero(), Vec3::Ones());
  appendMesh(corner, makeBox(Vec3(1, 1, 1), Vec3(2, 2, 2)));
  EXPECT_EQ(analyzeMesh(cleanMesh(corner).mesh).components, 2u);
}

TEST(MeshReport, EmptyMesh) {
  const MeshReport r = analyzeMesh(TriMesh{});
  EXPECT_EQ(r.triangles, 0u);
  EXPECT_EQ(r.components, 0u);
  EXPECT_EQ(r.volume, 0.0);
  EXPECT_TRUE(r.bounds.empty());
}

TEST(MeshReport, RejectsOutOfRangeIndices) {
  TriMesh box = makeBox(Vec3::Zero(), Vec3::Ones());
  box.triangles[0][0] = -1;
  EXPECT_THROW(analyzeMesh(box), InvalidInput);
}

TEST(MeshReport, AnalyticSolidsAreClosed) {
  const std::pair<const char*, TriMesh> solids[] = {
      {"sphere", makeSphere(Vec3::Zero(), 3, 3)},
      {"torus", testing::makeTorus(Vec3::Zero(), 5, 1, 32, 16)},
      {"sliver cylinder", testing::makeSliverCylinder(Vec3::Zero(), 2, 5, 20)},
      {"fine cylinder", testing::makeFineCylinder(Vec3::Zero(), 2, 5, 20, 4000)},
      {"L prism", testing::makeLPrism(5, 4, 1, 2)},
      {"half annulus", testing::makeHalfAnnulus(2, 3, 1, 16)},
      {"cone", testing::makeCone(Vec3::Zero(), 2, 0, 3, 16)},
      {"subdivided box", testing::makeSubdividedBox(Vec3::Zero(), Vec3::Ones(), 5)}};
  for (const auto& [name, mesh] : solids) {
    SCOPED_TRACE(name);
    const MeshReport r = analyzeMesh(mesh);
    EXPECT_TRUE(r.closed());
    EXPECT_TRUE(r.consistentlyOriented());
    EXPECT_EQ(r.degenerateTriangles, 0u);
    EXPECT_EQ(r.components, 1u);
    EXPECT_GT(r.volume, 0.0);
    EXPECT_EQ(r.vertices, mesh.vertexCount());
  }
}

TEST(MeshReport, BundledModelsAreClosedAfterCleaning) {
  for (const auto& entry : std::filesystem::directory_iterator(testing::modelPath(""))) {
    if (entry.path().extension() != ".stl") continue;
    SCOPED_TRACE(entry.path().filename().string());
    const TriMesh soup = readMesh(entry.path());
    const MeshReport raw = analyzeMesh(soup);
    EXPECT_EQ(raw.openEdges, 3 * soup.triangleCount());  // nothing shared before welding
    const CleanResult cleaned = cleanMesh(soup);
    const MeshReport r = analyzeMesh(cleaned.mesh);
    EXPECT_TRUE(r.closed()) << r.openEdges << " open, " << r.nonManifoldEdges << " non-manifold";
    EXPECT_TRUE(r.consistentlyOriented()) << r.inconsistentEdges;
    EXPECT_EQ(r.degenerateTriangles, 0u);
    EXPECT_GT(r.volume, 0.0);
    EXPECT_NEAR(r.volume, raw.volume, 1e-6 * raw.volume);  // welding does not move the surface
    RecordProperty(entry.path().stem().string(),
                   std::to_string(r.triangles) + " triangles, " + std::to_string(r.components) +
                       " components, volume " + std::to_string(r.volume));
  }
}

}  // namespace
}  // namespace curvedslicer
