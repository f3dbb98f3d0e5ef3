// Every bundled model, planned coarse from its usual start, moved by each bundled cell with
// placement auto and no collision allowed: no motion
// point (weld, air move or home) leaves the robot's joint ranges, violates one of its
// interference limits (robot/interference) or folds the forearm onto the upper arm. The checks
// are computed here from the controller joint angles and the cell file's numbers, not with the
// planner's own limit tests: the interference sums directly, the elbow angle in closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "common/sanitized_build.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "model_plans.hpp"

namespace curvedslicer {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;
constexpr double kMinElbow = 10.0 * kDegree;  ///< `cell check`'s folded-arm criterion

const char* const kBundledCellFiles[] = {
    "motoman_hp20d_tilt_rotate.json",
    "kuka_kr16_r1610_2_dkp400.json",
    "abb_irb1660id_irbp_a250.json",
    "fanuc_arcmate100ic_2axis_positioner.json",
};

/// The angle between upper arm and forearm at the elbow, from the controller's joint 2 and 3:
/// the model angle of joint 3 relative to the upper arm is θ3 = s3·J3 + o3 (minus θ2 = s2·J2 + o2
/// when J3 is measured from the horizontal); with the forearm (c3 along, a2 across) the cosine of
/// the elbow angle is sin(θ3 − atan2(a2, c3)).
double elbowAngleOf(const RobotDescription& robot, const JointVector& q) {
  const double theta2 = robot.jointSigns[1] * q[1] + robot.jointOffsets[1];
  double theta3 = robot.jointSigns[2] * q[2] + robot.jointOffsets[2];
  if (robot.j3RelativeToHorizontal) theta3 -= theta2;
  const double psi = std::atan2(robot.kinematics.a2, robot.kinematics.c3);
  return std::acos(std::clamp(std::sin(theta3 - psi), -1.0, 1.0));
}

/// Counts the points of `motion` outside the robot's limits, reporting the first few.
void expectWithinJointLimits(const MotionPlan& motion, const RobotDescription& robot) {
  std::size_t outside = 0, interfering = 0, folded = 0;
  double smallestElbow = 4.0;
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const JointVector& q = motion.points[i].joints;
    for (int j = 0; j < 6; ++j) {
      if (q[j] < robot.joints[j].min - 1e-9 || q[j] > robot.joints[j].max + 1e-9) {
        if (outside++ < 3)
          ADD_FAILURE() << "point " << i << " joint " << j + 1 << " " << q[j] / kDegree << " deg";
      }
    }
    for (const JointInequality& limit : robot.interference) {
      double sum = 0.0;
      for (int j = 0; j < 6; ++j) sum += limit.coefficients[j] * q[j];
      if (sum > limit.max + 1e-9) {
        if (interfering++ < 3) {
          ADD_FAILURE() << "point " << i << " violates " << limit.name << " by "
                        << (sum - limit.max) / kDegree << " deg";
        }
      }
    }
    const double elbow = elbowAngleOf(robot, q);
    smallestElbow = std::min(smallestElbow, elbow);
    if (elbow < kMinElbow && folded++ < 3) {
      ADD_FAILURE() << "point " << i << " folds the arm: elbow " << elbow / kDegree << " deg";
    }
  }
  EXPECT_EQ(outside, 0u);
  EXPECT_EQ(interfering, 0u);
  EXPECT_EQ(folded, 0u) << "smallest elbow angle " << smallestElbow / kDegree << " deg";
}

/// The bundled models with their usual starts (plane:bottom unless given), coarse: 40 voxels on
/// the longest side (at least 2 mm), layers 2 and beads 2.5 voxels apart; the branches' rods
/// (about 3 mm thick) at 2 mm voxels with 1.5 mm beads. Joint limits do not depend on the
/// resolution.
testing::ModelCase coarseCase(const std::string& model) {
  testing::ModelCase c;
  c.model = model;
  if (model == "custom_base_geom_to_slice.obj") {
    c.start = "mesh:" + testing::modelPath("custom_base_surface.obj").string();
    c.capHoles = true;
  }
  const Aabb box = readMesh(testing::modelPath(model)).bounds();
  const Vec3 size = box.max - box.min;
  c.voxel = std::max(2.0, size.maxCoeff() / 40.0);
  c.layerThickness = 2.0 * c.voxel;
  c.beadSpacing = model == "branches_70_closed_low_res.stl" ? 1.5 : 2.5 * c.voxel;
  c.pointSpacing = std::max(c.beadSpacing, 1.5);
  return c;
}

class BundledModelJointLimits : public ::testing::TestWithParam<std::string> {};

TEST_P(BundledModelJointLimits, NoMotionPointOfAnyCellLeavesItsJointOrInterferenceLimits) {
  CURVEDSLICER_SKIP_IF_SANITIZED(
      "VendorCells.InverseKinematicsNeverOffersASolutionViolatingAnInterferenceLimit");
  const Plan plan = testing::planModelCase(coarseCase(GetParam())).planned.plan;
  ASSERT_GT(plan.pathCount(), 0u);
  for (const char* file : kBundledCellFiles) {
    SCOPED_TRACE(file);
    const Cell cell =
        readCell(std::filesystem::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "cells" / file);
    // every model's motion clears table, riser and deposit (a collision would stop planMotion);
    // placement auto stands a part whose first layers bring the table to the torch on a riser
    MotionOptions options;
    options.placement = PartPlacement::Auto;
    const MotionPlan motion = planMotion(plan, cell, options);
    EXPECT_TRUE(motion.collisions.empty());
    ASSERT_EQ(motion.paths.size(), plan.pathCount());
    expectWithinJointLimits(motion, cell.robot);
  }
}

INSTANTIATE_TEST_SUITE_P(
    EveryBundledModel, BundledModelJointLimits,
    ::testing::Values("bunny_closed_low_res.stl", "branches_70_closed_low_res.stl",
                      "custom_base_geom_to_slice.obj", "distorted_v_closed_mid_res.stl",
                      "overhang_coin_closed_low_res.stl", "simple_box_closed_low_res.stl",
                      "simple_cylinder_closed_mid_res.stl"),
    [](const ::testing::TestParamInfo<std::string>& model) {
      std::string name = model.param.substr(0, model.param.find('.'));
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

}  // namespace
}  // namespace curvedslicer
