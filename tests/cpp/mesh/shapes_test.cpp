// Tests of the analytic test solids in tests/cpp/common/shapes.cpp: every solid is closed,
// consistently outward-oriented, and encloses the analytic volume.
#include "common/shapes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <utility>

namespace curvedslicer::testing {
namespace {

/// Counts directed edges: a closed, consistently oriented 2-manifold uses each directed edge
/// exactly once and its reverse exactly once.
struct EdgeCheck {
  std::size_t badEdges = 0;
  std::size_t degenerate = 0;
  std::size_t unusedVertices = 0;
};

EdgeCheck checkEdges(const TriMesh& mesh) {
  EdgeCheck check;
  std::map<std::pair<int, int>, int> directed;
  std::vector<bool> used(mesh.vertices.size(), false);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3i& tri = mesh.triangles[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] || mesh.triangleArea(t) <= 0) {
      ++check.degenerate;
    }
    for (int k = 0; k < 3; ++k) {
      ++directed[{tri[k], tri[(k + 1) % 3]}];
      used[tri[k]] = true;
    }
  }
  for (const auto& [edge, count] : directed) {
    auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) ++check.badEdges;
  }
  for (bool u : used) check.unusedVertices += u ? 0 : 1;
  return check;
}

void expectClosedSolid(const TriMesh& mesh, double expectedVolume, double relTol,
                       const char* what) {
  SCOPED_TRACE(what);
  ASSERT_FALSE(mesh.empty());
  EXPECT_EQ(mesh.faceIds.size(), mesh.triangles.size());
  const EdgeCheck check = checkEdges(mesh);
  EXPECT_EQ(check.badEdges, 0u);
  EXPECT_EQ(check.degenerate, 0u);
  EXPECT_EQ(check.unusedVertices, 0u);
  const double volume = signedVolume(mesh);
  EXPECT_GT(volume, 0.0);
  EXPECT_NEAR(volume, expectedVolume, relTol * expectedVolume);
}

double prismVolume(double radius, double height, int segments) {
  return 0.5 * segments * radius * radius * std::sin(2 * std::numbers::pi / segments) * height;
}

TEST(Shapes, BoxesAreClosedWithExactVolume) {
  const Vec3 lo(-1, 2, 3), hi(4, 5, 9);
  const TriMesh box = makeBox(lo, hi);
  EXPECT_EQ(box.triangleCount(), 12u);
  EXPECT_EQ(box.vertexCount(), 8u);
  expectClosedSolid(box, 5 * 3 * 6, 1e-12, "box");
  const TriMesh sub = makeSubdividedBox(lo, hi, 4);
  EXPECT_EQ(sub.triangleCount(), 6u * 16u * 2u);
  EXPECT_EQ(sub.vertexCount(), 5u * 5u * 5u - 3u * 3u * 3u);
  expectClosedSolid(sub, 5 * 3 * 6, 1e-12, "subdivided box");
  EXPECT_TRUE(sub.bounds().min.isApprox(lo));
  EXPECT_TRUE(sub.bounds().max.isApprox(hi));
}

TEST(Shapes, RotationKeepsVolumeAndMovesVertices) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(2, 1, 1));
  const Mat3 r = Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()).toRotationMatrix();
  const TriMesh turned = rotated(box, r, Vec3(0, 0, 0));
  expectClosedSolid(turned, 2.0, 1e-12, "rotated box");
  EXPECT_NEAR(turned.bounds().min.x(), -1.0, 1e-12);
  EXPECT_NEAR(turned.bounds().max.y(), 2.0, 1e-12);
}

TEST(Shapes, SphereVerticesOnSphereAndVolumeConverges) {
  const Vec3 c(1, -2, 0.5);
  const double r = 3.0;
  const TriMesh s3 = makeSphere(c, r, 3);
  EXPECT_EQ(s3.triangleCount(), 20u * 64u);
  for (const Vec3& p : s3.vertices) EXPECT_NEAR((p - c).norm(), r, 1e-12);
  const double exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  expectClosedSolid(s3, exact, 0.02, "sphere s=3");
  const TriMesh s0 = makeSphere(c, r, 0);
  expectClosedSolid(s0, exact, 0.4, "icosahedron");
  EXPECT_LT(std::abs(signedVolume(s3) - exact), std::abs(signedVolume(s0) - exact));
}

