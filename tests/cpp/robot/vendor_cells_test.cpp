// The cells of resources/cells/, one per vendor: every file valid by the cell schema and read
// without notes; forward kinematics equal to the published robot descriptions the numbers come
// from (resources/cells/README.md); inverse kinematics reproducing random joint vectors within the
// limits; home poses clear of the table; the vendor check of exports (checkCellVendor).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "plan/json_schema_subset.hpp"
#include "robot_test_support.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

fs::path cellsDir() {
  return fs::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "cells";
}

struct VendorCell {
  const char* file;
  RobotVendor vendor;
};

const VendorCell kCells[] = {
    {"motoman_hp20d_tilt_rotate.json", RobotVendor::Yaskawa},
    {"kuka_kr16_r1610_2_dkp400.json", RobotVendor::Kuka},
    {"abb_irb1660id_irbp_a250.json", RobotVendor::Abb},
    {"fanuc_arcmate100ic_2axis_positioner.json", RobotVendor::Fanuc},
};

TEST(VendorCells, EveryCellFileIsValidBySchemaAndReadsWithoutNotes) {
  std::ifstream schemaFile(fs::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "schema" /
                           "cell.schema.json");
  ASSERT_TRUE(schemaFile);
  const testing::SchemaSubsetValidator validator(Json::parse(schemaFile));
  int files = 0;
  for (const auto& entry : fs::directory_iterator(cellsDir())) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().filename().string());
    ++files;
    std::ifstream in(entry.path());
    const std::vector<std::string> errors = validator.validate(Json::parse(in));
    for (const std::string& e : errors) ADD_FAILURE() << e;
    const Cell cell = readCell(entry.path());
    EXPECT_TRUE(cell.notes.empty()) << cell.notes.front();
    EXPECT_NE(cell.vendor, RobotVendor::Unknown);
  }
  EXPECT_GE(files, 4);
  for (const VendorCell& c : kCells) EXPECT_EQ(readCell(cellsDir() / c.file).vendor, c.vendor);
  // The schema is not a rubber stamp: a wrong vendor and a missing joint list are refused.
  std::ifstream in(cellsDir() / kCells[1].file);
  Json bad = Json::parse(in);
  bad["vendor"] = "motoman";
  bad["robot"].erase("joints");
  EXPECT_EQ(validator.validate(bad).size(), 2u);
}

/// One revolute joint of a URDF chain: origin (mm, fixed-axis rpy in rad) and axis.
struct UrdfJoint {
  Vec3 xyz;
  Vec3 rpy;
  Vec3 axis;
};

/// base_link → tool0 of a URDF chain for URDF joint angles (rad); mm.
Pose urdfToolPose(const std::vector<UrdfJoint>& chain, const Vec3& toolRpy,
                  const std::array<double, 6>& q) {
  Pose pose = Pose::Identity();
  for (std::size_t i = 0; i < chain.size(); ++i) {
    pose = pose * makePose(chain[i].xyz, chain[i].rpy);
    pose.rotate(Eigen::AngleAxisd(q[i], chain[i].axis.normalized()));
  }
  return pose * makePose(Vec3::Zero(), toolRpy);
}

/// Random controller joint vectors within the joint limits (seeded).
std::vector<JointVector> randomJoints(const RobotDescription& robot, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<JointVector> out;
  for (int k = 0; k < count; ++k) {
    JointVector q;
    for (int j = 0; j < 6; ++j) {
      q[j] = std::uniform_real_distribution<double>(robot.joints[j].min, robot.joints[j].max)(rng);
    }
    out.push_back(q);
  }
  return out;
}

void expectSamePose(const Pose& a, const Pose& b, const std::string& what) {
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-6) << what;
  EXPECT_LT((a.linear() - b.linear()).norm(), 1e-9) << what;
}

