// The cells of resources/cells/, one per vendor: every file valid by the cell schema and read
// without notes; forward kinematics, flange and controller frame equal to the published robot
// descriptions copied into tests/data/robots/ (sources there and in resources/cells/README.md);
// inverse kinematics reproducing random joint vectors within the limits; home poses clear of the
// table; the vendor check of exports (checkCellVendor).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "common/test_constants.hpp"
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

using testing::kDeg;
using testing::kPi;

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

/// A public robot description as copied into tests/data/robots/ (lengths converted to mm): the
/// joint chain base_link → joint_1 … joint_6, the fixed joints to tool0 (the controller's flange
/// frame) and to `base` (the controller's Cartesian robot frame), and how exactly the source
/// states its rotations.
struct ReferenceDescription {
  std::string file;
  std::vector<UrdfJoint> chain;
  Pose tool0 = Pose::Identity();
  Pose base = Pose::Identity();
  double rotationTolerance = 0.0;  // rad
};

Vec3 jsonVec3(const Json& j, double scale = 1.0) {
  return Vec3(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()) * scale;
}

ReferenceDescription readReference(const std::string& file) {
  std::ifstream in(fs::path(CURVEDSLICER_SOURCE_DIR) / "tests" / "data" / "robots" / file);
  EXPECT_TRUE(in) << file;
  const Json j = Json::parse(in);
  ReferenceDescription d;
  d.file = file;
  for (const Json& joint : j.at("joints")) {
    d.chain.push_back({jsonVec3(joint.at("xyz_m"), 1000.0), jsonVec3(joint.at("rpy_rad")),
                       jsonVec3(joint.at("axis"))});
  }
  d.tool0 =
      makePose(jsonVec3(j.at("tool0").at("xyz_m"), 1000.0), jsonVec3(j.at("tool0").at("rpy_rad")));
  d.base =
      makePose(jsonVec3(j.at("base").at("xyz_m"), 1000.0), jsonVec3(j.at("base").at("rpy_rad")));
  d.rotationTolerance = j.at("rotation_tolerance_rad").get<double>();
  EXPECT_EQ(d.chain.size(), 6u) << file;
  EXPECT_FALSE(j.at("source").at("commit").get<std::string>().empty()) << file;
  EXPECT_FALSE(j.at("licence").get<std::string>().empty()) << file;
  return d;
}

/// base_link → tool0 of a description for its joint angles (rad); mm.
Pose referenceToolPose(const ReferenceDescription& d, const std::array<double, 6>& q) {
  Pose pose = Pose::Identity();
  for (std::size_t i = 0; i < d.chain.size(); ++i) {
    pose = pose * makePose(d.chain[i].xyz, d.chain[i].rpy);
    pose.rotate(Eigen::AngleAxisd(q[i], d.chain[i].axis.normalized()));
  }
  return pose * d.tool0;
}

/// The ortho-parallel lengths of a description whose joint origins carry no rotation (Motoman,
/// ABB): read off the joint origins at its zero pose — joint 2 at (a1, b, c1), joint 3 c2 above
/// it, the wrist centre (joint 5) c3 forward and a2 up from joint 3, tool0 c4 beyond the wrist.
RobotKinematics lengthsAtZero(const ReferenceDescription& d) {
  std::vector<Vec3> at;
  Vec3 p = Vec3::Zero();
  for (const UrdfJoint& joint : d.chain) {
    EXPECT_LT(joint.rpy.norm(), 1e-12) << d.file << ": joint origins must not rotate";
    p += joint.xyz;
    at.push_back(p);
  }
  const Vec3 tool = p + d.tool0.translation();
  return RobotKinematics{at[1].x(),           at[4].z() - at[2].z(), at[1].y(),
                         at[1].z(),           at[2].z() - at[1].z(), at[4].x() - at[2].x(),
                         tool.x() - at[4].x()};
}

/// Random controller joint vectors within the joint limits (seeded).
/// `count` joint vectors drawn uniformly from the joint ranges, keeping those that satisfy the
/// robot's interference limits (the poses the robot can take).
std::vector<JointVector> randomJoints(const RobotDescription& robot, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<JointVector> out;
  while (static_cast<int>(out.size()) < count) {
    JointVector q;
    for (int j = 0; j < 6; ++j) {
      q[j] = std::uniform_real_distribution<double>(robot.joints[j].min, robot.joints[j].max)(rng);
    }
    if (violatedInterference(robot, q) == nullptr) out.push_back(q);
  }
  return out;
}

