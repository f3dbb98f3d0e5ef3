// Deposition direction V (paper §3.2): flat first layer over a plate, concentric spherical shells,
// earlier beads of the same layer, fallbacks and determinism; the Growth method against the
// paper's (Nearest) where the nearest material lies beside the point.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/shapes.hpp"
#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/paths/deposition.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;

double angleDegrees(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / kPi;
}

/// A flat plate z = 0 over [-50, 50]², two triangles.
TriMesh makePlate(double z = 0.0) {
  TriMesh m;
  m.vertices = {Vec3(-50, -50, z), Vec3(50, -50, z), Vec3(50, 50, z), Vec3(-50, 50, z)};
  m.triangles = {Vec3i(0, 1, 2), Vec3i(0, 2, 3)};
  return m;
}

/// Concentric circles of radius r0 + k·s at height z, as closed paths with normal +z.
std::vector<PlanPath> makeRings(double z, double r0, double s, int count) {
  std::vector<PlanPath> paths;
  for (int k = 0; k < count; ++k) {
    PlanPath p;
    p.index = k;
    p.closed = true;
    const double r = r0 + k * s;
    const int n = 60;
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * kPi * i / n;
      PathPoint q;
      q.position = Vec3(r * std::cos(a), r * std::sin(a), z);
      q.normal = Vec3::UnitZ();
      p.points.push_back(q);
    }
    paths.push_back(p);
  }
  return paths;
}

TEST(Deposition, FlatFirstLayerAbovePlatePointsDown) {
  const TriangleBvh plate(makePlate());
  std::vector<PlanPath> paths = makeRings(1.5, 5.0, 3.7, 4);  // h = 1.5 < s = 3.7
  DepositionSupport support;
  support.surface = &plate;
  support.earlierBeads = true;
  const DepositionStats stats = assignDepositionDirections(paths, support);
  EXPECT_EQ(stats.points, 240u);
  EXPECT_EQ(stats.towardsSurface, 240u);
  EXPECT_EQ(stats.normalFallbacks, 0u);
  for (const PlanPath& p : paths) {
    for (const PathPoint& q : p.points) {
      EXPECT_LT(angleDegrees(q.deposition, Vec3(0, 0, -1)), 1.0);
    }
  }
  EXPECT_NEAR(stats.minDistance, 1.5, 1e-12);
}

TEST(Deposition, EarlierBeadIsNearerThanAFarSubstrate) {
  // The paper's method. Layer 10 mm above the plate, rings 3.7 mm apart: every ring after the
  // first leans on the previous ring, horizontally (towards the centre).
  const TriangleBvh plate(makePlate());
  std::vector<PlanPath> paths = makeRings(10.0, 5.0, 3.7, 3);
  DepositionSupport support;
  support.surface = &plate;
  support.earlierBeads = true;
  DepositionOptions nearest;
  nearest.method = DepositionMethod::Nearest;
  const DepositionStats stats = assignDepositionDirections(paths, support, nearest);
  EXPECT_EQ(stats.towardsSurface, 60u);  // the first ring
  EXPECT_EQ(stats.towardsBeads, 120u);
  for (std::size_t k = 1; k < paths.size(); ++k) {
    for (const PathPoint& q : paths[k].points) {
      const Vec3 inward = -Vec3(q.position.x(), q.position.y(), 0.0).normalized();
      EXPECT_LT(angleDegrees(q.deposition, inward), 1.0);
    }
  }
  // Without earlier beads the plate is the only material.
  std::vector<PlanPath> alone = makeRings(10.0, 5.0, 3.7, 3);
  support.earlierBeads = false;
  EXPECT_EQ(assignDepositionDirections(alone, support, nearest).towardsSurface, 180u);
}