// KUKA KR 16 R1610-2: kroshu/kuka_robot_descriptions, kuka_cybertech_support/urdf/
// kr16_r1610_2_macro.xacro (joint origins in m there, mm here); its joint angles are the
// controller's A1..A6 (the description drives the KUKA controllers through kuka_drivers).
TEST(VendorCells, KukaForwardKinematicsEqualsKukasRobotDescription) {
  const Cell cell = readCell(cellsDir() / "kuka_kr16_r1610_2_dkp400.json");
  const std::vector<UrdfJoint> chain = {
      {Vec3(0, 0, 312.7), Vec3(kPi, 0, 0), Vec3::UnitZ()},
      {Vec3(160, 0, -207.3), Vec3(kPi / 2, 0, 0), Vec3::UnitZ()},
      {Vec3(780, 0, 0), Vec3(0, 0, 0), Vec3::UnitZ()},
      {Vec3(427, -150, 0), Vec3(kPi / 2, 0, -kPi / 2), Vec3::UnitZ()},
      {Vec3(0, 0, -228), Vec3(0, kPi / 2, kPi / 2), Vec3::UnitZ()},
      {Vec3(153, 0, 0), Vec3(kPi / 2, 0, -kPi / 2), Vec3::UnitZ()}};
  const Vec3 tool0(kPi, 0, kPi);
  for (const JointVector& q : randomJoints(cell.robot, 200, 161)) {
    expectSamePose(computeFlangePose(cell.robot, q), urdfToolPose(chain, tool0, q), "KR 16");
  }
  // KUKA's mastering pose A2 = -90, A3 = +90: upper arm up, forearm level, flange 968 mm out.
  const Pose home = computeFlangePose(cell.robot, {0, -90 * kDeg, 90 * kDeg, 0, 0, 0});
  EXPECT_LT((home.translation() - Vec3(968, 0, 1450)).norm(), 1e-9);
}

// Fanuc M-10iA (ARC Mate 100iC): ros-industrial/fanuc, fanuc_m10ia_support/urdf/m10ia_macro.xacro.
// Its joint 3 is relative to the upper arm; the controller's J3 is relative to the horizontal:
// URDF joint 3 = J3 + J2. The cell's world origin is the URDF's base_link (floor), its robot base
// the URDF's `base` frame (the controller's world frame, 450 mm up).
TEST(VendorCells, FanucForwardKinematicsEqualsTheRosIndustrialDescription) {
  const Cell cell = readCell(cellsDir() / "fanuc_arcmate100ic_2axis_positioner.json");
  const std::vector<UrdfJoint> chain = {{Vec3(0, 0, 450), Vec3::Zero(), Vec3::UnitZ()},
                                        {Vec3(150, 0, 0), Vec3::Zero(), Vec3::UnitY()},
                                        {Vec3(0, 0, 600), Vec3::Zero(), -Vec3::UnitY()},
                                        {Vec3(0, 0, 200), Vec3::Zero(), -Vec3::UnitX()},
                                        {Vec3(640, 0, 0), Vec3::Zero(), -Vec3::UnitY()},
                                        {Vec3(100, 0, 0), Vec3::Zero(), -Vec3::UnitX()}};
  const Vec3 tool0(kPi, -kPi / 2, 0);
  for (const JointVector& q : randomJoints(cell.robot, 200, 100)) {
    const std::array<double, 6> urdf{q[0], q[1], q[2] + q[1], q[3], q[4], q[5]};
    expectSamePose(cell.robot.base * computeFlangePose(cell.robot, q),
                   urdfToolPose(chain, tool0, urdf), "M-10iA");
  }
  // J3 = 0 keeps the forearm level whatever J2: the wrist centre's height does not change.
  const RobotKinematics& k = cell.robot.kinematics;
  for (double j2 : {-30.0, 0.0, 40.0}) {
    const Pose flange = computeFlangePose(cell.robot, {0, j2 * kDeg, 0, 0, 0, 0});
    const Vec3 wrist = flange.translation() - k.c4 * flange.linear().col(2);
    EXPECT_NEAR(wrist.z(), k.c1 + k.c2 * std::cos(j2 * kDeg) + k.a2, 1e-9) << j2;
    EXPECT_NEAR(flange.linear().col(2).z(), 0.0, 1e-12) << j2;
  }
}