void expectSamePose(const Pose& a, const Pose& b, const std::string& what) {
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-6) << what;
  EXPECT_LT((a.linear() - b.linear()).norm(), 1e-9) << what;
}

/// The cell's flange pose (world) equals the description's tool0 (base_link) at 250 random joint
/// vectors within the cell's limits: positions to 1e-6 mm, orientations to the source's
/// precision (at most 1e-6 rad, far below 0.01°); and the cell's controller frame is the
/// description's `base`. `urdfJoints` maps controller joints to the description's.
void expectFlangeIsReferenceTool0(
    const RobotDescription& robot, const ReferenceDescription& d, unsigned seed,
    const std::function<std::array<double, 6>(const JointVector&)>& urdfJoints) {
  SCOPED_TRACE(d.file);
  double worstMm = 0.0, worstRad = 0.0;
  for (const JointVector& q : randomJoints(robot, 250, seed)) {
    const Pose cell = robot.base * computeFlangePose(robot, q);
    const Pose reference = referenceToolPose(d, urdfJoints(q));
    worstMm = std::max(worstMm, (cell.translation() - reference.translation()).norm());
    worstRad = std::max(worstRad,
                        Eigen::AngleAxisd(cell.linear().transpose() * reference.linear()).angle());
  }
  EXPECT_LT(worstMm, 1e-6);
  EXPECT_LT(worstRad, d.rotationTolerance);
  EXPECT_LE(d.rotationTolerance, 0.01 * kDeg);
  const Pose controller = robot.base * robot.controllerFrame;
  EXPECT_LT((controller.translation() - d.base.translation()).norm(), 1e-9);
  EXPECT_LT(Eigen::AngleAxisd(controller.linear().transpose() * d.base.linear()).angle(), 1e-12);
}

std::array<double, 6> sameJoints(const JointVector& q) {
  return q;
}

// KUKA KR 16 R1610-2: the description's joint angles are the controller's A1..A6.
TEST(VendorCells, KukaForwardKinematicsEqualsTheReferenceDescription) {
  const Cell cell = readCell(cellsDir() / "kuka_kr16_r1610_2_dkp400.json");
  expectFlangeIsReferenceTool0(cell.robot, readReference("kuka_kr16_r1610_2.json"), 161,
                               sameJoints);
  // KUKA's mastering pose A2 = -90, A3 = +90: upper arm up, forearm level, flange 968 mm out.
  const Pose home = computeFlangePose(cell.robot, {0, -90 * kDeg, 90 * kDeg, 0, 0, 0});
  EXPECT_LT((home.translation() - Vec3(968, 0, 1450)).norm(), 1e-9);
}

