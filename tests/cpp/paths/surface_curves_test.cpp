// Boundary loops and plane / user-surface sections of triangle surfaces.
#include "curvedslicer/paths/surface_curves.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "curvedslicer/core/error.hpp"
#include "paths/revolution_meshes.hpp"

namespace curvedslicer {
namespace {

using testing::makeRectangleMesh;
using testing::makeRevolutionMesh;
using testing::Profile;

TriMesh annulus(double ri, double ro, double h) {
  Profile p{[](double t) { return t; }, [](double) { return 0.0; }, ri, ro,
            static_cast<int>(std::lround((ro - ri) / h))};
  return makeRevolutionMesh(p, h);
}

TEST(SurfaceCurves, BoundaryLoopsOfAnnulus) {
  const TriMesh mesh = annulus(5.0, 12.0, 0.5);
  const std::vector<Polyline> loops = extractBoundaryLoops(mesh);
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_TRUE(loops[0].closed);
  EXPECT_TRUE(loops[1].closed);
  for (const Vec3& p : loops[0].points) EXPECT_NEAR(std::hypot(p.x(), p.y()), 12.0, 1e-9);
  for (const Vec3& p : loops[1].points) EXPECT_NEAR(std::hypot(p.x(), p.y()), 5.0, 1e-9);
  EXPECT_NEAR(loops[0].length(), 2 * std::numbers::pi * 12.0, 0.05);
  // One pass also gives the boundary vertices (the planner's GDTC sources): exactly the loops'
  // points, each once, sorted.
  const SurfaceBoundary boundary = findBoundary(mesh);
  ASSERT_EQ(boundary.loops.size(), 2u);
  EXPECT_EQ(boundary.loops[0].points, loops[0].points);
  EXPECT_EQ(boundary.vertices.size(), loops[0].points.size() + loops[1].points.size());
  EXPECT_TRUE(std::is_sorted(boundary.vertices.begin(), boundary.vertices.end()));
  for (std::size_t i = 1; i < boundary.vertices.size(); ++i) {
    EXPECT_LT(boundary.vertices[i - 1], boundary.vertices[i]);
  }
  for (const std::int32_t v : boundary.vertices) {
    const double r = std::hypot(mesh.vertices[v].x(), mesh.vertices[v].y());
    EXPECT_TRUE(std::abs(r - 5.0) < 1e-9 || std::abs(r - 12.0) < 1e-9) << r;
  }
}

TEST(SurfaceCurves, BoundaryOfRectangleIsOneLoopAndClosedMeshHasNone) {
  const TriMesh rect = makeRectangleMesh(0, 4, 0, 3, 4, 3);
  const std::vector<Polyline> loops = extractBoundaryLoops(rect);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].points.size(), 14u);
  EXPECT_NEAR(loops[0].length(), 14.0, 1e-12);
  // Orientation: counter-clockwise seen from +z (the triangles' normal side).
  double area2 = 0.0;
  const auto& pts = loops[0].points;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec3& a = pts[i];
    const Vec3& b = pts[(i + 1) % pts.size()];
    area2 += a.x() * b.y() - b.x() * a.y();
  }
  EXPECT_NEAR(area2, 24.0, 1e-9);
  Profile sphere{[](double t) { return 5 * std::sin(t); }, [](double t) { return 5 * std::cos(t); },
                 0.0, std::numbers::pi, 20};
  EXPECT_TRUE(extractBoundaryLoops(makeRevolutionMesh(sphere, 0.8)).empty());
}

TEST(SurfaceCurves, PlaneSectionOfCylinderIsAnEllipse) {
  Profile cylinder{[](double) { return 10.0; }, [](double t) { return t; }, 0.0, 20.0, 40};
  const TriMesh mesh = makeRevolutionMesh(cylinder, 0.5);
  const Vec3 point(0, 0, 10), normal(0.3, 0, 1);
  const std::vector<Polyline> sections = computePlaneSection(mesh, point, normal);
  ASSERT_EQ(sections.size(), 1u);
  EXPECT_TRUE(sections[0].closed);
  for (const Vec3& p : sections[0].points) {
    EXPECT_NEAR(normal.normalized().dot(p - point), 0.0, 1e-12);
    EXPECT_NEAR(std::hypot(p.x(), p.y()), 10.0, 0.01);
  }
  EXPECT_THROW(computePlaneSection(mesh, point, Vec3::Zero()), InvalidInput);
  EXPECT_TRUE(computePlaneSection(mesh, Vec3(0, 0, 50), Vec3::UnitZ()).empty());
}

TEST(SurfaceCurves, UserSurfaceSection) {
  // A tilted, open user surface z = 0.2·x + 1 crossing a flat layer z = 1 along the line x = 0.
  const TriMesh layer = [] {
    TriMesh m = makeRectangleMesh(-10, 10, -10, 10, 20, 20);
    for (Vec3& v : m.vertices) v.z() = 1.0;
    return m;
  }();
  TriMesh user = makeRectangleMesh(-15, 15, -15, 15, 7, 7);
  for (Vec3& v : user.vertices) v.z() = 0.2 * v.x() + 1.0 + 0.013;  // offset: not through vertices
  const std::vector<Polyline> sections = computeSurfaceSection(layer, user);
  ASSERT_EQ(sections.size(), 1u);
  EXPECT_FALSE(sections[0].closed);
  for (const Vec3& p : sections[0].points) EXPECT_NEAR(p.x(), -0.013 / 0.2, 1e-6);
  EXPECT_NEAR(sections[0].length(), 20.0, 1e-6);
  EXPECT_THROW(computeSurfaceSection(layer, TriMesh{}), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
