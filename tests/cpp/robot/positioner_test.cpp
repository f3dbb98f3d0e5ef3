// Positioner: eq. 16 closed form (both branches) and forward/inverse kinematics.
#include "common/test_constants.hpp"
#include "curvedslicer/robot/positioner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "curvedslicer/robot/cell.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;
using testing::kDeg;

Vec3 randomDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Vec3 v(normal(rng), normal(rng), normal(rng));
  return v.normalized();
}

/// A positioner with general axes: tilt axis not horizontal, rotation axis not perpendicular to
/// it, a rotated base and a table-to-part transform.
PositionerDescription skewedPositioner() {
  PositionerDescription p = defaultCell().positioner;
  p.base = makePose(Vec3(900, 300, 50), Vec3(0.05, -0.03, 0.7));
  p.tiltAxisDirection = Vec3(1, 0.2, 0.1).normalized();
  p.rotationAxisDirection = Vec3(0.15, -0.1, 1).normalized();
  p.tableToPart = makePose(Vec3(10, -5, 20), Vec3(0.2, 0.1, -0.4));
  return p;
}

TEST(Positioner, RandomDirectionsTurnOntoGravity) {
  const Cell cell = defaultCell();
  std::mt19937_64 rng(20240521);
  const double zone = 2.0 * kDeg;
  int checked = 0;
  double worst = 0.0;
  for (int i = 0; i < 10000; ++i) {
    const Vec3 v = randomDirection(rng);
    const GravityAlignment a = alignWithGravity(cell.positioner, v, cell.gravity);
    if (a.axisAngle < zone) continue;
    ASSERT_TRUE(a.feasible);
    for (const PositionerAngles& b : a.branches) {
      const double r = computeGravityResidual(cell.positioner, v, cell.gravity, b.a1, b.a2);
      worst = std::max(worst, r);
      // the transformed V, computed independently through the part pose in world
      const Vec3 turned = computePartInWorld(cell.positioner, b.a1, b.a2).linear() * v;
      worst =
          std::max(worst, std::atan2(turned.cross(cell.gravity).norm(), turned.dot(cell.gravity)));
    }
    ++checked;
  }
  EXPECT_GT(checked, 9900);
  EXPECT_LT(worst, 1e-9);
}

TEST(Positioner, RandomDirectionsGeneralAxes) {
  const PositionerDescription p = skewedPositioner();
  const Vec3 gravity = Vec3(0.02, -0.01, -1).normalized();
  std::mt19937_64 rng(7);
  int feasible = 0;
  double worst = 0.0;
  for (int i = 0; i < 10000; ++i) {
    const Vec3 v = randomDirection(rng);
    const GravityAlignment a = alignWithGravity(p, v, gravity);
    if (a.axisAngle < 2.0 * kDeg || !a.feasible) continue;
    ++feasible;
    for (const PositionerAngles& b : a.branches) {
      worst = std::max(worst, computeGravityResidual(p, v, gravity, b.a1, b.a2));
    }
  }
  EXPECT_GT(feasible, 5000);
  EXPECT_LT(worst, 1e-9);
}

TEST(Positioner, UsualCellMatchesTheRotateThenTiltConstruction) {
  // Tilt about x, rotation about the table z, gravity -z: after the rotation V lies in the plane
  // normal to the tilt axis (eq. 16, first condition), and |a1| is the angle of V to -z.
  const Cell cell = defaultCell();
  const Vec3 v = Vec3(0.3, -0.5, -0.6).normalized();
  const GravityAlignment a = alignWithGravity(cell.positioner, v, cell.gravity);
  for (const PositionerAngles& b : a.branches) {
    const Vec3 rotated = Eigen::AngleAxisd(b.a2, Vec3::UnitZ()) * v;
    EXPECT_NEAR(rotated.x(), 0.0, 1e-12);
    EXPECT_NEAR(std::abs(b.a1), std::acos(-v.z()), 1e-12);
  }
  // the two branches: (a1, a2) and (-a1, a2 + pi)
  EXPECT_NEAR(a.branches[0].a1, -a.branches[1].a1, 1e-12);
  EXPECT_NEAR(std::abs(std::remainder(a.branches[0].a2 - a.branches[1].a2 - kPi, 2 * kPi)), 0.0,
              1e-12);
}