// Fanuc M-10iA (ARC Mate 100iC): the description's joint 3 is relative to the upper arm, the
// controller's J3 to the horizontal: URDF joint 3 = J3 + J2. The cell's world origin is the
// description's base_link (floor), its robot base and controller frame the description's `base`
// (the controller's world frame, 450 mm up).
TEST(VendorCells, FanucForwardKinematicsEqualsTheReferenceDescription) {
  const Cell cell = readCell(cellsDir() / "fanuc_arcmate100ic_2axis_positioner.json");
  expectFlangeIsReferenceTool0(
      cell.robot, readReference("fanuc_m10ia.json"), 100, [](const JointVector& q) {
        return std::array<double, 6>{q[0], q[1], q[2] + q[1], q[3], q[4], q[5]};
      });
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
// forearm 110 mm above axis 3, c1 486.5, c2 700, c3 678, c4 135). ABB's joint directions, tool0
// and base frame are checked against the description of the IRB 1600-6/1.2, the same arm family,
// by giving the cell's robot that robot's lengths.
TEST(VendorCells, AbbForwardKinematicsEqualsTheReferenceDescription) {
  const Cell cell = readCell(cellsDir() / "abb_irb1660id_irbp_a250.json");
  // All axes at 0: flange centre 963 mm out (150 + 678 + 135) at 1296.5 mm (486.5 + 700 + 110),
  // tool0 z along +x, x down (ABB's calibration pose).
  const Pose zero = computeFlangePose(cell.robot, {0, 0, 0, 0, 0, 0});
  EXPECT_LT((zero.translation() - Vec3(963, 0, 1296.5)).norm(), 1e-9);
  EXPECT_LT((zero.linear().col(2) - Vec3::UnitX()).norm(), 1e-12);
  EXPECT_LT((zero.linear().col(0) + Vec3::UnitZ()).norm(), 1e-12);
  const ReferenceDescription irb1600 = readReference("abb_irb1600_6_12.json");
  RobotDescription robot = cell.robot;
  robot.kinematics = lengthsAtZero(irb1600);
  EXPECT_NEAR(robot.kinematics.c2, 475.0, 1e-9);  // the lengths are read off correctly
  EXPECT_NEAR(robot.kinematics.c3, 600.0, 1e-9);
  expectFlangeIsReferenceTool0(robot, irb1600, 1660, sameJoints);
}

// Yaskawa Motoman HP20D: its joint directions, T offset (flange = Yaskawa's flange = tool0) and
// controller frame (robot coordinates at the L axis) are checked against the Motoman GP25
// description, the arm of the same layout (S-L 150, L height 505, L-U 760, U-B 795, B-flange
// 100 mm; U offset 200 instead of the HP20D's 140 mm), by giving the cell's robot its lengths.
TEST(VendorCells, MotomanForwardKinematicsEqualsTheReferenceDescription) {
  const Cell cell = readCell(cellsDir() / "motoman_hp20d_tilt_rotate.json");
  const ReferenceDescription gp25 = readReference("motoman_gp25.json");
  RobotDescription robot = cell.robot;
  robot.kinematics = lengthsAtZero(gp25);
  EXPECT_NEAR(robot.kinematics.a2, 200.0, 1e-9);
  EXPECT_NEAR(robot.kinematics.c1, cell.robot.kinematics.c1, 1e-9);
  expectFlangeIsReferenceTool0(robot, gp25, 2025, sameJoints);
  // All joints 0: Yaskawa's flange has z forward and x up; the HP20D's flange centre lies at
  // (a1 + c3 + c4, 0, c1 + c2 + a2) = (1045, 0, 1405) mm, 900 mm above the L axis.
  const Pose zero = cell.robot.controllerFrame.inverse() * computeFlangePose(cell.robot, {});
  EXPECT_LT((zero.translation() - Vec3(1045, 0, 900)).norm(), 1e-9);
  EXPECT_LT((zero.linear().col(2) - Vec3::UnitX()).norm(), 1e-12);
  EXPECT_LT((zero.linear().col(0) - Vec3::UnitZ()).norm(), 1e-12);
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

// An interference limit (here L + U <= 30 deg on the HP20D) takes solutions out of the IK's
// "within limits" although every joint lies within its range: inverse kinematics never offers
// a violating solution as usable.
TEST(VendorCells, InverseKinematicsNeverOffersASolutionViolatingAnInterferenceLimit) {
  RobotDescription robot = readCell(cellsDir() / "motoman_hp20d_tilt_rotate.json").robot;
  const RobotDescription jointBox = robot;  // samples from the whole joint box
  robot.interference.push_back({"L/U", {0, 1, 1, 0, 0, 0}, 30 * kDeg});
  int violating = 0, kept = 0;
  for (const JointVector& q : randomJoints(jointBox, 300, 27)) {
    const IkResult ik = solveInverseKinematics(robot, computeFlangePose(robot, q), q[3]);
    for (const IkSolution& s : ik.solutions) {
      if (s.withinLimits) {
        EXPECT_EQ(violatedInterference(robot, s.joints), nullptr);
        ++kept;
      }
      bool same = true;
      for (int j = 0; j < 6; ++j)
        same = same && std::abs(angleDifference(s.joints[j], q[j])) < 1e-7;
      if (same && q[1] + q[2] > 30 * kDeg && std::abs(s.joints[2] - q[2]) < 1e-7) {
        EXPECT_FALSE(s.withinLimits);
        ++violating;
      }
    }
  }
  EXPECT_GT(violating, 20);
  EXPECT_GT(kept, 100);
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
