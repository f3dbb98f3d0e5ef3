// TriangleBvh (geom/triangle_bvh.hpp): closest points, signed distance (pseudo-normal sign), ray
// and box queries, against closed forms on boxes and spheres.
#include "curvedslicer/geom/triangle_bvh.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "common/shapes.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

using testing::makeBox;
using testing::makeSphere;

/// Exact signed distance to the box [lo, hi].
double boxSdf(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const Vec3 c = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const Vec3 q = (p - c).cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// The same triangles with every corner its own vertex (an unwelded STL soup).
TriMesh unwelded(const TriMesh& mesh) {
  TriMesh soup;
  for (const Vec3i& t : mesh.triangles) {
    const int base = static_cast<int>(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(mesh.vertices[t[k]]);
    soup.triangles.emplace_back(base, base + 1, base + 2);
  }
  return soup;
}

TEST(TriangleBvh, ClosestPointOnBoxMatchesClosedForm) {
  const Vec3 lo(-1, -2, -3), hi(2, 1, 0.5);
  const TriMesh box = makeBox(lo, hi);
  const TriangleBvh bvh(box);
  EXPECT_EQ(bvh.triangleCount(), 12u);
  EXPECT_FALSE(bvh.empty());
  EXPECT_NEAR((bvh.bounds().min - lo).norm(), 0.0, 1e-15);
  EXPECT_NEAR((bvh.bounds().max - hi).norm(), 0.0, 1e-15);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  for (int s = 0; s < 2000; ++s) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const ClosestPoint c = bvh.closestPoint(p);
    ASSERT_GE(c.triangle, 0);
    EXPECT_NEAR(c.distance, std::abs(boxSdf(p, lo, hi)), 1e-12);
    EXPECT_NEAR((p - c.point).norm(), c.distance, 1e-12);
    EXPECT_NEAR(boxSdf(c.point, lo, hi), 0.0, 1e-12);  // on the surface
    EXPECT_NEAR(bvh.distance(p), c.distance, 0.0);
  }
}

TEST(TriangleBvh, SignedDistanceExactOnBoxIncludingEdgesAndCorners) {
  const Vec3 lo(0, 0, 0), hi(3, 2, 1);
  for (const TriMesh& mesh : {makeBox(lo, hi), unwelded(makeBox(lo, hi))}) {
    const TriangleBvh bvh(mesh);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 4.0);
    for (int s = 0; s < 3000; ++s) {
      const Vec3 p(u(rng), u(rng), u(rng));
      EXPECT_NEAR(bvh.signedDistance(p), boxSdf(p, lo, hi), 1e-12) << p.transpose();
    }
    // Points a hair off corners and edges, where one face normal gives the wrong sign.
    const double eps = 1e-9;
    const std::vector<Vec3> outside = {Vec3(3 + eps, 2 + eps, 1 + eps), Vec3(-eps, -eps, 0.5),
                                       Vec3(1.5, 2 + eps, 1 + eps),     Vec3(-eps, 1, 1 + eps),
                                       Vec3(3 + eps, -eps, -eps),       Vec3(1.2, 1.1, 1 + eps)};
    for (const Vec3& p : outside) {
      EXPECT_GT(bvh.signedDistance(p), 0.0) << p.transpose();
      EXPECT_NEAR(bvh.signedDistance(p), boxSdf(p, lo, hi), 1e-12);
    }
    const std::vector<Vec3> inside = {Vec3(3 - eps, 2 - eps, 1 - eps), Vec3(eps, eps, 0.5),
                                      Vec3(1.5, 2 - eps, 1 - eps), Vec3(eps, 1, 1 - eps),
                                      Vec3(1.2, 1.1, 1 - eps)};
    for (const Vec3& p : inside) EXPECT_LT(bvh.signedDistance(p), 0.0) << p.transpose();
    EXPECT_EQ(bvh.signedDistance(Vec3(3, 2, 1)), 0.0);  // on a corner
    ClosestPoint c;
    const double d = bvh.signedDistance(Vec3(1.5, 1.0, 0.25), &c);
    EXPECT_NEAR(d, -0.25, 1e-15);
    EXPECT_NEAR((c.point - Vec3(1.5, 1.0, 0.0)).norm(), 0.0, 1e-15);
  }
}

TEST(TriangleBvh, SignedDistanceOnSphereAndShell) {
  const Vec3 centre(0.3, -0.1, 0.2);
  const double radius = 2.0;
  const TriMesh sphere = makeSphere(centre, radius, 3);
  const TriangleBvh bvh(sphere);
  // Facets lie inside the true sphere by at most the sagitta; stay outside that band.
  const double sag = 0.01;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  int tested = 0;
  for (int s = 0; s < 4000; ++s) {
    const Vec3 p = centre + Vec3(u(rng), u(rng), u(rng));
    const double r = (p - centre).norm();
    if (std::abs(r - radius) < sag) continue;
    ++tested;
    const double d = bvh.signedDistance(p);
    EXPECT_EQ(d < 0.0, r < radius) << p.transpose();
    EXPECT_NEAR(std::abs(d), bvh.distance(p), 1e-15);
  }
  EXPECT_GT(tested, 3500);
  // Points just off mesh vertices (vertex pseudo-normal) keep the right sign.
  for (std::size_t v = 0; v < sphere.vertices.size(); v += 37) {
    const Vec3 n = (sphere.vertices[v] - centre).normalized();
    EXPECT_GT(bvh.signedDistance(sphere.vertices[v] + 1e-10 * n), 0.0);
    EXPECT_LT(bvh.signedDistance(sphere.vertices[v] - 1e-10 * n), 0.0);
  }
  // Shell: the cavity (inner sphere faces inward) is outside the solid.
  const TriangleBvh shell(testing::makeSphericalShell(centre, 1.0, 2.0, 3));
  EXPECT_GT(shell.signedDistance(centre), 0.9);
  EXPECT_LT(shell.signedDistance(centre + Vec3(1.5, 0, 0)), -0.45);
  EXPECT_GT(shell.signedDistance(centre + Vec3(0, 3, 0)), 0.99);
}

