// Collision avoidance by torch angle (robot/torch_tilt): a path beside a tall wall of earlier
// beads, which the torch along gravity would hit, is welded with the torch leaning away from the
// wall by the smallest angle that clears (checked against a second computation of the envelope's
// lowest capsule against the wall's beads, and by sampling the torch cone itself); a wall too
// close for the torch window, or a window of 0, stays a collision that names the window; the
// window is a cell field with errors naming it; the angles reach the CSV. Beyond the torch
// window, the positioner turns the deposition direction off gravity (within the gravity
// deviation window) so that the torch, within its window off gravity, leans far enough against
// the part; the deviation is checked from the robot's poses alone.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>

#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/export/neutral_writer.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "robot_test_support.hpp"

namespace curvedslicer {
namespace {

using robot_test::distanceToSegment;
using robot_test::straightPath;
using testing::kPi;

constexpr double kDegree = kPi / 180.0;
constexpr double kBeadRadius = 1.85;    // half the plan's 3.7 mm bead spacing
constexpr double kWallTop = 45.0;       // 30 layers of 1.5 mm
constexpr double kWallHalfLength = 40;  // the wall runs from x = -40 to 40 mm

/// Layers 0-29: one bead each along x at y = 0 (a wall 45 mm high); layer 30: a path from
/// x = -20 to 20 mm at height 1.5 mm, `offset` mm beside the wall.
Plan pathBesideAWall(double offset) {
  Plan plan;
  plan.parameters.beadSpacing = 2.0 * kBeadRadius;
  plan.parameters.layerThickness = 1.5;
  for (int l = 0; l <= 30; ++l) {
    PlanLayer layer;
    layer.index = l;
    if (l < 30) {
      const double z = 1.5 * (l + 1);
      layer.paths.push_back(
          straightPath(Vec3(-kWallHalfLength, 0, z), Vec3(kWallHalfLength, 0, z)));
    } else {
      layer.paths.push_back(straightPath(Vec3(-20, offset, 1.5), Vec3(20, offset, 1.5)));
    }
    layer.paths.back().layer = l;
    plan.layers.push_back(layer);
  }
  return plan;
}

/// Second computation of the planner's torch model against the wall: the lowest capsule of the
/// default cell's cone (radius 15.625 mm, axis 30.625 to 111.25 mm above the TCP; the higher
/// capsules stay above the wall), sampled every 0.05 mm along its axis against every wall bead's
/// axis, and the nozzle below it (a flat-ended cylinder of the cone's radius at 30.625 mm,
/// 13.008 mm, from the nozzle face 15 mm above the TCP up to 30.625 mm; against a bead's axis,
/// a line along x, its distance is that of the rectangle it projects to in the y-z plane),
/// leaning by `angle` straight away from the wall. True when both clear every bead.
bool capsuleClearsWall(double offset, double angle) {
  const double radius = 15.625;
  for (double h = 30.625; h <= 111.25; h += 0.05) {
    const double y = offset + h * std::sin(angle);
    const double z = 1.5 + h * std::cos(angle);
    for (int l = 0; l < 30; ++l) {
      if (std::hypot(y, z - 1.5 * (l + 1)) < radius + kBeadRadius) return false;
    }
  }
  const double nozzle = 12.5 + 12.5 * 15.625 / 385.0;
  const double uy = std::sin(angle), uz = std::cos(angle);  // up the torch
  for (int l = 0; l < 30; ++l) {
    // the bead's axis relative to the nozzle face's centre, along and across the torch axis
    const double dy = -offset - 15.0 * uy, dz = 1.5 * (l + 1) - 1.5 - 15.0 * uz;
    const double along = dy * uy + dz * uz, across = std::abs(dy * uz - dz * uy);
    const double outside = std::max({0.0, -along, along - 15.625});
    if (std::hypot(std::max(0.0, across - nozzle), outside) < kBeadRadius) return false;
  }
  return true;
}

/// The smallest lean (rad) at which capsuleClearsWall, by bisection (monotone here: leaning
/// away only moves the capsule away from the wall).
double smallestClearingLean(double offset) {
  double lo = 0.0, hi = 40.0 * kDegree;
  while (hi - lo > 1e-4 * kDegree) {
    const double mid = 0.5 * (lo + hi);
    (capsuleClearsWall(offset, mid) ? hi : lo) = mid;
  }
  return hi;
}

/// Distance (mm) of the torch cone itself (the cell's envelope, sampled every 1 mm along the axis
/// and every 5° around) from the wall's bead surfaces; negative inside a bead.
double wallConeClearance(const TorchEnvelope& torch, const Vec3& tip, const Vec3& up) {
  const Vec3 u = up.normalized();
  const Vec3 a = u.unitOrthogonal();
  const Vec3 b = u.cross(a);
  double nearest = kInf;
  for (double h = torch.stickout; h <= torch.stickout + torch.length; h += 1.0) {
    const double r =
        torch.radius + (torch.topRadius - torch.radius) * (h - torch.stickout) / torch.length;
    for (int k = 0; k < 72; ++k) {
      const double phi = 2.0 * kPi * k / 72;
      const Vec3 x = tip + h * u + r * (std::cos(phi) * a + std::sin(phi) * b);
      if (x.z() > kWallTop + 50.0) break;
      for (int l = 0; l < 30; ++l) {
        const double z = 1.5 * (l + 1);
        nearest = std::min(nearest, distanceToSegment(x, Vec3(-kWallHalfLength, 0, z),
                                                      Vec3(kWallHalfLength, 0, z)) -
                                        kBeadRadius);
      }
    }
  }
  return nearest;
}

TEST(TorchTilt, PathBesideATallWallIsWeldedLeaningAwayByTheSmallestAngle) {
  constexpr double kOffset = 12.0;  // the torch along gravity reaches 5.5 mm into the wall
  ASSERT_FALSE(capsuleClearsWall(kOffset, 0.0));
  const double needed = smallestClearingLean(kOffset);
  ASSERT_GT(needed, 5.0 * kDegree);
  ASSERT_LT(needed, 15.0 * kDegree);
  const Cell cell = defaultCell();
  ASSERT_NEAR(cell.process.maxTorchAngle, 15.0 * kDegree, 1e-12);
  const MotionPlan motion = planMotion(pathBesideAWall(kOffset), cell);
  EXPECT_TRUE(motion.collisions.empty());
  const MotionPathSpan& weld = motion.paths.back();
  double largest = 0.0;
  for (std::size_t k = weld.begin; k < weld.end; ++k) {
    const MotionPoint& m = motion.points[k];
    SCOPED_TRACE("point " + std::to_string(m.index));
    ASSERT_EQ(m.kind, MoveKind::Path);
    EXPECT_TRUE(m.flags & kMotionTorchTilted);
    // the smallest clearing angle within the search's resolution (2.5° rings halved twice)
    EXPECT_GE(m.torchAngle, needed - 1e-9);
    EXPECT_LE(m.torchAngle, needed + 2.5 * kDegree / 4 + 0.01 * kDegree);
    // straight away from the wall (+y), across the travel (+x): a work angle, the body leaning
    // to the left of the travel, no push or drag
    EXPECT_NEAR(m.workAngle, m.torchAngle, 1e-9);
    EXPECT_NEAR(m.travelAngle, 0.0, 1e-9);
    // the robot's TCP: its z axis (out of the torch) is off gravity by the torch angle, leaning
    // so that the torch body points to +y in the part frame
    const Vec3 z = m.toolInWorld.linear().col(2);
    EXPECT_NEAR(std::acos(std::clamp(z.dot(cell.gravity.normalized()), -1.0, 1.0)), m.torchAngle,
                1e-9);
    const Vec3 up = -m.toolInPart.linear().col(2);
    EXPECT_GT(up.y(), 0.0);
    EXPECT_NEAR(std::atan2(up.y(), up.z()), m.torchAngle, 1e-9);
    // the torch cone itself clears every bead of the wall
    EXPECT_GE(wallConeClearance(cell.tool.envelope, m.toolInPart.translation(), up), 0.0);
    largest = std::max(largest, m.torchAngle);
  }
  EXPECT_NEAR(motion.total.maxTorchAngle, largest, 1e-12);
  EXPECT_NEAR(motion.layers.back().maxTorchAngle, largest, 1e-12);
  EXPECT_EQ(motion.layers.front().maxTorchAngle, 0.0);  // the wall itself: along gravity
  const bool noted = std::any_of(motion.notes.begin(), motion.notes.end(), [](const auto& n) {
    return n.find("torch tilted off gravity on") != std::string::npos;
  });
  EXPECT_TRUE(noted);
  // the angles reach the neutral CSV, in degrees
  const ExportResult csv = NeutralWriter(ExportFormat::Csv).write(motion, cell, {}, {});
  EXPECT_NE(csv.files[0].text.find("torch_angle_deg,travel_angle_deg,work_angle_deg"),
            std::string::npos);
}

/// The angle (rad) between the plan's V at a weld point of the wall test (straight down in the
/// part frame) and gravity, from the robot's TCP poses alone: the part's rotation in the world is
/// toolInWorld · toolInPart⁻¹.
double gravityDeviationOf(const MotionPoint& m, const Cell& cell) {
  const Mat3 partInWorld = m.toolInWorld.linear() * m.toolInPart.linear().transpose();
  const Vec3 v = partInWorld * Vec3(0, 0, -1);
  return std::acos(std::clamp(v.dot(cell.gravity.normalized()), -1.0, 1.0));
}

TEST(TorchTilt, PathBeyondTheTorchWindowIsClearedByAGravityDeviation) {
  constexpr double kOffset = 8.0;  // the nozzle needs about 22.5°: more than the 15° window
  const double needed = smallestClearingLean(kOffset);
  ASSERT_GT(needed, 15.0 * kDegree);
  ASSERT_LT(needed, 25.0 * kDegree);
  const Cell cell = defaultCell();
  ASSERT_NEAR(cell.process.maxGravityDeviation, 10.0 * kDegree, 1e-12);
  const MotionPlan motion = planMotion(pathBesideAWall(kOffset), cell);
  EXPECT_TRUE(motion.collisions.empty());
  const MotionPathSpan& weld = motion.paths.back();
  double largest = 0.0;
  for (std::size_t k = weld.begin; k < weld.end; ++k) {
    const MotionPoint& m = motion.points[k];
    SCOPED_TRACE("point " + std::to_string(m.index));
    EXPECT_TRUE(m.flags & kMotionGravityDeviated);
    // the torch within its window off gravity, the deposit within its window off gravity
    EXPECT_LE(m.torchAngle, cell.process.maxTorchAngle + 1e-9);
    EXPECT_LE(m.residual, cell.process.maxGravityDeviation + 1e-9);
    // the deviation recorded is the one the robot's poses show, and only as large as needed
    // (the excess over the window plus the 1° margin, within the search's resolution)
    const double deviation = gravityDeviationOf(m, cell);
    EXPECT_NEAR(m.residual, deviation, 1e-6);
    EXPECT_GE(deviation, needed - cell.process.maxTorchAngle - 1e-6);
    EXPECT_LE(deviation, needed - cell.process.maxTorchAngle + 1.0 * kDegree + 0.7 * kDegree);
    // relative to the part the torch leans away from the wall by at least the clearing angle,
    // and the torch cone itself clears every bead
    const Vec3 up = -m.toolInPart.linear().col(2);
    EXPECT_GT(up.y(), 0.0);
    EXPECT_GE(std::atan2(up.y(), up.z()), needed - 1e-6);
    EXPECT_GE(wallConeClearance(cell.tool.envelope, m.toolInPart.translation(), up), 0.0);
    largest = std::max(largest, m.residual);
  }
  EXPECT_NEAR(motion.layers.back().maxGravityDeviation, largest, 1e-12);
  EXPECT_LT(motion.layers.front().maxGravityDeviation, 1e-6);  // the wall itself: on gravity
  const bool noted = std::any_of(motion.notes.begin(), motion.notes.end(), [](const auto& n) {
    return n.find("deposition direction turned off gravity on") != std::string::npos &&
           n.find("process/max_gravity_deviation_deg") != std::string::npos;
  });
  EXPECT_TRUE(noted);
}

TEST(TorchTilt, WallBeyondTheWindowsOrWindowsOfZeroStaysACollisionNamingTheWindows) {
  // 8 mm from the wall the nozzle needs about 22.5°: more than the 15° torch window alone; 3 mm
  // from it about 37.5°: more than both windows together
  ASSERT_GT(smallestClearingLean(8.0), 15.0 * kDegree);
  ASSERT_GT(smallestClearingLean(3.0), 25.0 * kDegree);
  for (const auto& [offset, window, deviation] :
       {std::tuple{8.0, 15.0, 0.0}, std::tuple{3.0, 15.0, 10.0}, std::tuple{12.0, 0.0, 0.0}}) {
    SCOPED_TRACE("offset " + std::to_string(offset));
    Cell cell = defaultCell();
    cell.process.maxTorchAngle = window * kDegree;
    cell.process.maxGravityDeviation = deviation * kDegree;
    try {
      planMotion(pathBesideAWall(offset), cell);
      ADD_FAILURE() << "no collision reported";
    } catch (const InvalidInput& e) {
      const std::string text = e.what();
      EXPECT_NE(text.find("torch vs deposit of layer"), std::string::npos) << text;
      EXPECT_NE(text.find("widen the torch window (the cell's process/max_torch_angle_deg, now " +
                          std::string(window == 0.0 ? "0.0" : "15.0") + " deg"),
                std::string::npos)
          << text;
      if (deviation > 0.0) {
        EXPECT_NE(text.find("allow a larger gravity deviation (the cell's "
                            "process/max_gravity_deviation_deg, now 10.0 deg"),
                  std::string::npos)
            << text;
      }
    }
    MotionOptions options;
    options.allowCollisions = true;
    const MotionPlan motion = planMotion(pathBesideAWall(offset), cell, options);
    EXPECT_FALSE(motion.collisions.empty());
    // a tilt that does not clear is not made: the torch stays along gravity, V on gravity
    for (const MotionPoint& m : motion.points) {
      EXPECT_EQ(m.torchAngle, 0.0);
      EXPECT_FALSE(m.flags & kMotionGravityDeviated);
    }
  }
}

/// Clearance (mm) of the arm's wrist capsule (wrist centre to flange, the cell's wrist radius)
/// from the table disc's top face and rim, from the robot's joints by forward kinematics: over
/// the disc the axis point's height less the radius, beside it its distance from the rim's top
/// edge less the radius (the axis sampled every 0.5 mm; the capsule stays above the table's
/// plane here).
double wristClearanceOfTable(const MotionPoint& m, const Cell& cell, const Pose& tableToPart) {
  const ArmPoints arm = computeArmPoints(cell.robot, m.joints);
  const Pose partFromWorld = m.toolInPart * m.toolInWorld.inverse();
  const Pose toTable = tableToPart * partFromWorld * cell.robot.base;
  const Vec3 a = toTable * arm.wrist, b = toTable * arm.flange;
  const double rim = cell.positioner.geometry.tableRadius, radius = cell.robot.links.wrist;
  double clearance = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 200; ++k) {
    const Vec3 x = a + (b - a) * (k / 200.0);
    const double rho = x.head<2>().norm();
    const double d = rho <= rim ? x.z() : std::hypot(rho - rim, std::max(x.z(), 0.0));
    clearance = std::min(clearance, d - radius);
  }
  return clearance;
}

TEST(TorchTilt, TheSearchLeansTheTorchForTheWristToo) {
  // A path 30 mm above the table, 50 mm from its centre, whose V points outwards 5° below the
  // table plane: the table tilts to about 85°, and the torch along gravity lies 5° above the
  // table top, across it. The torch clears it (its envelope is at most 25 mm wide and 30 mm up
  // at the nozzle), but the wrist, 400 to 500 mm up the straight torch with its 86 mm radius,
  // would reach into the table's rim; the torch search leans the torch until the wrist clears,
  // checked here from the joints.
  Plan plan;
  plan.parameters.beadSpacing = 2.0 * kBeadRadius;
  plan.parameters.layerThickness = 1.5;
  PlanLayer layer;
  layer.paths.push_back(straightPath(Vec3(50, -10, 30), Vec3(50, 10, 30)));
  const Vec3 v(std::cos(5 * kDegree), 0.0, -std::sin(5 * kDegree));
  for (PathPoint& q : layer.paths.back().points) q.deposition = v, q.normal = -v;
  plan.layers.push_back(layer);
  const Cell cell = defaultCell();
  ASSERT_GT(cell.robot.links.wrist, 0.0);
  // the premise, without the planner: along -V, the cone (stickout 15, radius <= 25) stays above
  // the table and the wrist capsule does not
  const Vec3 up = -v;
  const TorchEnvelope& torch = cell.tool.envelope;
  for (double t = torch.stickout; t <= torch.stickout + torch.length; t += 1.0) {
    ASSERT_GT(30.0 + t * up.z() - torch.topRadius * std::sqrt(1 - up.z() * up.z()), 0.0);
  }
  // the flange, 48 mm beside the rim and 65 mm above the table: 81 mm from the rim's edge
  const Vec3 flange = Vec3(50, 0, 30) + 400.0 * up;
  const double rim = cell.positioner.geometry.tableRadius;
  ASSERT_LT(std::hypot(flange.head<2>().norm() - rim, flange.z()), cell.robot.links.wrist);
  MotionOptions options;
  options.placement = PartPlacement::Cell;  // the path stays 30 mm above the table
  const MotionPlan motion = planMotion(plan, cell, options);
  EXPECT_TRUE(motion.collisions.empty());
  const MotionPathSpan& weld = motion.paths.back();
  for (std::size_t k = weld.begin; k < weld.end; ++k) {
    const MotionPoint& m = motion.points[k];
    SCOPED_TRACE("point " + std::to_string(m.index));
    EXPECT_TRUE(m.flags & kMotionTorchTilted);
    EXPECT_GT(m.torchAngle, 0.0);
    EXPECT_LE(m.torchAngle, cell.process.maxTorchAngle + 1e-9);
    EXPECT_GE(wristClearanceOfTable(m, cell, motion.tableToPart), 0.0);
  }
}

TEST(TorchTilt, TheWindowIsACellFieldWithErrorsNamingIt) {
  nlohmann::json cell = nlohmann::json::parse(writeCellJson(defaultCell()));
  EXPECT_EQ(cell["process"]["max_torch_angle_deg"], 15.0);
  cell["process"]["max_torch_angle_deg"] = 20;
  EXPECT_NEAR(parseCell(cell.dump(), "cell.json").process.maxTorchAngle, 20.0 * kDegree, 1e-12);
  for (const double bad : {50.0, -1.0}) {
    cell["process"]["max_torch_angle_deg"] = bad;
    try {
      parseCell(cell.dump(), "cell.json");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InvalidInput& e) {
      const std::string text = e.what();
      EXPECT_NE(text.find("/process/max_torch_angle_deg"), std::string::npos) << text;
      EXPECT_NE(text.find("must be in [0, 45] degrees"), std::string::npos) << text;
      EXPECT_NE(text.find(bad == 50.0 ? "50" : "-1"), std::string::npos) << text;
    }
  }
  cell["process"]["max_torch_angle_deg"] = 15;
  EXPECT_EQ(cell["process"]["max_gravity_deviation_deg"], 10.0);
  cell["process"]["max_gravity_deviation_deg"] = 5;
  EXPECT_NEAR(parseCell(cell.dump(), "cell.json").process.maxGravityDeviation, 5.0 * kDegree,
              1e-12);
  for (const double bad : {46.0, -2.0}) {
    cell["process"]["max_gravity_deviation_deg"] = bad;
    try {
      parseCell(cell.dump(), "cell.json");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InvalidInput& e) {
      const std::string text = e.what();
      EXPECT_NE(text.find("/process/max_gravity_deviation_deg"), std::string::npos) << text;
      EXPECT_NE(text.find("must be in [0, 45] degrees"), std::string::npos) << text;
      EXPECT_NE(text.find(bad == 46.0 ? "46" : "-2"), std::string::npos) << text;
    }
  }
}

}  // namespace
}  // namespace curvedslicer
