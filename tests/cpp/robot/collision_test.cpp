// Collision check (robot/collision): a torch that must hit a tall wall deposited next to its path
// fails with a message naming the move and what it hits, and passes with allowCollisions
// listing the moves; the positioner table; a free plan has no collisions; the envelope and the
// bead radius from the plan; bad envelopes.
#include "curvedslicer/robot/collision.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <string_view>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "curvedslicer/robot/travel.hpp"
#include "robot_test_support.hpp"

namespace curvedslicer {
namespace {

using robot_test::distanceToSegment;
using robot_test::straightPath;

/// A cylinder envelope (one capsule in the check: radius 10 mm from the nozzle 15 mm above the
/// TCP, 300 mm long) on a 250 x 40 mm table: the shape the brute-force distances below model.
CollisionGeometry capsuleGeometry() {
  CollisionGeometry g;
  g.torch.stickout = 15.0;
  g.torch.radius = 10.0;
  g.torch.topRadius = 10.0;
  g.torch.length = 300.0;
  g.table.tableRadius = 250.0;
  g.table.tableThickness = 40.0;
  return g;
}

/// A wall along x at y = 0, `layers` layers of 1.5 mm, then one more layer with a path at
/// height 1.5 mm along the wall at y = `offset`.
Plan wallAndPathPlan(int layers, double offset) {
  Plan plan;
  plan.parameters.beadSpacing = 3.7;  // bead radius 1.85 mm
  plan.parameters.layerThickness = 1.5;
  for (int l = 0; l <= layers; ++l) {
    PlanLayer layer;
    layer.index = l;
    if (l < layers) {
      const double z = 1.5 * (l + 1);
      layer.paths.push_back(straightPath(Vec3(-40, 0, z), Vec3(40, 0, z)));
    } else {
      layer.paths.push_back(straightPath(Vec3(-20, offset, 1.5), Vec3(20, offset, 1.5)));
    }
    layer.paths.back().layer = l;
    plan.layers.push_back(layer);
  }
  return plan;
}

/// The default cell without the gravity deviation window: 8 mm beside the wall the 15° torch
/// window alone does not clear the torch, which then stays along gravity (the collision the
/// tests below detect and report).
Cell cellWithoutGravityDeviation() {
  Cell cell = defaultCell();
  cell.process.maxGravityDeviation = 0.0;
  return cell;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(Collision, TorchAgainstATallWallNamesTheMove) {
  // torch radius 10 mm, wall bead radius 1.85 mm: at 8 mm from the wall the nozzle clears the
  // deposit below it but the torch body hits the 45 mm wall
  const Plan plan = wallAndPathPlan(30, 8.0);
  try {
    planMotion(plan, cellWithoutGravityDeviation());
    FAIL() << "no collision reported";
  } catch (const InvalidInput& e) {
    const std::string text = e.what();
    EXPECT_TRUE(contains(text, "torch collides on")) << text;
    EXPECT_TRUE(contains(text, "layer 30 path 0 point 1 (weld move): torch vs deposit of layer"))
        << text;
    EXPECT_TRUE(contains(text, "--allow-collisions")) << text;
  }
}

/// Radius of the lowest of the four capsules that cover the cell's torch cone: the cone's
/// largest radius over the lowest quarter of its length (collision.hpp).
double lowestCapsuleRadius(const TorchEnvelope& torch) {
  return torch.radius + 0.25 * (torch.topRadius - torch.radius);
}

TEST(Collision, AllowCollisionsListsTheMoves) {
  const Plan plan = wallAndPathPlan(30, 8.0);
  MotionOptions options;
  options.allowCollisions = true;
  const Cell cell = cellWithoutGravityDeviation();
  const MotionPlan motion = planMotion(plan, cell, options);
  // the default cell's cone (12.5 -> 25 mm over 385 mm): the lowest capsule, 15 to 111.25 mm
  // above the TCP, is the only one reaching down to the 45 mm wall
  const double torchRadius = lowestCapsuleRadius(cell.tool.envelope);
  ASSERT_DOUBLE_EQ(torchRadius, 15.625);
  ASSERT_FALSE(motion.collisions.empty());
  const MotionPathSpan& weld = motion.paths.back();
  std::size_t weldCollisions = 0;
  for (const CollisionReport& c : motion.collisions) {
    ASSERT_LT(c.point, motion.points.size());
    const MotionPoint& m = motion.points[c.point];
    EXPECT_TRUE(m.flags & kMotionCollision);
    EXPECT_TRUE(contains(c.what, "torch vs deposit of layer")) << c.what;
    // penetration: torch radius + bead radius - 8 mm axis distance (the weld moves: exactly)
    EXPECT_GT(c.depth, 0.0);
    EXPECT_LE(c.depth, torchRadius + 1.85 - 8.0 + 1e-6);
    if (c.point > weld.begin && c.point < weld.end) {
      ++weldCollisions;
      EXPECT_NEAR(c.depth, torchRadius + 1.85 - 8.0, 1e-6) << describeMove(motion, c.point);
    }
  }
  // every weld move of the path along the wall collides (the wall is longer than the path)
  EXPECT_EQ(weldCollisions, weld.end - weld.begin - 1);
  std::size_t flagged = 0;
  for (const MotionPoint& m : motion.points) flagged += (m.flags & kMotionCollision) != 0;
  EXPECT_EQ(flagged, motion.collisions.size());
  const bool warned =
      std::any_of(motion.warnings.begin(), motion.warnings.end(),
                  [](const std::string& w) { return contains(w, "torch collides"); });
  EXPECT_TRUE(warned);
}

TEST(Collision, PathFarEnoughFromTheWallIsFree) {
  // the cell's cone: 18 mm from the wall centre line, 18 - 1.85 > 15.625 mm (its lowest capsule)
  const MotionPlan motion = planMotion(wallAndPathPlan(30, 18.0), defaultCell());
  EXPECT_TRUE(motion.collisions.empty());
  for (const MotionPoint& m : motion.points) EXPECT_FALSE(m.flags & kMotionCollision);
  // the 10 mm capsule: 12 mm from the wall, 12 - 1.85 > 10 mm (the cone hits the wall there
  // with the torch along gravity: a torch window of 0 keeps it so)
  const Plan plan = wallAndPathPlan(30, 12.0);
  MotionOptions options;
  options.allowCollisions = true;
  Cell upright = defaultCell();
  upright.process.maxTorchAngle = 0.0;
  MotionPlan near = planMotion(plan, upright, options);
  EXPECT_FALSE(near.collisions.empty());
  checkMotionCollisions(near, upright, capsuleGeometry(), depositBeadRadius(plan.parameters),
                        MotionOptions{});
  EXPECT_TRUE(near.collisions.empty());
  for (const MotionPoint& m : near.points) EXPECT_FALSE(m.flags & kMotionCollision);
}

TEST(Collision, SlimmerEnvelopeOrLowerWallClears) {
  // a 4 mm wall stays below the nozzle end (stick-out 15 mm)
  EXPECT_TRUE(planMotion(wallAndPathPlan(2, 8.0), defaultCell()).collisions.empty());
  // the same tall wall with a 5 mm envelope radius: checked directly
  const Plan plan = wallAndPathPlan(30, 8.0);
  MotionOptions options;
  options.allowCollisions = true;
  MotionPlan motion = planMotion(plan, cellWithoutGravityDeviation(), options);
  ASSERT_FALSE(motion.collisions.empty());
  CollisionGeometry slim = capsuleGeometry();
  slim.torch.radius = 5.0;
  slim.torch.topRadius = 5.0;
  checkMotionCollisions(motion, defaultCell(), slim, depositBeadRadius(plan.parameters), options);
  EXPECT_TRUE(motion.collisions.empty());
  // and the default envelope finds them again on the same motion
  checkMotionCollisions(motion, defaultCell(), capsuleGeometry(),
                        depositBeadRadius(plan.parameters), options);
  EXPECT_FALSE(motion.collisions.empty());
}

TEST(Collision, TorchAgainstThePositionerTable) {
  // A path 30 mm below the table surface where the cell puts the part (part frame = table
  // frame): planMotion refuses weld points below the table and its placement rest lifts the part
  // onto it, so the motion planned that way is checked against the table of the cell as given.
  // The torch body crosses the table disc.
  const Cell cell = defaultCell();
  ASSERT_TRUE(cell.positioner.tableToPart.isApprox(Pose::Identity()));
  Plan plan;
  plan.parameters.beadSpacing = 3.7;
  PlanLayer layer;
  layer.paths.push_back(straightPath(Vec3(-20, 50, -30), Vec3(20, 50, -30)));
  plan.layers.push_back(layer);
  const CollisionGeometry geometry = collisionGeometryOf(cell);
  const double beadRadius = depositBeadRadius(plan.parameters);
  MotionPlan below = planMotion(plan, cell);
  EXPECT_TRUE(below.collisions.empty());  // resting on the table: free
  // lifted 30 mm (no layer thickness in the plan: the bead bottom is the weld point)
  EXPECT_NEAR(below.tableToPart.translation().z(), 30.0, 1e-9);
  try {
    checkMotionCollisions(below, cell, geometry, beadRadius, MotionOptions{});
    FAIL() << "no collision reported";
  } catch (const InvalidInput& e) {
    EXPECT_TRUE(contains(e.what(), "torch vs positioner table")) << e.what();
    EXPECT_TRUE(contains(e.what(), "layer 0 path 0")) << e.what();
  }
  // the vertical torch's nozzle end reaches 30 - 15 = 15 mm below the table surface
  MotionOptions options;
  options.allowCollisions = true;
  checkMotionCollisions(below, cell, geometry, beadRadius, options);
  const MotionPathSpan& weld = below.paths.front();
  std::size_t weldHits = 0;
  for (const CollisionReport& c : below.collisions) {
    if (c.point <= weld.begin || c.point >= weld.end) continue;
    ++weldHits;
    EXPECT_EQ(c.what, "torch vs positioner table");
    EXPECT_NEAR(c.depth, 15.0, 1e-9);
  }
  EXPECT_EQ(weldHits, weld.end - weld.begin - 1);
  // outside the table's radius (300 mm) by more than the cone's lowest capsule radius (15.625
  // mm) the same path is free
  plan.layers[0].paths[0] = straightPath(Vec3(-20, 330, -30), Vec3(20, 330, -30));
  MotionPlan outside = planMotion(plan, cell);
  checkMotionCollisions(outside, cell, geometry, beadRadius, options);
  for (const CollisionReport& c : outside.collisions) {
    EXPECT_FALSE(contains(c.what, "table")) << describeMove(outside, c.point) << ": " << c.what;
  }
}

/// One weld move: a path start at `start` and a weld point 2 mm further along x, the torch's body
/// along unit `up` from the tip (part frame), the robot at `joints` at the weld point (all joints
/// 0 at the start).
MotionPlan oneWeldMove(const Vec3& start, const Vec3& up, const JointVector& joints) {
  MotionPlan motion;
  for (int i = 0; i < 2; ++i) {
    MotionPoint m;
    m.index = i;
    m.pathStart = i == 0;
    m.pathEnd = i == 1;
    m.arcOn = i == 1;
    m.position = start + Vec3(2.0 * i, 0, 0);
    m.toolInPart = Pose::Identity();
    m.toolInPart.linear() =
        Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), -up).toRotationMatrix();
    m.toolInPart.translation() = m.position;
    if (i == 1) m.joints = joints;
    motion.points.push_back(m);
  }
  motion.paths.push_back({0, 0, 0, motion.points.size(), {}});
  return motion;
}

TEST(Collision, ArmLinksAgainstTheTableNameTheLinkAndTheDepth) {
  // A weld point 10 mm above the table centre with the torch vertical, but the robot's joint L
  // swung forward by 90°: the upper arm lies level at the height of joint 2 (505 mm, the table's
  // top is at 530 mm), the elbow housing over the table's near edge and the forearm points down
  // through the table. The torch is clear; the arm is not. The depth, as for the torch, is how far
  // the capsules reach below the table's top face over the disc (the riser that would lift the
  // table's top above them): from the links' axes sampled every 0.5 mm here.
  const Cell cell = defaultCell();
  ASSERT_TRUE(cell.robot.links.known());
  MotionPlan motion =
      oneWeldMove(Vec3(0, 0, 10), Vec3::UnitZ(), {0.0, M_PI / 2, 0.0, 0.0, 0.0, 0.0});
  const CollisionGeometry geometry = collisionGeometryOf(cell);
  try {
    checkMotionCollisions(motion, cell, geometry, 1.85, MotionOptions{});
    FAIL() << "no collision reported";
  } catch (const InvalidInput& e) {
    EXPECT_TRUE(contains(e.what(), "torch or robot arm collide on 1 move(s)")) << e.what();
    EXPECT_TRUE(contains(e.what(), "vs positioner table")) << e.what();
  }
  MotionOptions allow;
  allow.allowCollisions = true;
  checkMotionCollisions(motion, cell, geometry, 1.85, allow);
  ASSERT_EQ(motion.collisions.size(), 1u);
  const CollisionReport& hit = motion.collisions.front();
  EXPECT_EQ(hit.point, 1u);
  EXPECT_EQ(hit.obstacle, CollisionObstacle::Table);
  // the second computation: every link's capsule (axis sampled every 0.5 mm) against the disc
  const ArmEnvelope& links = cell.robot.links;
  const ArmPoints a = computeArmPoints(cell.robot, motion.points[1].joints);
  const Vec3 side = links.upperArmOffset * a.side;
  const std::pair<std::string, std::array<Vec3, 2>> axes[] = {
      {"robot column", {Vec3::Zero(), a.column}},
      {"upper arm", {a.shoulder + side, a.elbow + side}},
      {"forearm", {a.elbow, a.forearmRoot}},
      {"forearm", {a.forearmRoot, a.wrist}},
      {"wrist", {a.wrist, a.flange}}};
  const double radii[] = {links.column, links.upperArm, links.elbow, links.forearm, links.wrist};
  const Pose baseToTable = computeTableInWorld(cell.positioner, 0.0, 0.0).inverse();
  double deepest = 0.0;
  std::string deepestPart;
  const PositionerGeometry& g = cell.positioner.geometry;
  for (std::size_t k = 0; k < 5; ++k) {
    const Vec3 from = baseToTable * axes[k].second[0], to = baseToTable * axes[k].second[1];
    const int n = std::max(1, static_cast<int>(std::ceil((to - from).norm() / 0.5)));
    bool touches = false;
    double reach = 0.0;
    for (int j = 0; j <= n; ++j) {
      const Vec3 x = from + (to - from) * (static_cast<double>(j) / n);
      const double dr = std::hypot(x.x(), x.y()) - g.tableRadius;
      const double dz = std::max(-g.tableThickness - x.z(), x.z());
      const double distance = dr <= 0.0 && dz <= 0.0
                                  ? std::max(dr, dz)
                                  : std::hypot(std::max(dr, 0.0), std::max(dz, 0.0));
      touches = touches || distance < radii[k];
      if (dr <= 0.0) reach = std::max(reach, radii[k] - x.z());
    }
    if (touches && reach > deepest) deepest = reach, deepestPart = axes[k].first;
  }
  ASSERT_GT(deepest, 500.0);  // the forearm through the table
  EXPECT_EQ(hit.what, deepestPart + " vs positioner table");
  EXPECT_NEAR(hit.depth, deepest, 1.0);
  // with the arm upright again (L = 0) nothing collides; a cell without the arm's capsules (a
  // version-2 file) checks the torch alone
  motion.points[1].joints[1] = 0.0;
  checkMotionCollisions(motion, cell, geometry, 1.85, allow);
  EXPECT_TRUE(motion.collisions.empty());
  motion.points[1].joints[1] = M_PI / 2;
  Cell noArm = cell;
  noArm.robot.links = ArmEnvelope{};
  checkMotionCollisions(motion, noArm, geometry, 1.85, allow);
  EXPECT_TRUE(motion.collisions.empty());
}

TEST(Collision, TorchAgainstThePositionerBody) {
  // The torch reaching up under the table, beside the positioner's body (radius 150 mm, from the
  // table's underside at -30 mm down to the tilt axis at -150 mm in the table frame): a point
  // 100 mm from the rotation axis at the body's mid-height, the torch leaning in towards it.
  const Cell cell = defaultCell();
  // the torch's body from the tip towards the rotation axis
  MotionPlan motion = oneWeldMove(Vec3(200, 0, -90), Vec3(-1, 0, 0), JointVector{});
  MotionOptions allow;
  allow.allowCollisions = true;
  checkMotionCollisions(motion, cell, collisionGeometryOf(cell), 1.85, allow);
  ASSERT_EQ(motion.collisions.size(), 1u);
  EXPECT_EQ(motion.collisions[0].what, "torch vs positioner body");
  EXPECT_EQ(motion.collisions[0].obstacle, CollisionObstacle::PositionerBody);
  // the torch's axis runs through the body at its mid-height, 60 mm from its top and bottom
  // faces: the envelope reaches in by 60 mm and its radius
  EXPECT_GT(motion.collisions[0].depth, 60.0 + 12.5);
}

TEST(Collision, BeadRadiusFromThePlan) {
  PlanParameters p;
  EXPECT_EQ(depositBeadRadius(p), 1.0);
  p.layerThickness = 1.5;
  EXPECT_EQ(depositBeadRadius(p), 1.5);
  p.beadSpacing = 3.7;
  EXPECT_EQ(depositBeadRadius(p), 1.85);
}

TEST(Collision, BadEnvelopeIsRejected) {
  const Plan plan = wallAndPathPlan(1, 8.0);
  MotionPlan motion = planMotion(plan, defaultCell());
  for (int field = 0; field < 4; ++field) {
    CollisionGeometry g = capsuleGeometry();
    if (field == 0) g.torch.stickout = 0.0;
    if (field == 1) g.torch.radius = -1.0;
    if (field == 2) g.torch.length = 2.0 * g.torch.radius;
    if (field == 3) g.table.tableThickness = 0.0;
    EXPECT_THROW(checkMotionCollisions(motion, defaultCell(), g, 1.85, MotionOptions{}),
                 InvalidInput);
  }
}

TEST(Collision, DescribesEveryKindOfMove) {
  const Plan plan = wallAndPathPlan(1, 30.0);
  const MotionPlan motion = planMotion(plan, defaultCell());
  EXPECT_EQ(describeMove(motion, 0), "home pose");
  EXPECT_EQ(describeMove(motion, 1), "approach above layer 0 path 0");
  EXPECT_EQ(describeMove(motion, 2), "layer 0 path 0 point 0 (approach onto the path start)");
  EXPECT_EQ(describeMove(motion, 3), "layer 0 path 0 point 1 (weld move)");
  const std::size_t end = motion.paths.front().end;
  EXPECT_EQ(describeMove(motion, end), "retract from layer 0 path 0");
  EXPECT_EQ(describeMove(motion, motion.points.size() - 1),
            "move to the home pose after layer 1 path 0");
}

TEST(Collision, AgreesWithBruteForceOnRandomPoses) {
  // A random walk of 2 mm weld steps in a 40 mm box high above the table, the torch leaning
  // randomly up to 80 degrees from +z at every point: many near misses. Every weld move's verdict
  // must match the brute-force distance of the envelope's model (bead segments sampled every
  // 0.01 mm against the capsule along the torch axis and the flat-ended nozzle cylinder below
  // it), except within 0.01 mm of contact.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  MotionPlan motion;
  Vec3 position(0, 0, 200);
  const int count = 400;
  for (int i = 0; i < count; ++i) {
    MotionPoint m;
    m.index = i;
    m.pathStart = i == 0;
    m.pathEnd = i + 1 == count;
    m.arcOn = i > 0;
    if (i > 0) {
      Vec3 step(unit(random), unit(random), unit(random));
      position += 2.0 * step.normalized();
      position = position.cwiseMax(Vec3(-20, -20, 180)).cwiseMin(Vec3(20, 20, 220));
    }
    m.position = position;
    Vec3 up(unit(random), unit(random), 0.0);
    up = (Vec3::UnitZ() + std::tan(80.0 * 3.14159265358979 / 180.0) * std::abs(unit(random)) *
                              (up.norm() > 1e-9 ? Vec3(up.normalized()) : Vec3::UnitX()))
             .normalized();
    m.toolInPart = Pose::Identity();
    m.toolInPart.linear() =
        Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), -up).toRotationMatrix();
    m.toolInPart.translation() = position;
    motion.points.push_back(m);
  }
  motion.paths.push_back({0, 0, 0, motion.points.size(), {}});
  MotionOptions options;
  options.allowCollisions = true;
  const double r = 1.85;
  checkMotionCollisions(motion, defaultCell(), capsuleGeometry(), r, options);
  const TorchEnvelope torch = capsuleGeometry().torch;
  std::size_t hits = 0, checked = 0;
  for (int i = 1; i < count; ++i) {
    const MotionPoint& m = motion.points[static_cast<std::size_t>(i)];
    const Vec3 tip = m.toolInPart.translation();
    const Vec3 up = -m.toolInPart.linear().col(2);
    const Vec3 nozzle = tip + torch.stickout * up;
    const Vec3 low = tip + (torch.stickout + torch.radius) * up;
    const Vec3 high = tip + (torch.stickout + torch.length - torch.radius) * up;
    // signed distance of x from the envelope: the capsule, or the nozzle's flat-ended cylinder
    const auto envelopeDistance = [&](const Vec3& x) {
      const double h = (x - nozzle).dot(up);
      const double radial = (x - nozzle - h * up).norm() - torch.radius;
      const double axial = std::max(-h, h - torch.radius);
      const double cylinder = radial <= 0.0 && axial <= 0.0
                                  ? std::max(radial, axial)
                                  : std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
      return std::min(distanceToSegment(x, low, high) - torch.radius, cylinder);
    };
    double smallest = kInf;
    for (int k = 1; k < i; ++k) {
      const Vec3& p = motion.points[static_cast<std::size_t>(k - 1)].position;
      const Vec3& q = motion.points[static_cast<std::size_t>(k)].position;
      const int n = static_cast<int>(std::ceil((q - p).norm() / 0.01));
      for (int j = 0; j <= n; ++j) {
        smallest = std::min(smallest, envelopeDistance(p + (q - p) * (double(j) / n)));
      }
    }
    const double contact = r;
    if (std::abs(smallest - contact) < 0.01) continue;
    ++checked;
    const bool flagged = (m.flags & kMotionCollision) != 0;
    EXPECT_EQ(flagged, smallest < contact) << "point " << i << " distance " << smallest;
    hits += smallest < contact;
  }
  EXPECT_GT(hits, 20u);            // the case has collisions ...
  EXPECT_GT(checked - hits, 20u);  // ... and free poses
  EXPECT_EQ(motion.collisions.size(), hits);
}

TEST(Collision, TravelAndCollisionStagesCanBeCancelled) {
  const Plan plan = wallAndPathPlan(5, 30.0);
  for (const std::string stage : {"travel", "collisions"}) {
    bool seen = false;
    const Progress progress([&](double, std::string_view name) {
      seen = seen || name == stage;
      return name != stage;
    });
    EXPECT_THROW(planMotion(plan, defaultCell(), MotionOptions{}, progress), Cancelled) << stage;
    EXPECT_TRUE(seen) << stage;
  }
}

}  // namespace
}  // namespace curvedslicer
