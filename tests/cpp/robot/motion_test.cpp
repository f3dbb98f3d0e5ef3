// Motion planning: positioner angles along paths (singular zone, branches, limits, unwrapping,
// smoothing), world poses and robot joints, unreachable points, estimates, cancellation.
#include "curvedslicer/robot/motion.hpp"
#include "common/test_constants.hpp"
#include "curvedslicer/robot/placement.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"

namespace curvedslicer {
namespace {

using testing::kDeg;
using testing::kPi;

double angleBetween(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// The plan's path points of `motion` in execution order (the MotionPlan::paths spans), without
/// the arc-off points the planner adds around them (retract, travel, approach, home).
std::vector<MotionPoint> pathPoints(const MotionPlan& motion) {
  std::vector<MotionPoint> points;
  for (const MotionPathSpan& span : motion.paths) {
    for (std::size_t k = span.begin; k < span.end; ++k) {
      EXPECT_EQ(motion.points[k].kind, MoveKind::Path) << k;
      points.push_back(motion.points[k]);
    }
  }
  return points;
}

/// A plan with one path along +x (0.5 mm spacing) whose deposition directions are `dirs`.
Plan linePlan(const std::vector<Vec3>& dirs) {
  Plan plan;
  PlanLayer layer;
  PlanPath path;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    PathPoint p;
    p.position = Vec3(-50.0 + 0.5 * static_cast<double>(i) * 100.0 / dirs.size(), 20.0, 10.0);
    p.deposition = dirs[i].normalized();
    p.normal = -p.deposition;
    path.points.push_back(p);
  }
  layer.paths.push_back(path);
  plan.layers.push_back(layer);
  return plan;
}

/// Directions along a great circle passing at `offset` from -z, t in [-span, span].
std::vector<Vec3> sweep(double offset, double span, int count) {
  std::vector<Vec3> dirs;
  for (int i = 0; i < count; ++i) {
    const double t = -span + 2.0 * span * i / (count - 1);
    dirs.push_back(std::cos(offset) * Vec3(std::sin(t), 0, -std::cos(t)) +
                   std::sin(offset) * Vec3::UnitY());
  }
  return dirs;
}

TEST(Motion, NearSingularBandBoundsTheA2StepAndTheResidual) {
  const Cell cell = defaultCell();
  for (double stepDeg : {5.0, 2.5, 1.0}) {
    for (double offsetDeg : {0.0, 0.3, 1.9, 2.9, 3.5, 5.0, 8.0}) {
      for (int count : {41, 401}) {
        SCOPED_TRACE(std::to_string(stepDeg) + " " + std::to_string(offsetDeg) + " " +
                     std::to_string(count));
        MotionOptions options;
        options.maxA2Step = stepDeg * kDeg;
        const Plan plan = linePlan(sweep(offsetDeg * kDeg, 30 * kDeg, count));
        const MotionPlan motion = planMotion(plan, cell, options);
        const std::vector<MotionPoint> points = pathPoints(motion);
        ASSERT_GE(points.size(), static_cast<std::size_t>(count));
        EXPECT_EQ(motion.nearSingularBand, options.nearSingularBand);
        if (offsetDeg < 3.0) {
          EXPECT_GT(motion.singularPoints, 0u);
        }
        int previousIndex = -1;
        for (std::size_t i = 0; i < points.size(); ++i) {
          const MotionPoint& m = points[i];
          if (i > 0) {
            EXPECT_LE(std::abs(m.a2 - points[i - 1].a2), options.maxA2Step * (1 + 1e-12))
                << "point " << i;
          }
          // inserted points carry the index of the plan point before them
          if (m.flags & kMotionInserted) {  // NOLINT(bugprone-branch-clone)
            EXPECT_EQ(m.index, previousIndex);
          } else {
            EXPECT_EQ(m.index, previousIndex + 1);
            previousIndex = m.index;
          }
          // V within the band angle of gravity everywhere (inside the band: by the tilt alone)
          EXPECT_LE(m.residual, options.nearSingularBand + 1e-9) << "point " << i;
          if (!(m.flags & (kMotionNearSingular | kMotionA2RateLimited))) {
            EXPECT_LT(m.residual, 1e-9);
          }
          const double axisAngle =
              alignWithGravity(cell.positioner, m.deposition, cell.gravity).axisAngle;
          EXPECT_EQ(axisAngle < options.nearSingularBand, (m.flags & kMotionNearSingular) != 0);
        }
        EXPECT_EQ(previousIndex, count - 1);
      }
    }
  }
}

TEST(Motion, NearDuplicatePointsAreMerged) {
  const Cell cell = defaultCell();
  Plan plan = linePlan(sweep(20 * kDeg, 1 * kDeg, 5));
  PlanPath& path = plan.layers[0].paths[0];
  PathPoint duplicate = path.points[2];
  duplicate.position.x() += 0.0014;  // the near-duplicates
  path.points.insert(path.points.begin() + 3, duplicate);
  const MotionPlan motion = planMotion(plan, cell);
  const std::vector<MotionPoint> points = pathPoints(motion);
  ASSERT_EQ(points.size(), 5u);
  EXPECT_EQ(points[3].index, 4);  // plan point 3 (the duplicate) merged into point 2
  // (after the note of the placement rule, which rests the line on the table)
  ASSERT_EQ(motion.notes.size(), 2u);
  EXPECT_NE(motion.notes[0].find("part placement rest"), std::string::npos) << motion.notes[0];
  EXPECT_NE(motion.notes[1].find("1 path point(s) closer than 0.0100 mm"), std::string::npos)
      << motion.notes[1];
  MotionOptions keep;
  keep.mergeTolerance = 0.0;
  EXPECT_EQ(pathPoints(planMotion(plan, cell, keep)).size(), 6u);
}

TEST(Motion, PassingThroughTheAxisKeepsA2AndTurnsTheTiltSmoothly) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(linePlan(sweep(0.0, 30 * kDeg, 301)), cell);
  const std::vector<MotionPoint> points = pathPoints(motion);
  double maxA1Step = 0.0, maxA2Step = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    maxA1Step = std::max(maxA1Step, std::abs(points[i].a1 - points[i - 1].a1));
    maxA2Step = std::max(maxA2Step, std::abs(points[i].a2 - points[i - 1].a2));
  }
  EXPECT_LT(maxA2Step, 1e-9);               // the branch switches instead of spinning the table
  EXPECT_LT(maxA1Step, 0.2 * kDeg + 1e-9);  // 60 deg over 300 steps
  EXPECT_NEAR(std::abs(points.front().a1), 30 * kDeg, 1e-9);
  EXPECT_NEAR(std::abs(points.back().a1), 30 * kDeg, 1e-9);
  EXPECT_LT(motion.maxResidual, 1e-9);
}