// ABB IRB 1660ID-6/1.55: OPW parameters of the RobotComponents preset (a1 150, a2 -110 there =
// forearm 110 mm above axis 3, c1 486.5, c2 700, c3 678, c4 135). ABB's joint directions and
// tool0 are checked against the ROS-Industrial IRB 1600-6/1.2 description (abb_experimental,
// abb_irb1600_support/urdf/irb1600_6_12_macro.xacro), the same arm family, by giving the cell's
// robot that robot's lengths.
TEST(VendorCells, AbbForwardKinematicsEqualsThePublishedDescriptions) {
  const Cell cell = readCell(cellsDir() / "abb_irb1660id_irbp_a250.json");
  // All axes at 0: flange centre 963 mm out (150 + 678 + 135) at 1296.5 mm (486.5 + 700 + 110),
  // tool0 z along +x, x down (ABB's calibration pose).
  const Pose zero = computeFlangePose(cell.robot, {0, 0, 0, 0, 0, 0});
  EXPECT_LT((zero.translation() - Vec3(963, 0, 1296.5)).norm(), 1e-9);
  EXPECT_LT((zero.linear().col(2) - Vec3::UnitX()).norm(), 1e-12);
  EXPECT_LT((zero.linear().col(0) + Vec3::UnitZ()).norm(), 1e-12);
  RobotDescription irb1600 = cell.robot;
  irb1600.kinematics = RobotKinematics{150, 0, 0, 486.5, 475, 600, 65};
  const std::vector<UrdfJoint> chain = {{Vec3::Zero(), Vec3::Zero(), Vec3::UnitZ()},
                                        {Vec3(150, 0, 486.5), Vec3::Zero(), Vec3::UnitY()},
                                        {Vec3(0, 0, 475), Vec3::Zero(), Vec3::UnitY()},
                                        {Vec3(300, 0, 0), Vec3::Zero(), Vec3::UnitX()},
                                        {Vec3(300, 0, 0), Vec3::Zero(), Vec3::UnitY()},
                                        {Vec3(65, 0, 0), Vec3::Zero(), Vec3::UnitX()}};
  for (const JointVector& q : randomJoints(cell.robot, 200, 1660)) {
    expectSamePose(computeFlangePose(irb1600, q), urdfToolPose(chain, Vec3(0, kPi / 2, 0), q),
                   "IRB 1600");
  }
}

/// The difference of two angles, wrapped to (-π, π].
double angleDifference(double a, double b) {
  return std::remainder(a - b, 2.0 * kPi);
}

TEST(VendorCells, InverseKinematicsReproducesRandomJointsWithinLimits) {
  for (const VendorCell& c : kCells) {
    SCOPED_TRACE(c.file);
    const Cell cell = readCell(cellsDir() / c.file);
    int checked = 0;
    for (const JointVector& q : randomJoints(cell.robot, 400, 2026)) {
      const Pose flange = computeFlangePose(cell.robot, q);
      const IkResult ik = solveInverseKinematics(cell.robot, flange, q[3]);
      ASSERT_FALSE(ik.solutions.empty());
      bool found = false;
      for (const IkSolution& s : ik.solutions) {
        expectSamePose(computeFlangePose(cell.robot, s.joints), flange, "solution");
        if (s.wristSingular) continue;
        bool same = true;
        for (int j = 0; j < 6; ++j)
          same = same && std::abs(angleDifference(s.joints[j], q[j])) < 1e-7;
        if (same) {
          found = true;
          EXPECT_TRUE(s.withinLimits);
        }
      }
      if (std::abs(std::sin(q[4] - cell.robot.jointOffsets[4])) < 1e-3) continue;  // near singular
      EXPECT_TRUE(found) << "joints " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << " "
                         << q[4] << " " << q[5];
      ++checked;
    }
    EXPECT_GT(checked, 390);
  }
}

