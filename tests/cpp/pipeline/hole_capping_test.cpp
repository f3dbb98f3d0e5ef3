// Unit tests of pipeline/hole_capping.hpp on meshes with known holes.
#include "curvedslicer/pipeline/hole_capping.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/shapes.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/mesh/mesh_report.hpp"

namespace curvedslicer {
namespace {

/// `mesh` without the triangles whose corners all satisfy `drop`, welded.
template <typename Pred>
TriMesh withoutTriangles(const TriMesh& mesh, Pred drop) {
  TriMesh out;
  out.vertices = mesh.vertices;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (drop(mesh.corner(t, 0)) && drop(mesh.corner(t, 1)) && drop(mesh.corner(t, 2))) continue;
    out.triangles.push_back(mesh.triangles[t]);
    out.faceIds.push_back(static_cast<int>(t));
  }
  return cleanMesh(out).mesh;
}

/// Height field z = 0.02 (x² + y²) over [-15, 15]², 60 × 60 quads.
TriMesh makeParaboloid() {
  TriMesh m;
  const int n = 60;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const double x = -15.0 + 30.0 * i / n, y = -15.0 + 30.0 * j / n;
      m.vertices.emplace_back(x, y, 0.02 * (x * x + y * y));
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j, b = a + n + 1;
      m.triangles.emplace_back(a, b, b + 1);
      m.triangles.emplace_back(a, b + 1, a + 1);
    }
  }
  return m;
}

TEST(HoleCapping, ClosedMeshIsUnchanged) {
  const TriMesh box = cleanMesh(testing::makeBox(Vec3(0, 0, 0), Vec3(1, 2, 3))).mesh;
  const HoleCappingResult r = capHoles(box, {});
  EXPECT_EQ(r.loops, 0u);
  EXPECT_EQ(r.capTriangles, 0u);
  EXPECT_EQ(r.mesh.vertices, box.vertices);
  EXPECT_EQ(r.mesh.triangles, box.triangles);
}

TEST(HoleCapping, OpenBoxTopGetsAPlanarCap) {
  const TriMesh open =
      withoutTriangles(testing::makeSubdividedBox(Vec3(0, 0, 0), Vec3(10, 20, 30), 4),
                       [](const Vec3& p) { return p.z() == 30.0; });
  ASSERT_FALSE(analyzeMesh(open).closed());
  const HoleCappingResult r = capHoles(open, {});
  EXPECT_EQ(r.loops, 1u);
  EXPECT_EQ(r.cappedLoops, 1u);
  EXPECT_EQ(r.loopsOnStartSurface, 0u);
  EXPECT_EQ(r.openBoundaryEdges, 0u);
  EXPECT_EQ(r.capTriangles, 16u);  // a fan over the 16 edges of the subdivided rim
  const MeshReport report = analyzeMesh(r.mesh);
  EXPECT_TRUE(report.closed());
  EXPECT_TRUE(report.consistentlyOriented());
  EXPECT_NEAR(report.volume, 6000.0, 1e-6);
  // Caps carry face id −1; the model's triangles keep theirs.
  ASSERT_EQ(r.mesh.faceIds.size(), r.mesh.triangleCount());
  for (std::size_t t = open.triangleCount(); t < r.mesh.triangleCount(); ++t) {
    EXPECT_EQ(r.mesh.faceIds[t], -1);
  }
  EXPECT_EQ(std::vector<int>(r.mesh.faceIds.begin(), r.mesh.faceIds.begin() + open.triangleCount()),
            open.faceIds);
}

TEST(HoleCapping, CapOnACurvedStartSurfaceFollowsIt) {
  // A tube r = 10 whose bottom rim (z = 2) lies on the paraboloid z = 0.02 r², open at both ends.
  const double r = 10.0, zBase = 2.0, height = 20.0;
  const int segments = 64;
  const TriMesh tube =
      withoutTriangles(testing::makeCylinder(Vec3(0, 0, zBase), r, height, segments, 4),
                       [&](const Vec3& p) { return p.z() == zBase || p.z() == zBase + height; });
  const TriMesh base = makeParaboloid();
  const double spacing = 0.5;
  const HoleCappingResult capped = capHoles(tube, base, {spacing, 0.25 * spacing});
  EXPECT_EQ(capped.loops, 2u);
  EXPECT_EQ(capped.cappedLoops, 2u);
  EXPECT_EQ(capped.loopsOnStartSurface, 1u);
  const MeshReport report = analyzeMesh(capped.mesh);
  EXPECT_TRUE(report.closed());
  EXPECT_TRUE(report.consistentlyOriented());
  // Volume = prism above the rim + the bowl between rim plane and paraboloid:
  // ∫ (2 − 0.02 ρ²) dA over the disc = 2πr² − 0.01πr⁴ = 100π (the polygon differs at the rim,
  // where the integrand vanishes).
  const double polygonArea = 0.5 * segments * r * r * std::sin(2.0 * M_PI / segments);
  const double expected = polygonArea * height + 100.0 * M_PI;
  EXPECT_NEAR(report.volume, expected, 5.0);
  // Every cap vertex of the bottom cap lies on the paraboloid.
  const TriangleBvh bvh(base);
  double worst = 0.0;
  for (std::size_t v = tube.vertexCount(); v < capped.mesh.vertexCount(); ++v) {
    const Vec3& p = capped.mesh.vertices[v];
    if (p.z() < zBase + 1.0) worst = std::max(worst, bvh.distance(p));
  }
  EXPECT_LT(worst, 1e-6);
  // Without the start surface the bottom cap is flat: the bowl is missing.
  EXPECT_NEAR(analyzeMesh(capHoles(tube, {}).mesh).volume, polygonArea * height, 1e-6 * expected);
}

TEST(HoleCapping, PinchedBoundaryStaysOpen) {
  // Two triangles sharing one vertex: its boundary passes that vertex twice.
  TriMesh bowtie;
  bowtie.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)};
  bowtie.triangles = {Vec3i(0, 1, 2), Vec3i(0, 3, 4)};
  const HoleCappingResult r = capHoles(bowtie, {});
  EXPECT_EQ(r.cappedLoops, 0u);
  EXPECT_EQ(r.openBoundaryEdges, 6u);
  EXPECT_EQ(r.mesh.triangleCount(), 2u);
}

TEST(HoleCapping, RejectsBadOptions) {
  const TriMesh box = testing::makeBox(Vec3(0, 0, 0), Vec3(1, 1, 1));
  EXPECT_THROW(capHoles(box, {}, {0.0, 0.1}), InvalidInput);
  EXPECT_THROW(capHoles(box, {}, {std::nan(""), 0.1}), InvalidInput);
  EXPECT_THROW(capHoles(box, {}, {1.0, -1.0}), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