TEST(Motion, BranchPreferenceAtTheFirstPoint) {
  const Cell cell = defaultCell();
  const Plan plan = linePlan({Vec3(0, 0.5, -0.8), Vec3(0, 0.5, -0.8)});
  MotionOptions options;
  // the part as the cell places it: rest would turn a start this far from down onto the table
  options.placement = PartPlacement::Cell;
  options.preferPositiveTilt = true;
  const MotionPlan positive = planMotion(plan, cell, options);
  options.preferPositiveTilt = false;
  const MotionPlan negative = planMotion(plan, cell, options);
  const MotionPoint& positiveStart = positive.points[positive.paths.front().begin];
  const MotionPoint& negativeStart = negative.points[negative.paths.front().begin];
  EXPECT_GT(positiveStart.a1, 0.0);
  EXPECT_LT(negativeStart.a1, 0.0);
  EXPECT_NEAR(positiveStart.a1, -negativeStart.a1, 1e-12);
  EXPECT_LT(positive.maxResidual, 1e-9);
  EXPECT_LT(negative.maxResidual, 1e-9);
}

TEST(Motion, TiltLimitGivesBestFeasiblePoseAndWarning) {
  Cell cell = defaultCell();  // tilt limits +-95 deg
  const Vec3 v(0, std::sin(100 * kDeg), -std::cos(100 * kDeg));
  // the table tilted 95 deg stands nearly upright beside the vertical torch: the part sits
  // 150 mm off its surface (as on a riser), out of the torch's way
  cell.positioner.tableToPart.translation().z() = 150.0;
  MotionOptions options;
  options.placement = PartPlacement::Cell;  // (rest would turn the part so V points down)
  const MotionPlan motion = planMotion(linePlan({v, v, v}), cell, options);
  for (const MotionPoint& m : pathPoints(motion)) {
    EXPECT_TRUE(m.flags & kMotionTiltLimited);
    EXPECT_NEAR(std::abs(m.a1), 95 * kDeg, 1e-12);
    EXPECT_NEAR(m.residual, 5 * kDeg, 1e-9);
  }
  EXPECT_EQ(motion.limitedPoints, 3u);
  const auto limit = std::find_if(
      motion.warnings.begin(), motion.warnings.end(),
      [](const std::string& w) { return w.find("positioner limit") != std::string::npos; });
  ASSERT_NE(limit, motion.warnings.end());
  EXPECT_NE(limit->find("5.00 deg"), std::string::npos) << *limit;
}