TEST(Deposition, GrowthKeepsTheLayersNormalWhereTheNearestBeadLiesBeside) {
  // The same rings with the default method: the earlier ring beside a point is 90° off the
  // layer's growth direction (−normal, straight down), so V is −normal there; the first ring's
  // V (to the plate, straight down) is the paper's and is kept.
  const TriangleBvh plate(makePlate());
  std::vector<PlanPath> paths = makeRings(10.0, 5.0, 3.7, 3);
  DepositionSupport support;
  support.surface = &plate;
  support.earlierBeads = true;
  const DepositionStats stats = assignDepositionDirections(paths, support);
  EXPECT_EQ(stats.towardsSurface, 60u);
  EXPECT_EQ(stats.towardsBeads, 120u);
  EXPECT_EQ(stats.growthCorrections, 120u);
  EXPECT_EQ(stats.normalsOverruled, 0u);
  for (const PlanPath& p : paths) {
    for (const PathPoint& q : p.points) EXPECT_LT(angleDegrees(q.deposition, -Vec3::UnitZ()), 1e-9);
  }
}

/// A layer below: rings at z = 0 whose points all carry the deposition direction `v`.
std::vector<PlanPath> layerBelowWith(const Vec3& v) {
  std::vector<PlanPath> below = makeRings(0.0, 2.0, 3.7, 3);
  for (PlanPath& p : below) {
    for (PathPoint& q : p.points) q.deposition = v.normalized();
  }
  return below;
}

TEST(Deposition, GrowthTakesTheLayerBelowsDirectionOnAFragmentWithNoiseNormals) {
  // A two-point fragment 1.5 mm above the layer below, its normals pointing down (a fragment of
  // a layer surface whose orientation is noise), the nearest material a wall 1 mm beside it (the
  // paper's V: sideways, +x). The layer below grew along v: within 2·s every one of its points
  // carries v, so the weighted mean is v exactly, and V becomes v.
  const Vec3 v = Vec3(0.0, 0.2, -1.0).normalized();
  const std::vector<PlanPath> below = layerBelowWith(v);
  TriMesh wall;  // x = 1, a vertical square beside the fragment
  wall.vertices = {Vec3(1, -5, -5), Vec3(1, 5, -5), Vec3(1, 5, 5), Vec3(1, -5, 5)};
  wall.triangles = {Vec3i(0, 1, 2), Vec3i(0, 2, 3)};
  const TriangleBvh surface(wall);
  const auto fragment = [] {
    PlanPath p;
    for (const double y : {0.0, 0.4}) {
      PathPoint q;
      q.position = Vec3(0.0, y, 1.5);
      q.normal = -Vec3::UnitZ();
      p.points.push_back(q);
    }
    return std::vector<PlanPath>{p};
  };
  DepositionSupport support;
  support.surface = &surface;
  support.below = &below;
  support.belowRadius = 7.4;

  std::vector<PlanPath> growth = fragment();
  const DepositionStats stats = assignDepositionDirections(growth, support);
  EXPECT_EQ(stats.normalsOverruled, 2u);
  EXPECT_EQ(stats.growthCorrections, 2u);
  for (const PathPoint& q : growth[0].points) EXPECT_LT(angleDegrees(q.deposition, v), 1e-6);

  // The paper's method lays the torch along the layer, towards the wall.
  std::vector<PlanPath> paper = fragment();
  DepositionOptions nearest;
  nearest.method = DepositionMethod::Nearest;
  assignDepositionDirections(paper, support, nearest);
  for (const PathPoint& q : paper[0].points)
    EXPECT_LT(angleDegrees(q.deposition, Vec3::UnitX()), 1e-6);

  // Beyond the radius the layer below says nothing: the growth direction is −normal (up, as the
  // fragment's normals have it), and the wall, 90° from it, is not taken either.
  support.belowRadius = 1.0;
  std::vector<PlanPath> far = fragment();
  const DepositionStats alone = assignDepositionDirections(far, support);
  EXPECT_EQ(alone.normalsOverruled, 0u);
  for (const PathPoint& q : far[0].points)
    EXPECT_LT(angleDegrees(q.deposition, Vec3::UnitZ()), 1e-9);
}

TEST(Deposition, ParsesMethodNames) {
  EXPECT_EQ(parseDepositionMethod("growth"), DepositionMethod::Growth);
  EXPECT_EQ(parseDepositionMethod("nearest"), DepositionMethod::Nearest);
  EXPECT_STREQ(depositionMethodName(DepositionMethod::Nearest), "nearest");
  try {
    parseDepositionMethod("gradient");
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("\"gradient\""), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("growth"), std::string::npos) << e.what();
  }
}