TEST(VendorCells, HomePosesAreWithinLimitsVerticalAndClearOfTheTable) {
  for (const VendorCell& c : kCells) {
    SCOPED_TRACE(c.file);
    const Cell cell = readCell(cellsDir() / c.file);
    for (int i = 0; i < 6; ++i) EXPECT_TRUE(cell.robot.joints[i].contains(cell.home.robot[i]));
    const Pose tcp =
        cell.robot.base * computeFlangePose(cell.robot, cell.home.robot) * cell.tool.tcp;
    const Pose table = computeTableInWorld(cell.positioner, cell.home.a1, cell.home.a2);
    const Vec3 z = tcp.rotation().col(2);
    EXPECT_NEAR(z.dot(cell.gravity.normalized()), 1.0, 1e-6) << "torch vertical at home";
    const TorchEnvelope& env = cell.tool.envelope;
    double closest = 1e9;
    for (int k = 0; k <= 100; ++k) {
      const Vec3 world = tcp.translation() - (env.stickout + env.length * k / 100.0) * z;
      const double radius = env.radius + (env.topRadius - env.radius) * k / 100.0;
      closest = std::min(closest, robot_test::distanceFromTableAndVolume(cell.positioner.geometry,
                                                                         table.inverse() * world) -
                                      radius);
    }
    EXPECT_GT(closest, 50.0) << "the torch at home keeps 50 mm from the table and working volume";
    const Vec3 tcpInTable = table.inverse() * tcp.translation();
    EXPECT_GT(std::hypot(tcpInTable.x(), tcpInTable.y()), cell.positioner.geometry.maxPartRadius);
  }
}

TEST(VendorCells, AnotherVendorsLanguageIsRefusedUnlessAllowed) {
  const char* formats[] = {"jbi", "krl", "rapid", "ls", "gcode", "csv", "json"};
  for (const VendorCell& c : kCells) {
    const Cell cell = readCell(cellsDir() / c.file);
    for (const char* format : formats) {
      SCOPED_TRACE(std::string(c.file) + " " + format);
      const RobotVendor language = vendorOfFormat(format);
      EXPECT_NO_THROW(checkCellVendor(cell, format, true));
      if (language == RobotVendor::Unknown || language == c.vendor) {
        EXPECT_NO_THROW(checkCellVendor(cell, format, false));
        continue;
      }
      try {
        checkCellVendor(cell, format, false);
        ADD_FAILURE() << "accepted";
      } catch (const InvalidInput& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("the cell is for a " + std::string(toString(c.vendor)) +
                         " controller but the format " + format + " is for " +
                         std::string(toString(language))),
                  std::string::npos)
            << m;
        EXPECT_NE(m.find("--allow-foreign-cell"), std::string::npos) << m;
      }
    }
  }
  // A cell without "vendor": a note says so, and no format is refused.
  std::ifstream in(cellsDir() / kCells[0].file);
  Json j = Json::parse(in);
  j.erase("vendor");
  const Cell unknown = parseCell(j.dump(), "mine.json");
  EXPECT_EQ(unknown.vendor, RobotVendor::Unknown);
  ASSERT_EQ(unknown.notes.size(), 1u);
  EXPECT_NE(unknown.notes[0].find("cell names no vendor"), std::string::npos);
  for (const char* format : formats) EXPECT_NO_THROW(checkCellVendor(unknown, format, false));
  EXPECT_EQ(Json::parse(writeCellJson(unknown)).count("vendor"), 0u);
}

TEST(VendorCells, StationPulsesNeedThePositionersPulsesPerDegree) {
  const Cell kuka = readCell(cellsDir() / "kuka_kr16_r1610_2_dkp400.json");
  EXPECT_EQ(kuka.positioner.tilt.pulsesPerDegree, 0.0);  // not given: degrees on a KRC
  try {
    positionerPulses(kuka.positioner.tilt, 0.5);
    ADD_FAILURE() << "pulses without pulses per degree";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("positioner/tilt/pulses_per_degree"), std::string::npos);
  }
  EXPECT_EQ(positionerPulses(defaultCell().positioner.tilt, 1.0 * kDeg), 1994);
  EXPECT_EQ(Json::parse(writeCellJson(kuka))["positioner"]["tilt"].count("pulses_per_degree"), 0u);
}

}  // namespace
}  // namespace curvedslicer