TEST(Motion, RotationLimitRespected) {
  Cell cell = defaultCell();
  cell.positioner.rotation.endless = false;
  cell.positioner.rotation.limit.min = -30 * kDeg;
  cell.positioner.rotation.limit.max = 30 * kDeg;
  // needs a2 = +-90 deg (either branch) to align exactly
  const Vec3 v(1, 0, -1);
  MotionOptions options;
  options.placement = PartPlacement::Cell;  // (rest would turn the part so V points down)
  const MotionPlan motion = planMotion(linePlan({v, v}), cell, options);
  for (const MotionPoint& m : pathPoints(motion)) {
    EXPECT_GE(m.a2, -30 * kDeg - 1e-12);
    EXPECT_LE(m.a2, 30 * kDeg + 1e-12);
    EXPECT_TRUE(m.flags & kMotionRotationLimited);
    EXPECT_GT(m.residual, 1 * kDeg);
    // the best feasible pose: no other feasible rotation does better
    for (double a2 = -30 * kDeg; a2 <= 30 * kDeg; a2 += 1 * kDeg) {
      const double a1 = optimalTiltForRotation(cell.positioner, m.deposition, cell.gravity, a2);
      EXPECT_GE(computeGravityResidual(cell.positioner, m.deposition, cell.gravity, a1, a2),
                m.residual - 1e-9);
    }
  }
}

TEST(Motion, EndlessRotationUnwraps) {
  const Cell cell = defaultCell();
  std::vector<Vec3> dirs;
  const int count = 400;
  for (int i = 0; i < count; ++i) {
    const double phi = 4 * kPi * i / (count - 1);
    dirs.push_back(
        Vec3(std::sin(0.5) * std::cos(phi), std::sin(0.5) * std::sin(phi), -std::cos(0.5)));
  }
  // Two table turns within one path: with the torch x along the travel direction joint T would
  // have to turn twice as well (beyond its +-360 deg), so keep the torch x fixed in world.
  MotionOptions options;
  options.toolAlongTravel = false;
  const MotionPlan motion = planMotion(linePlan(dirs), cell, options);
  const std::vector<MotionPoint> points = pathPoints(motion);
  for (std::size_t i = 1; i < points.size(); ++i) {
    EXPECT_LT(std::abs(points[i].a2 - points[i - 1].a2), 4 * kPi / (count - 1) + 1e-9);
  }
  EXPECT_NEAR(std::abs(points.back().a2 - points.front().a2), 4 * kPi, 1e-9);
  EXPECT_LT(motion.maxResidual, 1e-9);
  // With the torch x following the travel direction joint T turns with the table. Where it
  // cannot follow within its +-360 deg (four table turns), the arm changes its IK branch within
  // the weld (the wrist flips) rather than cross a joint limit, and a warning says so.
  MotionOptions along;
  along.toolAlongTravel = true;
  const MotionPlan twoTurns = planMotion(linePlan(dirs), cell, along);
  for (const MotionPoint& m : pathPoints(twoTurns)) {
    for (int j = 0; j < 6; ++j) EXPECT_TRUE(cell.robot.joints[j].contains(m.joints[j]));
  }
  std::vector<Vec3> fourTurns;
  for (int i = 0; i < 2 * count; ++i) {
    const double phi = 8 * kPi * i / (2 * count - 1);
    fourTurns.push_back(
        Vec3(std::sin(0.5) * std::cos(phi), std::sin(0.5) * std::sin(phi), -std::cos(0.5)));
  }
  const MotionPlan four = planMotion(linePlan(fourTurns), cell, along);
  for (const MotionPoint& m : pathPoints(four)) {
    for (int j = 0; j < 6; ++j) EXPECT_TRUE(cell.robot.joints[j].contains(m.joints[j]));
  }
  bool warned = false;
  for (const std::string& w : four.warnings) {
    warned = warned || w.find(
                           "robot configuration (IK branch) changes within a weld (joint "
                           "limits)") != std::string::npos;
  }
  EXPECT_TRUE(warned);
}