TEST(Positioner, AxisAngleMeasuresTheSingularZone) {
  const Cell cell = defaultCell();
  const Vec3 down = -Vec3::UnitZ();
  EXPECT_NEAR(alignWithGravity(cell.positioner, down, cell.gravity).axisAngle, 0.0, 1e-15);
  const Vec3 tilted = Vec3(std::sin(1.0 * kDeg), 0, -std::cos(1.0 * kDeg));
  EXPECT_NEAR(alignWithGravity(cell.positioner, tilted, cell.gravity).axisAngle, 1.0 * kDeg, 1e-12);
  const Vec3 up = Vec3(0, std::sin(0.5 * kDeg), std::cos(0.5 * kDeg));
  EXPECT_NEAR(alignWithGravity(cell.positioner, up, cell.gravity).axisAngle, 0.5 * kDeg, 1e-12);
}

TEST(Positioner, ForwardInverseRoundTrip) {
  for (const PositionerDescription& p : {defaultCell().positioner, skewedPositioner()}) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> tilt(-95 * kDeg, 95 * kDeg), rot(-kPi + 1e-9, kPi);
    for (int i = 0; i < 2000; ++i) {
      const double a1 = tilt(rng), a2 = rot(rng);
      const Pose pose = computePartInPositionerBase(p, a1, a2);
      const PositionerAngles back = solvePositionerPose(p, pose);
      EXPECT_NEAR(back.a1, a1, 1e-9);
      EXPECT_NEAR(std::remainder(back.a2 - a2, 2 * kPi), 0.0, 1e-9);
      const Pose again = computePartInPositionerBase(p, back.a1, back.a2);
      const Vec3 point(123.0, -45.0, 67.0);
      EXPECT_LT((again * point - pose * point).norm(), 1e-6);
    }
  }
}

TEST(Positioner, ZeroPoseAndAxes) {
  const PositionerDescription p = defaultCell().positioner;
  const Pose zero = computePartInWorld(p, 0, 0);
  EXPECT_TRUE(zero.translation().isApprox(Vec3(1100, 0, 530), 1e-12));
  EXPECT_TRUE(zero.linear().isApprox(Mat3::Identity(), 1e-12));
  // points on the tilt axis do not move with a1; the table origin turns about it
  const Pose tilted = computePartInPositionerBase(p, 0.5, 0.0);
  const Vec3 onAxis = tilted.inverse() * Vec3(250, 0, 380);
  EXPECT_TRUE((computePartInPositionerBase(p, 0, 0) * onAxis).isApprox(Vec3(250, 0, 380), 1e-12));
  EXPECT_NEAR((tilted.translation() - Vec3(0, 0, 380)).norm(), 150.0, 1e-9);
  EXPECT_NEAR(tilted.translation().y(), -150.0 * std::sin(0.5), 1e-9);  // right-handed about +x
  // the rotation turns the part about the table axis
  const Pose turned = computePartInPositionerBase(p, 0.0, kPi / 2);
  EXPECT_TRUE((turned.linear() * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-12));
}

TEST(Positioner, OptimalAnglesForAFixedAxis) {
  const Cell cell = defaultCell();
  const Vec3 v = Vec3(0.2, 0.7, -0.4).normalized();
  const GravityAlignment a = alignWithGravity(cell.positioner, v, cell.gravity);
  const PositionerAngles b = a.branches[0];
  EXPECT_NEAR(optimalTiltForRotation(cell.positioner, v, cell.gravity, b.a2), b.a1, 1e-12);
  EXPECT_NEAR(optimalRotationForTilt(cell.positioner, v, cell.gravity, b.a1), b.a2, 1e-12);
  // for a rotation off the solution, the optimal tilt is no worse than nearby tilts
  const double a2 = b.a2 + 0.3;
  const double best = optimalTiltForRotation(cell.positioner, v, cell.gravity, a2);
  const double r = computeGravityResidual(cell.positioner, v, cell.gravity, best, a2);
  for (double d : {-0.01, 0.01}) {
    EXPECT_LE(r, computeGravityResidual(cell.positioner, v, cell.gravity, best + d, a2) + 1e-15);
  }
}

TEST(Positioner, UnwrapNear) {
  EXPECT_NEAR(unwrapNear(0.1, 6.2), 0.1 + 2 * kPi, 1e-15);
  EXPECT_NEAR(unwrapNear(-3.0, 3.0), -3.0 + 2 * kPi, 1e-15);
  EXPECT_NEAR(unwrapNear(1.0, 1.2), 1.0, 1e-15);
}

}  // namespace
}  // namespace curvedslicer
