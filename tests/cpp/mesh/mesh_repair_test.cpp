// Tests of cleanMesh (mesh_repair.hpp): welding, degenerate and duplicate removal, face ids.
#include "curvedslicer/mesh/mesh_repair.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "common/shapes.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_report.hpp"

namespace curvedslicer {
namespace {

using ::testing::HasSubstr;
using testing::makeBox;
using testing::makeSphere;

/// Every triangle gets its own three vertices (what an STL reader returns); face id = index.
TriMesh toSoup(const TriMesh& mesh) {
  TriMesh soup;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const int base = static_cast<int>(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(mesh.corner(t, k));
    soup.triangles.emplace_back(base, base + 1, base + 2);
    soup.faceIds.push_back(static_cast<int>(t));
  }
  return soup;
}

bool containsPoint(const TriMesh& mesh, const Vec3& p) {
  return std::find(mesh.vertices.begin(), mesh.vertices.end(), p) != mesh.vertices.end();
}

TEST(CleanMesh, WeldsATriangleSoupIntoAClosedMesh) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(3, 4, 12));
  const CleanResult r = cleanMesh(toSoup(box));
  EXPECT_EQ(r.mesh.vertexCount(), 8u);
  EXPECT_EQ(r.mesh.triangleCount(), 12u);
  EXPECT_EQ(r.mergedVertices, 36u - 8u);
  EXPECT_EQ(r.degenerateTriangles, 0u);
  EXPECT_EQ(r.duplicateTriangles, 0u);
  EXPECT_DOUBLE_EQ(r.weldTolerance, 1e-6 * 13.0);  // diagonal of 3×4×12 is 13
  const MeshReport report = analyzeMesh(r.mesh);
  EXPECT_TRUE(report.closed());
  EXPECT_TRUE(report.consistentlyOriented());
  EXPECT_NEAR(report.volume, 144.0, 1e-12);
  EXPECT_EQ(r.mesh.faceIds, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}));
}

TEST(CleanMesh, ToleranceIsRelativeToTheBoundingBox) {
  for (double scale : {1e-3, 1.0, 1e4}) {
    SCOPED_TRACE(scale);
    TriMesh soup = toSoup(makeBox(Vec3::Zero(), Vec3(3, 4, 12) * scale));
    const double tol = 1e-6 * 13.0 * scale;
    // Triangle 0's corners move by 0.4·tol (merged); triangle 1's first corner by 3·tol (kept).
    for (int k = 0; k < 3; ++k) soup.vertices[k] += Vec3(0.4 * tol, 0, 0);
    soup.vertices[3] += Vec3(0, 0, 3 * tol);
    const CleanResult r = cleanMesh(soup);
    EXPECT_NEAR(r.weldTolerance, tol, 1e-9 * tol);
    EXPECT_EQ(r.mesh.vertexCount(), 9u);
    EXPECT_EQ(r.mergedVertices, 36u - 9u);
    EXPECT_EQ(analyzeMesh(r.mesh).openEdges, 4u);  // the moved corner opens two edges each side
  }
}

TEST(CleanMesh, ZeroToleranceMergesOnlyIdenticalPositions) {
  TriMesh soup = toSoup(makeBox(Vec3::Zero(), Vec3::Ones()));
  soup.vertices[0].x() = std::nextafter(soup.vertices[0].x(), 1.0);
  CleanOptions options;
  options.relativeWeldTolerance = 0.0;
  const CleanResult exact = cleanMesh(soup, options);
  EXPECT_EQ(exact.mesh.vertexCount(), 9u);
  EXPECT_EQ(exact.weldTolerance, 0.0);
  EXPECT_EQ(cleanMesh(soup).mesh.vertexCount(), 8u);  // the default tolerance merges it
}

TEST(CleanMesh, ChainOfNearPointsMergesIntoFirstRepresentatives) {
  // A0..A3 on a line, 0.6·tol apart: A1 joins A0; A2 is 1.2·tol from A0 and A1 is no
  // representative, so A2 starts a new one, which A3 joins. No transitive chain A0-A1-A2-A3.
  TriMesh mesh;
  const Vec3 b(0, 10, 0), c(0, 0, 10);
  mesh.vertices = {b, c, Vec3(10, 10, 10)};
  const double diag = std::sqrt(300.0);
  CleanOptions options;
  options.relativeWeldTolerance = 1e-3;
  const double tol = 1e-3 * diag;
  for (int i = 0; i < 4; ++i) mesh.vertices.push_back(Vec3(5 + 0.6 * tol * i, 5, 5));
  for (int i = 0; i < 4; ++i) {
    mesh.triangles.emplace_back(3 + i, 0, 1);
    mesh.faceIds.push_back(10 + i);
  }
  mesh.triangles.emplace_back(0, 1, 2);  // pins the bounding box
  mesh.faceIds.push_back(99);
  const CleanResult r = cleanMesh(mesh, options);
  EXPECT_EQ(r.mergedVertices, 2u);
  EXPECT_TRUE(containsPoint(r.mesh, mesh.vertices[3]));
  EXPECT_FALSE(containsPoint(r.mesh, mesh.vertices[4]));
  EXPECT_TRUE(containsPoint(r.mesh, mesh.vertices[5]));
  EXPECT_FALSE(containsPoint(r.mesh, mesh.vertices[6]));
  EXPECT_EQ(r.duplicateTriangles, 2u);
  EXPECT_EQ(r.mesh.triangleCount(), 3u);
  EXPECT_EQ(r.mesh.faceIds, (std::vector<int>{10, 12, 99}));
}