TEST(Motion, SmoothingStaysWithinItsBound) {
  const Cell cell = defaultCell();
  std::vector<Vec3> dirs;
  for (int i = 0; i < 200; ++i) {
    const double tilt = (20.0 + ((i % 2) ? 3.0 : -3.0)) * kDeg;  // 6 deg zig-zag
    dirs.push_back(Vec3(0, std::sin(tilt), -std::cos(tilt)));
  }
  for (double boundDeg : {2.0, 5.0}) {
    MotionOptions options;
    options.smoothingLength = 2.0;
    options.maxSmoothingDeviation = boundDeg * kDeg;
    const MotionPlan motion = planMotion(linePlan(dirs), cell, options);
    const std::vector<MotionPoint> points = pathPoints(motion);
    double maxA1Step = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const MotionPoint& m = points[i];
      EXPECT_TRUE(m.flags & kMotionSmoothed);
      EXPECT_LE(angleBetween(m.usedDeposition, m.deposition), boundDeg * kDeg + 1e-12);
      EXPECT_NEAR(m.residual, angleBetween(m.usedDeposition, m.deposition), 1e-9);
      if (i > 10 && i + 10 < points.size()) {
        maxA1Step = std::max(maxA1Step, std::abs(m.a1 - points[i - 1].a1));
      }
    }
    // the bound keeps the used V within boundDeg of the zig-zag: steps of 6 - 2*bound degrees
    // (or ~0 once the bound exceeds the 3 deg amplitude)
    EXPECT_LE(maxA1Step, std::max(0.0, 6.0 - 2.0 * boundDeg) * kDeg + 0.05 * kDeg);
  }
}

/// Two layers of rings around the table centre with V tilted outwards by up to 40 degrees; 90
/// points per ring, so a2 steps 4 degrees (below maxA2Step: no points inserted).
Plan ringPlan() {
  Plan plan;
  for (int l = 0; l < 2; ++l) {
    PlanLayer layer;
    layer.index = l;
    for (int r = 0; r < 3; ++r) {
      PlanPath path;
      path.layer = l;
      path.index = r;
      path.closed = true;
      const double radius = 30.0 + 10.0 * r;
      const double tilt = (10.0 + 15.0 * r) * kDeg;
      for (int i = 0; i < 90; ++i) {
        const double phi = 2 * kPi * i / 90;
        PathPoint p;
        p.position = Vec3(radius * std::cos(phi), radius * std::sin(phi), 2.0 * l);
        p.deposition =
            Vec3(std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), -std::cos(tilt));
        p.normal = -p.deposition;
        path.points.push_back(p);
      }
      layer.paths.push_back(path);
    }
    plan.layers.push_back(layer);
  }
  return plan;
}