TEST(TriangleBvh, FirstRayHit) {
  const TriangleBvh bvh(makeBox(Vec3(0, 0, 0), Vec3(2, 2, 2)));
  const auto hit = bvh.firstRayHit(Vec3(-1, 0.5, 0.7), Vec3(2, 0, 0));  // t in units of |dir|
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.5, 1e-14);
  EXPECT_NEAR((hit->point - Vec3(0, 0.5, 0.7)).norm(), 0.0, 1e-14);
  EXPECT_GE(hit->triangle, 0);
  // From inside: the exit face.
  const auto exit = bvh.firstRayHit(Vec3(1, 1, 1), Vec3(0, 0, -1));
  ASSERT_TRUE(exit.has_value());
  EXPECT_NEAR(exit->t, 1.0, 1e-14);
  EXPECT_FALSE(bvh.firstRayHit(Vec3(-1, 0.5, 0.7), Vec3(-1, 0, 0)).has_value());
  EXPECT_FALSE(bvh.firstRayHit(Vec3(-1, 0.5, 0.7), Vec3(1, 0, 0), 0.5).has_value());
  EXPECT_FALSE(bvh.firstRayHit(Vec3(-1, 0.5, 0.7), Vec3(0, 0, 0)).has_value());
}

TEST(TriangleBvh, IntersectsBox) {
  const TriangleBvh bvh(makeBox(Vec3(0, 0, 0), Vec3(2, 2, 2)));
  Aabb inner;
  inner.extend(Vec3(0.5, 0.5, 0.5));
  inner.extend(Vec3(1.5, 1.5, 1.5));
  EXPECT_FALSE(bvh.intersectsBox(inner));  // strictly inside the solid: no surface
  Aabb straddling;
  straddling.extend(Vec3(1.5, 1.5, 1.5));
  straddling.extend(Vec3(2.5, 1.8, 1.8));
  EXPECT_TRUE(bvh.intersectsBox(straddling));
  Aabb away;
  away.extend(Vec3(3, 3, 3));
  away.extend(Vec3(4, 4, 4));
  EXPECT_FALSE(bvh.intersectsBox(away));
  EXPECT_FALSE(bvh.intersectsBox(Aabb{}));
}

TEST(TriangleBvh, EmptyAndDegenerateInput) {
  const TriangleBvh empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.closestPoint(Vec3::Zero()).triangle, -1);
  EXPECT_EQ(empty.distance(Vec3::Zero()), kInf);
  EXPECT_EQ(empty.signedDistance(Vec3::Zero()), kInf);
  EXPECT_FALSE(empty.firstRayHit(Vec3::Zero(), Vec3::UnitX()).has_value());

  TriMesh mesh = makeBox(Vec3(0, 0, 0), Vec3(1, 1, 1));
  mesh.vertices.push_back(Vec3(5, 5, 5));
  const int v = static_cast<int>(mesh.vertices.size()) - 1;
  mesh.triangles.emplace_back(v, v, 0);  // zero area: takes no part
  const TriangleBvh bvh(mesh);
  EXPECT_EQ(bvh.triangleCount(), 12u);
  EXPECT_NEAR(bvh.distance(Vec3(5, 5, 5)), std::sqrt(48.0), 1e-12);

  TriMesh bad = makeBox(Vec3(0, 0, 0), Vec3(1, 1, 1));
  bad.vertices[0].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(TriangleBvh{bad}, InvalidInput);
  TriMesh badIndex = makeBox(Vec3(0, 0, 0), Vec3(1, 1, 1));
  badIndex.triangles[3][1] = 99;
  EXPECT_THROW(TriangleBvh{badIndex}, InvalidInput);
}

TEST(TriangleBvh, ConcurrentQueriesMatchSerial) {
  const TriangleBvh bvh(makeSphere(Vec3(0, 0, 0), 1.0, 4));
  std::vector<Vec3> points;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int s = 0; s < 20000; ++s) points.emplace_back(u(rng), u(rng), u(rng));
  std::vector<double> serial(points.size()), parallel(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) serial[i] = bvh.signedDistance(points[i]);
#pragma omp parallel for num_threads(2)
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(points.size()); ++i) {
    parallel[i] = bvh.signedDistance(points[i]);
  }
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace curvedslicer