TEST(Shapes, SphericalShellHasInwardCavity) {
  const TriMesh shell = makeSphericalShell(Vec3::Zero(), 2.0, 5.0, 3);
  const double exact = 4.0 / 3.0 * std::numbers::pi * (125.0 - 8.0);
  expectClosedSolid(shell, exact, 0.02, "shell");
  // Inner sphere triangles point towards the centre.
  std::size_t inward = 0;
  for (std::size_t t = 0; t < shell.triangleCount(); ++t) {
    const Vec3 centroid = (shell.corner(t, 0) + shell.corner(t, 1) + shell.corner(t, 2)) / 3.0;
    if (centroid.norm() < 3.0) {
      EXPECT_LT(shell.areaNormal(t).dot(centroid), 0.0);
      ++inward;
    }
  }
  EXPECT_EQ(inward, shell.triangleCount() / 2);
}

TEST(Shapes, TorusVolume) {
  const double R = 10, r = 3;
  const TriMesh torus = makeTorus(Vec3(0, 0, 1), R, r, 96, 48);
  EXPECT_EQ(torus.triangleCount(), 2u * 96u * 48u);
  expectClosedSolid(torus, 2 * std::numbers::pi * std::numbers::pi * R * r * r, 0.01, "torus");
}

TEST(Shapes, CylinderTessellationsDescribeTheSamePrism) {
  const Vec3 base(1, 2, -3);
  const double radius = 5, height = 7;
  const int segments = 24;
  const double exact = prismVolume(radius, height, segments);
  const TriMesh plain = makeCylinder(base, radius, height, segments);
  EXPECT_EQ(plain.triangleCount(), 4u * segments);
  expectClosedSolid(plain, exact, 1e-12, "cylinder");
  const TriMesh ringed = makeCylinder(base, radius, height, segments, 5);
  EXPECT_EQ(ringed.triangleCount(), 2u * segments + 2u * 5u * segments);
  expectClosedSolid(ringed, exact, 1e-12, "cylinder with rings");
  const TriMesh sliver = makeSliverCylinder(base, radius, height, segments);
  expectClosedSolid(sliver, exact, 1e-12, "sliver cylinder");
  for (int target : {500, 5000, 20000}) {
    const TriMesh fine = makeFineCylinder(base, radius, height, segments, target);
    expectClosedSolid(fine, exact, 1e-12, "fine cylinder");
    EXPECT_NEAR(double(fine.triangleCount()), target, 0.25 * target);
  }
  // All share the same bounding box.
  for (const TriMesh* m : {&ringed, &sliver}) {
    EXPECT_TRUE(m->bounds().min.isApprox(plain.bounds().min, 1e-12));
    EXPECT_TRUE(m->bounds().max.isApprox(plain.bounds().max, 1e-12));
  }
}

TEST(Shapes, SliverCylinderHasSlivers) {
  const TriMesh sliver = makeSliverCylinder(Vec3::Zero(), 5, 7, 32);
  // Aspect = longest edge² / (2·area); a sliver has a large one.
  double worst = 0;
  for (std::size_t t = 0; t < sliver.triangleCount(); ++t) {
    double longest = 0;
    for (int k = 0; k < 3; ++k) {
      longest = std::max(longest, (sliver.corner(t, k) - sliver.corner(t, (k + 1) % 3)).norm());
    }
    worst = std::max(worst, longest * longest / (2 * sliver.triangleArea(t)));
  }
  EXPECT_GT(worst, 20.0);
}

TEST(Shapes, ConeVolumeIncludingApex) {
  const int n = 32;
  const double h = 4;
  auto frustum = [&](double r0, double r1) {
    // Frustum of regular n-gons: h/3·(A0 + A1 + sqrt(A0·A1)).
    const double k = 0.5 * n * std::sin(2 * std::numbers::pi / n);
    const double a0 = k * r0 * r0, a1 = k * r1 * r1;
    return h / 3 * (a0 + a1 + std::sqrt(a0 * a1));
  };
  expectClosedSolid(makeCone(Vec3(0, 0, 1), 3, 1, h, n), frustum(3, 1), 1e-12, "frustum");
  expectClosedSolid(makeCone(Vec3(0, 0, 1), 3, 0, h, n), frustum(3, 0), 1e-12, "cone");
  expectClosedSolid(makeCone(Vec3(0, 0, 1), 0, 2, h, n), frustum(0, 2), 1e-12, "inverted cone");
}