TEST(Motion, WorldPosesAndRobotJoints) {
  const Cell cell = defaultCell();
  const Plan plan = ringPlan();
  const MotionPlan motion = planMotion(plan, cell);
  ASSERT_EQ(pathPoints(motion).size(), plan.pointCount() + plan.pathCount());  // closing points
  ASSERT_EQ(motion.paths.size(), plan.pathCount());
  EXPECT_LT(motion.maxResidual, 1e-9);
  for (const MotionPathSpan& span : motion.paths) {
    const int configuration = motion.points[span.begin].configuration;
    EXPECT_TRUE(motion.points[span.begin].pathStart);
    EXPECT_FALSE(motion.points[span.begin].arcOn);
    EXPECT_TRUE(motion.points[span.end - 1].pathEnd);
    EXPECT_EQ(motion.points[span.end - 1].index, 90);  // closing point repeats point 0
    for (std::size_t k = span.begin; k < span.end; ++k) {
      const MotionPoint& m = motion.points[k];
      EXPECT_EQ(m.configuration, configuration);
      EXPECT_EQ(m.arcOn, k != span.begin);
      // torch vertical, pointing down, at the path point carried by the positioner
      EXPECT_LT(angleBetween(m.toolInWorld.linear().col(2), cell.gravity), 1e-12);
      const Vec3 world = computePartInWorld(cell.positioner, m.a1, m.a2) * m.position;
      EXPECT_LT((m.toolInWorld.translation() - world).norm(), 1e-9);
      EXPECT_LT((m.toolInPart.translation() - m.position).norm(), 1e-9);
      const Pose viaTable = computeTableInWorld(cell.positioner, m.a1, m.a2) * m.toolInTable;
      EXPECT_TRUE(viaTable.isApprox(m.toolInWorld, 1e-12));
      // the round torch's x axis fixed in the world within the weld (toolAlongTravel off)
      EXPECT_LT(
          (m.toolInWorld.linear().col(0) - motion.points[span.begin].toolInWorld.linear().col(0))
              .norm(),
          1e-12);
      // robot joints reproduce the TCP pose, within limits
      const Pose tcp = computeFlangePose(cell.robot, m.joints) * cell.tool.tcp;
      EXPECT_LT((tcp.translation() - m.toolInRobotBase.translation()).norm(), 1e-6);
      EXPECT_LT(Eigen::AngleAxisd(tcp.linear().transpose() * m.toolInRobotBase.linear()).angle(),
                1e-9);
      for (int j = 0; j < 6; ++j) EXPECT_TRUE(cell.robot.joints[j].contains(m.joints[j]));
      EXPECT_FALSE(m.flags & kMotionRobotLimit);
      // the weld's configuration holds every point: J4 sits on 0 (vertical torch) and J6 is
      // centred in a quadrant away from +-180 deg
      EXPECT_TRUE(isWithinConfiguration(m.joints, span.configuration)) << k;
      EXPECT_GT(std::abs(std::abs(std::remainder(m.joints[5], 2 * kPi)) - kPi), 30 * kDeg);
      // within a path the joints move continuously (no 2*pi jumps)
      if (k > span.begin) {
        for (int j = 0; j < 6; ++j) {
          EXPECT_LT(std::abs(m.joints[j] - motion.points[k - 1].joints[j]), 30 * kDeg);
        }
      }
    }
  }
}

TEST(Motion, FlatRingsRecentreTheWrist) {
  // V = -z everywhere (singular: the table holds still) and the torch x follows the travel
  // direction, so joint T turns a full turn per ring; the arc-off move between rings must bring
  // it back instead of running into the +-360 deg limit.
  const Cell cell = defaultCell();
  Plan plan;
  for (int l = 0; l < 4; ++l) {
    PlanLayer layer;
    PlanPath path;
    path.closed = true;
    for (int i = 0; i < 72; ++i) {
      const double phi = 2 * kPi * i / 72;
      PathPoint p;
      p.position = Vec3(40 * std::cos(phi), 40 * std::sin(phi), 2.0 * l);
      path.points.push_back(p);
    }
    layer.paths.push_back(path);
    plan.layers.push_back(layer);
  }
  MotionOptions along;
  along.toolAlongTravel = true;
  const MotionPlan motion = planMotion(plan, cell, along);
  EXPECT_EQ(motion.singularPoints, pathPoints(motion).size());
  for (const MotionPathSpan& span : motion.paths) {
    const double turn = motion.points[span.end - 1].joints[5] - motion.points[span.begin].joints[5];
    EXPECT_NEAR(std::abs(turn), 2 * kPi, 0.2);
    for (std::size_t k = span.begin; k < span.end; ++k) {
      for (int j = 0; j < 6; ++j)
        EXPECT_TRUE(cell.robot.joints[j].contains(motion.points[k].joints[j]));
      EXPECT_FALSE(motion.points[k].flags & kMotionRobotLimit);
    }
  }
}

TEST(Motion, ClosedPathSmoothingWraps) {
  const Cell cell = defaultCell();
  Plan plan = ringPlan();
  MotionOptions options;
  options.smoothingLength = 3.0;
  const MotionPlan motion = planMotion(plan, cell, options);
  for (const MotionPathSpan& span : motion.paths) {
    const MotionPoint& first = motion.points[span.begin];
    const MotionPoint& closing = motion.points[span.end - 1];
    EXPECT_TRUE(first.usedDeposition.isApprox(closing.usedDeposition, 1e-15));
    // a rotationally symmetric ring: smoothing changes every V by the same small angle
    EXPECT_NEAR(angleBetween(first.usedDeposition, first.deposition),
                angleBetween(motion.points[span.begin + 45].usedDeposition,
                             motion.points[span.begin + 45].deposition),
                1e-9);
  }
}

