// Six-axis robot: forward kinematics against hand-computed poses, inverse kinematics round trip
// (all 8 solutions), wrist singularity and the reach check.
#include "common/test_constants.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "curvedslicer/robot/cell.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;
using testing::kDeg;

double angleDistance(double a, double b) {
  return std::abs(std::remainder(a - b, 2 * kPi));
}

double rotationError(const Mat3& a, const Mat3& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

RobotDescription offsetRobot() {
  // lateral offset and joint offsets exercise every parameter
  RobotDescription r = defaultCell().robot;
  r.kinematics.b = 35.0;
  r.jointOffsets = {0.1, -0.2, 0.3, 0.0, 0.15, -0.4};
  r.jointSigns = {1, -1, 1, -1, 1, 1};
  for (auto& j : r.joints) j = JointLimit{-kPi, kPi, 3.0};
  return r;
}

TEST(RobotKinematics, ZeroPose) {
  const RobotDescription r = defaultCell().robot;
  const Pose flange = computeFlangePose(r, JointVector{});
  // wrist centre (a1 + c3, 0, c1 + c2 + a2), flange c4 further along +x, flange z along +x; the
  // HP20D's T offset of 180 deg makes the flange Yaskawa's, x up at the controller's zero
  EXPECT_TRUE(flange.translation().isApprox(Vec3(150 + 795 + 100, 0, 505 + 760 + 140), 1e-12));
  EXPECT_TRUE(flange.linear().col(2).isApprox(Vec3::UnitX(), 1e-12));
  EXPECT_TRUE(flange.linear().col(0).isApprox(Vec3::UnitZ(), 1e-12));
}

TEST(RobotKinematics, ArmPointsZeroPose) {
  const RobotDescription r = defaultCell().robot;
  const ArmPoints p = computeArmPoints(r, JointVector{});
  // shoulder (a1, 0, c1), elbow c2 above it, wrist centre (a1 + c3, 0, c1 + c2 + a2), flange c4
  // further along +x (the cell's numbers: a1 150, c1 505, c2 760, a2 140, c3 795, c4 100)
  EXPECT_TRUE(p.base.isApprox(Vec3::Zero()));
  EXPECT_TRUE(p.shoulder.isApprox(Vec3(150, 0, 505), 1e-12));
  EXPECT_TRUE(p.elbow.isApprox(Vec3(150, 0, 505 + 760), 1e-12));
  EXPECT_TRUE(p.wrist.isApprox(Vec3(150 + 795, 0, 505 + 760 + 140), 1e-12));
  EXPECT_TRUE(p.flange.isApprox(Vec3(150 + 795 + 100, 0, 505 + 760 + 140), 1e-12));
}

TEST(RobotKinematics, ArmPointsFollowTheJoints) {
  const RobotDescription r = offsetRobot();
  const RobotKinematics& k = r.kinematics;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  for (int trial = 0; trial < 50; ++trial) {
    JointVector q;
    for (double& v : q) v = angle(rng);
    const ArmPoints p = computeArmPoints(r, q);
    const Pose flange = computeFlangePose(r, q);
    EXPECT_LT((p.flange - flange.translation()).norm(), 1e-9);
    // link lengths are fixed: upper arm c2, forearm hypot(c3, a2), wrist to flange c4
    EXPECT_NEAR((p.elbow - p.shoulder).norm(), k.c2, 1e-9);
    EXPECT_NEAR((p.wrist - p.elbow).norm(), std::hypot(k.c3, k.a2), 1e-9);
    EXPECT_NEAR((p.flange - p.wrist).norm(), k.c4, 1e-9);
    // the wrist centre lies c4 behind the flange along the flange's z axis
    EXPECT_LT((p.wrist - (flange.translation() - k.c4 * flange.linear().col(2))).norm(), 1e-9);
    // the shoulder turns with joint 1 only, at height c1
    EXPECT_NEAR(p.shoulder.z(), k.c1, 1e-9);
    EXPECT_NEAR(std::hypot(p.shoulder.x(), p.shoulder.y()), std::hypot(k.a1, k.b), 1e-9);
  }
}

TEST(RobotKinematics, ControllerDirections) {
  const RobotDescription r = defaultCell().robot;
  const Vec3 zero = computeFlangePose(r, JointVector{}).translation();
  // S positive turns the arm counter-clockwise seen from above
  EXPECT_GT(computeFlangePose(r, {0.1, 0, 0, 0, 0, 0}).translation().y(), zero.y());
  // L positive leans the upper arm forward: the wrist moves forward and down
  EXPECT_GT(computeFlangePose(r, {0, 0.1, 0, 0, 0, 0}).translation().x(), zero.x());
  // U positive raises the forearm
  EXPECT_GT(computeFlangePose(r, {0, 0, 0.1, 0, 0, 0}).translation().z(), zero.z());
  // B positive raises the flange
  EXPECT_GT(computeFlangePose(r, {0, 0, 0, 0, 0.1, 0}).translation().z(), zero.z());
  // torch pointing down: B = -90 deg with the forearm horizontal
  const Pose down = computeFlangePose(r, {0, 0, 0, 0, -kPi / 2, 0});
  EXPECT_TRUE(down.linear().col(2).isApprox(-Vec3::UnitZ(), 1e-12));
}

TEST(RobotKinematics, ForwardInverseRoundTrip) {
  for (const RobotDescription& r : {defaultCell().robot, offsetRobot()}) {
    std::mt19937_64 rng(11);
    int matched = 0, poses = 0;
    double worstPosition = 0.0, worstRotation = 0.0, worstJoint = 0.0;
    for (int i = 0; i < 3000; ++i) {
      JointVector q;
      for (int j = 0; j < 6; ++j) {
        const double lo = std::max(r.joints[j].min, -kPi + 1e-3);
        const double hi = std::min(r.joints[j].max, kPi - 1e-3);
        q[j] = std::uniform_real_distribution<double>(lo, hi)(rng);
      }
      const JointVector model{0, 0, 0, 0, r.jointSigns[4] * q[4] + r.jointOffsets[4], 0};
      if (std::abs(std::sin(model[4])) < 1e-3) continue;  // wrist singular: tested below
      const Pose flange = computeFlangePose(r, q);
      const IkResult ik = solveInverseKinematics(r, flange);
      ASSERT_FALSE(ik.solutions.empty());
      EXPECT_EQ(ik.reachShortfall, 0.0);
      ++poses;
      double best = kInf;
      for (const IkSolution& s : ik.solutions) {
        const Pose back = computeFlangePose(r, s.joints);
        worstPosition = std::max(worstPosition, (back.translation() - flange.translation()).norm());
        worstRotation = std::max(worstRotation, rotationError(back.linear(), flange.linear()));
        double d = 0.0;
        for (int j = 0; j < 6; ++j) d = std::max(d, angleDistance(s.joints[j], q[j]));
        best = std::min(best, d);
      }
      worstJoint = std::max(worstJoint, best);
      if (best < 1e-9) ++matched;
    }
    EXPECT_GT(poses, 2500);
    EXPECT_EQ(matched, poses);
    EXPECT_LT(worstPosition, 1e-6);
    EXPECT_LT(worstRotation, 1e-9);
    EXPECT_LT(worstJoint, 1e-9);
  }
}

TEST(RobotKinematics, EightDistinctSolutions) {
  const RobotDescription r = defaultCell().robot;
  const Pose flange = computeFlangePose(r, {0.3, 0.2, -0.1, 0.4, -1.0, 0.5});
  const IkResult ik = solveInverseKinematics(r, flange);
  ASSERT_EQ(ik.solutions.size(), 8u);
  std::set<int> configurations;
  for (const IkSolution& s : ik.solutions) configurations.insert(s.configuration);
  EXPECT_EQ(configurations.size(), 8u);
  // the original joints are configuration 0 (front, elbow up, no flip) and within limits
  EXPECT_EQ(ik.solutions[0].configuration, 0);
  EXPECT_TRUE(ik.solutions[0].withinLimits);
  EXPECT_NEAR(ik.solutions[0].joints[4], -1.0, 1e-9);
}

TEST(RobotKinematics, WristSingularKeepsReference) {
  const RobotDescription r = defaultCell().robot;
  const Pose flange = computeFlangePose(r, {0.2, 0.1, 0.2, 0.7, 0.0, -0.3});
  const IkResult ik = solveInverseKinematics(r, flange, 0.7);
  ASSERT_FALSE(ik.solutions.empty());
  bool found = false;
  for (const IkSolution& s : ik.solutions) {
    const Pose back = computeFlangePose(r, s.joints);
    EXPECT_LT((back.translation() - flange.translation()).norm(), 1e-6);
    EXPECT_LT(rotationError(back.linear(), flange.linear()), 1e-9);
    if (s.configuration == 0) {
      EXPECT_TRUE(s.wristSingular);
      EXPECT_NEAR(s.joints[3], 0.7, 1e-9);
      EXPECT_NEAR(s.joints[5], -0.3, 1e-9);
      found = true;
    }
  }
  EXPECT_TRUE(found);
}

TEST(RobotKinematics, ReachShortfall) {
  const RobotDescription r = defaultCell().robot;
  // wrist centre 2500 mm in front at shoulder height: beyond c2 + hypot(c3, a2) from joint 2
  Pose flange = Pose::Identity();
  flange.linear() = Eigen::AngleAxisd(kPi / 2, Vec3::UnitY()).toRotationMatrix();  // z along +x
  flange.translation() = Vec3(2500 + 100, 0, 505);
  const IkResult ik = solveInverseKinematics(r, flange);
  EXPECT_TRUE(ik.solutions.empty());
  const double reach = 760 + std::hypot(795.0, 140.0);
  EXPECT_NEAR(ik.reachShortfall, (2500 - 150) - reach, 1e-9);
}

TEST(RobotKinematics, UnwrapJointsIntoLimits) {
  const RobotDescription r = defaultCell().robot;  // T: +-360 deg
  JointVector q{0, 0, 0, 0, 0, 3.0};
  EXPECT_TRUE(unwrapJoints(r, q, {0, 0, 0, 0, 0, 3.0 - 2 * kPi - 0.1}));
  EXPECT_NEAR(q[5], 3.0 - 2 * kPi, 1e-12);
  JointVector bad{0, 0, 0, 0, 170 * kDeg, 0};  // B limit 125 deg
  EXPECT_FALSE(unwrapJoints(r, bad, JointVector{}));
}

}  // namespace
}  // namespace curvedslicer