TEST(Deposition, SphericalShellLayersPointRadiallyInward) {
  // Layer k at radius 20 + 1.5·k; the previous layer surface is the sphere one step inside.
  const Vec3 c(1.0, -2.0, 3.0);
  double worst = 0.0;
  for (int k = 1; k <= 3; ++k) {
    const double r = 20.0 + 1.5 * k;
    const TriangleBvh previous(testing::makeSphere(c, r - 1.5, 5));
    PlanPath path;
    path.closed = true;
    for (int i = 0; i < 90; ++i) {  // a tilted great circle and a few off-circle points
      const double a = 2.0 * kPi * i / 90;
      const Vec3 dir =
          Vec3(std::cos(a), std::sin(a) * std::cos(0.7), std::sin(a) * 0.64).normalized();
      PathPoint q;
      q.position = c + r * dir;
      q.normal = dir;
      path.points.push_back(q);
    }
    std::vector<PlanPath> paths = {path};
    DepositionSupport support;
    support.surface = &previous;
    assignDepositionDirections(paths, support);
    for (const PathPoint& q : paths[0].points) {
      const double angle = angleDegrees(q.deposition, (c - q.position).normalized());
      EXPECT_LT(angle, 2.0);
      worst = std::max(worst, angle);
    }
  }
  std::printf("spherical shells (exact points): largest angle to the radial direction %.3f deg\n",
              worst);
}

TEST(Deposition, ThinWallBeadLeansOnThePreviousBead) {
  // A vertical wall: the support curve is the edge at z = 0, the beads at z = 1.65, 3.3.
  Polyline edge;
  edge.closed = true;
  std::vector<PlanPath> paths = makeRings(1.65, 30.0, 0.0, 1);
  const std::vector<PlanPath> edgeRing = makeRings(0.0, 30.0, 0.0, 1);
  for (const PathPoint& q : edgeRing[0].points) edge.points.push_back(q.position);
  DepositionSupport support;
  support.curves = {edge};
  assignDepositionDirections(paths, support);
  for (const PathPoint& q : paths[0].points) {
    EXPECT_LT(angleDegrees(q.deposition, Vec3(0, 0, -1)), 1.0);
  }
}

TEST(Deposition, NoMaterialFallsBackToMinusNormal) {
  std::vector<PlanPath> paths = makeRings(1.0, 5.0, 1.0, 1);
  for (PathPoint& q : paths[0].points) q.normal = Vec3(0, 1, 0);
  const DepositionStats stats = assignDepositionDirections(paths, DepositionSupport{});
  EXPECT_EQ(stats.normalFallbacks, paths[0].points.size());
  EXPECT_EQ(paths[0].points[7].deposition, Vec3(0, -1, 0));
}

TEST(Deposition, PointOnSupportFallsBackToMinusNormal) {
  const TriangleBvh plate(makePlate());
  std::vector<PlanPath> paths = makeRings(0.0, 5.0, 1.0, 1);
  DepositionSupport support;
  support.surface = &plate;
  const DepositionStats stats = assignDepositionDirections(paths, support);
  EXPECT_EQ(stats.normalFallbacks, paths[0].points.size());
  EXPECT_EQ(paths[0].points[0].deposition, Vec3(0, 0, -1));
}

TEST(Deposition, RejectsNonFinitePoint) {
  std::vector<PlanPath> paths = makeRings(1.0, 5.0, 1.0, 1);
  paths[0].points[3].position.x() = std::nan("");
  EXPECT_THROW(assignDepositionDirections(paths, DepositionSupport{}), InvalidInput);
}

TEST(Deposition, IsDeterministic) {
  const TriangleBvh plate(makePlate());
  DepositionSupport support;
  support.surface = &plate;
  support.earlierBeads = true;
  std::vector<PlanPath> a = makeRings(6.0, 5.0, 3.0, 4), b = a;
  assignDepositionDirections(a, support);
  assignDepositionDirections(b, support);
  for (std::size_t k = 0; k < a.size(); ++k) {
    for (std::size_t i = 0; i < a[k].points.size(); ++i) {
      EXPECT_EQ(a[k].points[i].deposition, b[k].points[i].deposition);
    }
  }
}

}  // namespace
}  // namespace curvedslicer