TEST(Motion, UnreachablePointsAreNamed) {
  Cell cell = defaultCell();
  cell.positioner.base = makePose(Vec3(4000, 0, 0), Vec3::Zero());
  const Plan plan = ringPlan();
  try {
    planMotion(plan, cell);
    ADD_FAILURE() << "unreachable plan accepted";
  } catch (const InvalidInput& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("layer 0 path 0 point 0"), std::string::npos) << message;
    EXPECT_NE(message.find("misses by"), std::string::npos) << message;
    EXPECT_NE(message.find(std::to_string(plan.pointCount() + plan.pathCount()) + " point(s)"),
              std::string::npos)
        << message;
  }
  MotionOptions options;
  options.unreachable = UnreachablePolicy::Warn;
  const MotionPlan motion = planMotion(plan, cell, options);
  ASSERT_FALSE(motion.warnings.empty());
  EXPECT_NE(motion.warnings[0].find("misses by"), std::string::npos);
  for (const MotionPoint& m : pathPoints(motion)) EXPECT_TRUE(m.flags & kMotionRobotLimit);
}

TEST(Motion, JointLimitCrossingIsNamed) {
  Cell cell = defaultCell();
  cell.robot.joints[0].min = -5 * kDeg;  // S cannot turn towards negative y
  cell.robot.joints[0].max = 5 * kDeg;
  cell.positioner.base = makePose(Vec3(800, -700, 0), Vec3::Zero());
  try {
    planMotion(ringPlan(), cell);
    ADD_FAILURE() << "joint limit crossing accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("joint 1 at"), std::string::npos) << e.what();
  }
}

TEST(Motion, Estimates) {
  Cell cell = defaultCell();
  cell.process.weldSpeed = 10.0;
  cell.process.travelSpeed = 100.0;
  cell.process.wireFeed = 6.0;  // m/min = 100 mm/s
  cell.process.wireDiameter = 1.2;
  cell.process.wireDensity = 8.0;
  cell.process.layerDwell = 30.0;
  cell.process.pathDwell = 2.0;
  Plan plan;
  PlanLayer layer;
  for (int p = 0; p < 2; ++p) {
    PlanPath path;
    for (int i = 0; i <= 10; ++i) {
      PathPoint pt;
      pt.position = Vec3(10.0 * i, 5.0 * p, 0);
      path.points.push_back(pt);
    }
    layer.paths.push_back(path);
  }
  plan.layers.push_back(layer);
  // without the home moves the arc-off moves are: the approach onto path 0, the retract from it,
  // the travel to above path 1, the approach onto it and the retract at the end; retract and
  // approach go along the normal to the clearance above the bead top (default plan parameters:
  // bead radius 1 mm)
  MotionOptions options;
  options.addHome = false;
  const MotionPlan motion = planMotion(plan, cell, options);
  const double lift = 1.0 + options.clearance;
  const MotionEstimate& e = motion.total;
  EXPECT_NEAR(e.beadLength, 200.0, 1e-9);
  EXPECT_NEAR(e.arcTime, 20.0, 1e-9);
  EXPECT_NEAR(e.travelLength, 4 * lift + std::hypot(100.0, 5.0), 1e-9);
  EXPECT_NEAR(e.travelTime, (4 * lift + std::hypot(100.0, 5.0)) / 100.0, 1e-9);
  EXPECT_NEAR(e.dwellTime, 30.0 + 2 * 2.0, 1e-12);
  EXPECT_NEAR(e.wireLength, 2000.0, 1e-9);
  const double volume = kPi * 0.36 * 2000.0;
  EXPECT_NEAR(e.depositedVolume, volume, 1e-9);
  EXPECT_NEAR(e.depositedMass, volume * 8.0 / 1000.0, 1e-9);
  EXPECT_NEAR(e.totalTime, e.arcTime + e.travelTime + e.dwellTime, 1e-12);
  ASSERT_EQ(motion.layers.size(), 1u);
  EXPECT_NEAR(motion.layers[0].depositedMass, e.depositedMass, 1e-12);
  EXPECT_EQ(e.paths, 2u);
  EXPECT_EQ(e.points, 22u);
  // the home moves at the start and the end add travel, not arc time
  const MotionPlan withHome = planMotion(plan, cell);
  EXPECT_GT(withHome.total.travelLength, e.travelLength + 1.0);
  EXPECT_NEAR(withHome.total.arcTime, e.arcTime, 1e-9);
}