TEST(Shapes, LPrismFaceIds) {
  const double a = 10, b = 6, w = 2, h = 3;
  const TriMesh l = makeLPrism(a, b, w, h);
  expectClosedSolid(l, (a * w + (b - w) * w) * h, 1e-12, "L prism");
  double area1 = 0, area2 = 0;
  for (std::size_t t = 0; t < l.triangleCount(); ++t) {
    const Vec3 nrm = l.areaNormal(t).normalized();
    if (l.faceIds[t] == 1) {
      area1 += l.triangleArea(t);
      for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(l.corner(t, k).x(), a);
      EXPECT_NEAR(nrm.x(), 1.0, 1e-12);
    } else if (l.faceIds[t] == 2) {
      area2 += l.triangleArea(t);
      for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(l.corner(t, k).y(), b);
      EXPECT_NEAR(nrm.y(), 1.0, 1e-12);
    } else {
      EXPECT_EQ(l.faceIds[t], 0);
    }
  }
  EXPECT_NEAR(area1, w * h, 1e-12);
  EXPECT_NEAR(area2, w * h, 1e-12);
}

TEST(Shapes, HalfAnnulusFaceIds) {
  const double ri = 4, ro = 7, h = 2;
  const int segments = 64;
  const TriMesh u = makeHalfAnnulus(ri, ro, h, segments);
  // Cross-section: half of a regular 2·segments-gon annulus.
  const double ring =
      0.5 * (2 * segments) * std::sin(std::numbers::pi / segments) * (ro * ro - ri * ri);
  expectClosedSolid(u, 0.5 * ring * h, 1e-12, "half annulus");
  EXPECT_NEAR(signedVolume(u), 0.5 * std::numbers::pi * (ro * ro - ri * ri) * h,
              0.01 * signedVolume(u));
  double area1 = 0, area2 = 0;
  for (std::size_t t = 0; t < u.triangleCount(); ++t) {
    if (u.faceIds[t] == 0) continue;
    ASSERT_TRUE(u.faceIds[t] == 1 || u.faceIds[t] == 2);
    const double sign = u.faceIds[t] == 1 ? 1.0 : -1.0;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(u.corner(t, k).y(), 0.0);
      EXPECT_GT(sign * u.corner(t, k).x(), 0.0);
    }
    EXPECT_LT(u.areaNormal(t).y(), 0.0);  // end faces look towards -y
    (u.faceIds[t] == 1 ? area1 : area2) += u.triangleArea(t);
  }
  EXPECT_NEAR(area1, (ro - ri) * h, 1e-12);
  EXPECT_NEAR(area2, (ro - ri) * h, 1e-12);
}

TEST(Shapes, DeleteTrianglesRemovesAboutTheFraction) {
  const TriMesh sphere = makeSphere(Vec3::Zero(), 1, 3);
  const TriMesh holed = deleteTriangles(sphere, 0.1);
  EXPECT_EQ(holed.triangleCount(), sphere.triangleCount() - 128u);
  EXPECT_EQ(holed.faceIds.size(), holed.triangleCount());
  EXPECT_GT(checkEdges(holed).badEdges, 0u);
  EXPECT_EQ(deleteTriangles(sphere, 0.0).triangleCount(), sphere.triangleCount());
  EXPECT_EQ(deleteTriangles(sphere, 1.0).triangleCount(), 0u);
  // Deterministic.
  EXPECT_EQ(deleteTriangles(sphere, 0.1).triangles, holed.triangles);
}

TEST(Shapes, GeneratorsAreDeterministic) {
  EXPECT_EQ(makeTorus(Vec3::Zero(), 5, 1, 20, 10).vertices,
            makeTorus(Vec3::Zero(), 5, 1, 20, 10).vertices);
  EXPECT_EQ(makeFineCylinder(Vec3::Zero(), 1, 2, 16, 3000).triangles,
            makeFineCylinder(Vec3::Zero(), 1, 2, 16, 3000).triangles);
}

TEST(Shapes, WriteTempStlWritesBinaryStl) {
  const TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(1, 2, 3));
  const std::string path = writeTempStl(box, "box.stl");
  const std::string other = writeTempStl(box, "box.stl");
  EXPECT_NE(path, other);
  EXPECT_EQ(std::filesystem::path(path).filename(), "box.stl");
  EXPECT_EQ(std::filesystem::file_size(path), 84u + 50u * 12u);
  std::ifstream in(path, std::ios::binary);
  char header[80];
  std::uint32_t count = 0;
  in.read(header, 80);
  in.read(reinterpret_cast<char*>(&count), 4);
  EXPECT_EQ(count, 12u);
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
  std::filesystem::remove_all(std::filesystem::path(other).parent_path());
}

}  // namespace
}  // namespace curvedslicer::testing