TEST(CleanMesh, RemovesDegenerateTriangles) {
  TriMesh mesh = makeBox(Vec3::Zero(), Vec3::Ones());
  mesh.vertices.push_back(Vec3(0.5, 0, 0));  // on the edge (0,0,0)-(1,0,0)
  const int mid = static_cast<int>(mesh.vertices.size()) - 1;
  int v000 = -1, v100 = -1;
  for (int i = 0; i < 8; ++i) {
    if (mesh.vertices[i] == Vec3(0, 0, 0)) v000 = i;
    if (mesh.vertices[i] == Vec3(1, 0, 0)) v100 = i;
  }
  ASSERT_GE(v000, 0);
  ASSERT_GE(v100, 0);
  mesh.triangles.emplace_back(v000, v100, mid);  // zero area
  mesh.triangles.emplace_back(3, 3, 5);          // repeated index
  mesh.faceIds.push_back(-1);
  mesh.faceIds.push_back(-2);
  const CleanResult r = cleanMesh(mesh);
  EXPECT_EQ(r.degenerateTriangles, 2u);
  EXPECT_EQ(r.mesh.triangleCount(), 12u);
  EXPECT_EQ(r.mesh.vertexCount(), 8u);  // the point used only by a removed triangle is dropped
  EXPECT_EQ(std::count(r.mesh.faceIds.begin(), r.mesh.faceIds.end(), -1), 0);
  EXPECT_TRUE(analyzeMesh(r.mesh).closed());

  CleanOptions keep;
  keep.removeDegenerate = false;
  const CleanResult kept = cleanMesh(mesh, keep);
  EXPECT_EQ(kept.degenerateTriangles, 0u);
  EXPECT_EQ(kept.mesh.triangleCount(), 14u);
  EXPECT_EQ(kept.mesh.faceIds.back(), -2);
}

TEST(CleanMesh, WeldingCanMakeTrianglesDegenerate) {
  // A sliver whose two close corners weld together.
  TriMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1e-9, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 1)};
  mesh.triangles = {Vec3i(0, 1, 2), Vec3i(0, 2, 3)};
  const CleanResult r = cleanMesh(mesh);
  EXPECT_EQ(r.mergedVertices, 1u);
  EXPECT_EQ(r.degenerateTriangles, 1u);
  EXPECT_EQ(r.mesh.triangleCount(), 1u);
  EXPECT_TRUE(r.mesh.faceIds.empty());  // none in, none out
}

TEST(CleanMesh, CountsDuplicatesByOrientation) {
  TriMesh mesh = makeBox(Vec3::Zero(), Vec3::Ones());
  for (int t = 0; t < 12; ++t) mesh.faceIds[t] = t;
  const Vec3i t0 = mesh.triangles[0], t5 = mesh.triangles[5];
  mesh.triangles.push_back(Vec3i(t0[1], t0[2], t0[0]));  // same orientation (rotated)
  mesh.triangles.push_back(Vec3i(t0[0], t0[2], t0[1]));  // opposite
  mesh.triangles.push_back(Vec3i(t5[2], t5[1], t5[0]));  // opposite
  mesh.triangles.push_back(t5);                          // same
  for (int id : {100, 101, 102, 103}) mesh.faceIds.push_back(id);
  const CleanResult r = cleanMesh(mesh);
  EXPECT_EQ(r.duplicateTriangles, 2u);
  EXPECT_EQ(r.oppositeDuplicateTriangles, 2u);
  EXPECT_EQ(r.mesh.triangleCount(), 12u);
  EXPECT_EQ(r.mesh.triangles[0], t0);  // the first copy is kept
  EXPECT_EQ(*std::max_element(r.mesh.faceIds.begin(), r.mesh.faceIds.end()), 11);

  CleanOptions keep;
  keep.removeDuplicates = false;
  const CleanResult kept = cleanMesh(mesh, keep);
  EXPECT_EQ(kept.duplicateTriangles + kept.oppositeDuplicateTriangles, 0u);
  EXPECT_EQ(kept.mesh.triangleCount(), 16u);
  EXPECT_EQ(kept.mesh.faceIds.back(), 103);
}

TEST(CleanMesh, RejectsBadInput) {
  TriMesh mesh = makeBox(Vec3::Zero(), Vec3::Ones());
  TriMesh nan = mesh;
  nan.vertices[2].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    cleanMesh(nan);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("vertex 2 has a non-finite coordinate"));
  }
  TriMesh badIndex = mesh;
  badIndex.triangles[4][2] = 8;
  try {
    cleanMesh(badIndex);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("triangle 4 has a vertex index out of range: 8"));
  }
  CleanOptions negative;
  negative.relativeWeldTolerance = -1e-6;
  EXPECT_THROW(cleanMesh(mesh, negative), InvalidInput);
}

TEST(CleanMesh, LargeSoupIsFastAndDeterministic) {
  const TriMesh sphere = makeSphere(Vec3(1, 2, 3), 10, 6);  // 81,920 triangles
  const TriMesh soup = toSoup(sphere);
  const auto start = std::chrono::steady_clock::now();
  const CleanResult r = cleanMesh(soup);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 3.0);  // ~0.1 s in Release
  EXPECT_EQ(r.mesh.vertexCount(), sphere.vertexCount());
  EXPECT_EQ(r.mesh.triangleCount(), sphere.triangleCount());
  const MeshReport report = analyzeMesh(r.mesh);
  EXPECT_TRUE(report.closed());
  EXPECT_TRUE(report.consistentlyOriented());
  const CleanResult again = cleanMesh(soup);
  EXPECT_EQ(again.mesh.vertices, r.mesh.vertices);
  EXPECT_EQ(again.mesh.triangles, r.mesh.triangles);
}

}  // namespace
}  // namespace curvedslicer