TEST(Motion, BadInputNamesTheProblem) {
  const Cell cell = defaultCell();
  Plan plan = linePlan({Vec3(0, 0, -1), Vec3(0, 0, -1)});
  plan.layers[0].paths[0].points.pop_back();
  try {
    planMotion(plan, cell);
    ADD_FAILURE();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("layer 0 path 0"), std::string::npos) << e.what();
  }
  plan = linePlan({Vec3(0, 0, -1), Vec3(0, 0, 0)});
  EXPECT_THROW(planMotion(plan, cell), InvalidInput);
  MotionOptions options;
  options.maxA2Step = 0.0;
  EXPECT_THROW(planMotion(linePlan({Vec3(0, 0, -1), Vec3(0, 0, -1)}), cell, options), InvalidInput);
  for (double band : {0.0, 50 * kDeg}) {
    MotionOptions bad;
    bad.nearSingularBand = band;
    try {
      planMotion(linePlan({Vec3(0, 0, -1), Vec3(0, 0, -1)}), cell, bad);
      ADD_FAILURE() << band;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("near-singular band must be in (0, 45) degrees"),
                std::string::npos)
          << e.what();
    }
  }
  MotionOptions negativeMerge;
  negativeMerge.mergeTolerance = -0.1;
  EXPECT_THROW(planMotion(linePlan({Vec3(0, 0, -1), Vec3(0, 0, -1)}), cell, negativeMerge),
               InvalidInput);
  Cell bad = cell;
  bad.process.wireDiameter = 0.0;
  EXPECT_THROW(planMotion(linePlan({Vec3(0, 0, -1), Vec3(0, 0, -1)}), bad), InvalidInput);
}

TEST(Motion, UnreachablePolicyNamesRoundTrip) {
  for (UnreachablePolicy p : {UnreachablePolicy::Throw, UnreachablePolicy::Warn}) {
    EXPECT_EQ(parseUnreachablePolicy(toString(p)), p);
  }
  EXPECT_EQ(toString(MotionOptions{}.unreachable), "throw");
  EXPECT_THROW(parseUnreachablePolicy("ignore"), InvalidInput);
}

TEST(Motion, CancellationAndDeterminism) {
  const Cell cell = defaultCell();
  const Plan plan = ringPlan();
  int calls = 0;
  const Progress cancel([&](double, std::string_view) { return ++calls < 3; });
  EXPECT_THROW(planMotion(plan, cell, {}, cancel), Cancelled);
  double last = -1.0;
  const Progress watch([&](double f, std::string_view) {
    EXPECT_GE(f, last);
    last = f;
    return true;
  });
  const MotionPlan a = planMotion(plan, cell, {}, watch);
  EXPECT_DOUBLE_EQ(last, 1.0);
  const MotionPlan b = planMotion(plan, cell);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].a1, b.points[i].a1);
    EXPECT_EQ(a.points[i].a2, b.points[i].a2);
    EXPECT_EQ(a.points[i].joints, b.points[i].joints);
  }
}

TEST(Motion, Pulses) {
  const Cell cell = defaultCell();
  EXPECT_EQ(positionerPulses(cell.positioner.tilt, 1.0 * kDeg), 1994);
  EXPECT_EQ(positionerPulses(cell.positioner.rotation, -10.0 * kDeg), -13767);
  PositionerAxis reversed = cell.positioner.tilt;
  reversed.sign = -1;
  EXPECT_EQ(positionerPulses(reversed, 1.0 * kDeg), -1994);
  EXPECT_THROW(robotPulses(cell.robot, JointVector{}), InvalidInput);
  RobotDescription robot = cell.robot;
  robot.pulsesPerDegree = {1000, 1000, 1000, 500, 500, 250};
  const auto pulses = robotPulses(robot, {1 * kDeg, -2 * kDeg, 0, 0, 0, 4 * kDeg});
  EXPECT_EQ(pulses[0], 1000);
  EXPECT_EQ(pulses[1], -2000);
  EXPECT_EQ(pulses[5], 1000);
}

}  // namespace
}  // namespace curvedslicer
