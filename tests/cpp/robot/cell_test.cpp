// Cell description: the default cell equals its resource file, round trips, and every bad field
// gives its own error naming the JSON path.
#include "curvedslicer/robot/cell.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "robot_test_support.hpp"

namespace curvedslicer {
namespace {

using Json = nlohmann::json;
using robot_test::distanceFromTableAndVolume;

std::filesystem::path defaultCellFile() {
  return std::filesystem::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "cells" /
         "motoman_hp20d_tilt_rotate.json";
}

Json defaultJson() {
  std::ifstream in(defaultCellFile());
  return Json::parse(in);
}

/// Expects parseCell(json) to throw InvalidInput whose message contains every `needle`.
void expectInvalid(const Json& json, std::initializer_list<std::string> needles) {
  try {
    parseCell(json.dump(), "test.json");
    ADD_FAILURE() << "no error for " << *needles.begin();
  } catch (const InvalidInput& e) {
    const std::string message = e.what();
    for (const auto& needle : needles) {
      EXPECT_NE(message.find(needle), std::string::npos)
          << "message \"" << message << "\" lacks \"" << needle << "\"";
    }
    EXPECT_NE(message.find("; "), std::string::npos) << message;  // says what to do
  }
}

TEST(Cell, DefaultCellEqualsResourceFile) {
  const Cell fromFile = readCell(defaultCellFile());
  EXPECT_EQ(writeCellJson(fromFile), writeCellJson(defaultCell()));
  EXPECT_EQ(fromFile.robot.model, "Yaskawa Motoman HP20D");
  EXPECT_DOUBLE_EQ(fromFile.positioner.tilt.pulsesPerDegree, 1994.3);
  EXPECT_NEAR(fromFile.robot.joints[1].max, 155.0 * M_PI / 180.0, 1e-15);
  EXPECT_TRUE(fromFile.positioner.rotation.endless);
}

TEST(Cell, WriteReadRoundTrip) {
  Cell cell = defaultCell();
  cell.robot.base = makePose(Vec3(10, -20, 30), Vec3(0.1, -0.2, 0.3));
  cell.positioner.tableToPart = makePose(Vec3(1, 2, 3), Vec3(0, 0, 1.0));
  cell.robot.pulsesPerDegree = {1000, 1100, 1200, 900, 800, 500};
  cell.exportOptions.positionType = PositionType::Pulse;
  cell.process.arcControl = ArcControl::Direct;
  cell.process.current = 180;
  cell.process.voltage = 19.5;
  const std::string text = writeCellJson(cell);
  const Cell back = parseCell(text);
  EXPECT_EQ(writeCellJson(back), text);
  EXPECT_TRUE(back.robot.base.isApprox(cell.robot.base, 1e-9));
  EXPECT_EQ(back.exportOptions.positionType, PositionType::Pulse);
  EXPECT_EQ(back.process.arcControl, ArcControl::Direct);
  EXPECT_DOUBLE_EQ(back.process.voltage, 19.5);
}

TEST(Cell, MinimumLayerTimeDefaultsTo30SecondsAndZeroTurnsItOff) {
  Json j = Json::parse(writeCellJson(defaultCell()));
  EXPECT_DOUBLE_EQ(j["process"]["min_layer_time_s"].get<double>(), 30.0);
  j["process"]["min_layer_time_s"] = 0;
  EXPECT_DOUBLE_EQ(parseCell(j.dump()).process.minLayerTime, 0.0);
  j["process"]["min_layer_time_s"] = 45.5;
  EXPECT_DOUBLE_EQ(parseCell(j.dump()).process.minLayerTime, 45.5);
  j["process"].erase("min_layer_time_s");  // a file written before the field existed
  EXPECT_DOUBLE_EQ(parseCell(j.dump()).process.minLayerTime, kDefaultMinLayerTime);
}

TEST(Cell, PoseRollPitchYawRoundTrip) {
  const Vec3 rpy(0.3, -1.1, 2.9);
  const Pose pose = makePose(Vec3(1, 2, 3), rpy);
  EXPECT_TRUE(rollPitchYaw(pose.rotation()).isApprox(rpy, 1e-12));
}

TEST(Cell, EachBadFieldHasItsOwnError) {
  struct Case {
    std::string pointer;  // JSON pointer to change
    Json value;           // new value; null = remove the field
    std::string needle;   // expected words besides the pointer
  };
  const std::vector<Case> cases = {
      {"/robot/kinematics_mm/c2", nullptr, "is missing"},
      {"/robot/kinematics_mm/c2", -760, "must be positive"},
      {"/robot/kinematics_mm/c4", -1, "must not be negative"},
      {"/robot/joints/1/limits_deg", Json::array({10, -10}), "minimum must be below maximum"},
      {"/robot/joints/4/max_speed_deg_s", 0, "must be between 0.1 and 10000"},
      {"/robot/joints/2/sign", 2, "must be 1 or -1"},
      {"/robot/joints", Json::array({1, 2}), "array of 6"},
      {"/robot/base/xyz_mm", Json::array({1, 2}), "array of 3"},
      {"/robot/model", 42, "must be a string"},
      {"/robot/modle", "x", "is not a known field"},
      {"/robot/pulses_per_degree", Json::array({1, 2, 3, 4, 5, -6}), "must be positive"},
      {"/tool/tcp", nullptr, "is missing"},
      {"/tool/number", 99, "between 0 and 63"},
      {"/gravity", Json::array({0, 0, 0}), "non-zero"},
      {"/positioner/rotation_axis/direction", Json::array({1, 0, 0}), "parallel to the tilt axis"},
      {"/positioner/tilt_axis/direction", Json::array({0, 0, 0}), "non-zero"},
      {"/positioner/tilt/endless", true, "only allowed for the rotation axis"},
      {"/positioner/tilt/pulses_per_degree", 0, "must be positive"},
      {"/positioner/rotation/sign", 0, "must be 1 or -1"},
      {"/positioner/table_to_part", nullptr, "is missing"},
      {"/process/weld_speed_mm_s", "fast", "must be a number"},
      {"/process/wire_diameter_mm", 0, "must be positive"},
      {"/process/speed_unit", "furlong/fortnight", "must be one of"},
      {"/process/deposition_efficiency", 1.5, "must be in (0, 1]"},
      {"/process/layer_dwell_s", -5, "must be between 0 and 86400"},
      {"/process/min_layer_time_s", -1, "must be between 0 and 86400"},
      {"/process/min_layer_time_s", 1e9, "must be between 0 and 86400"},
      {"/process/arc/start_condition", 0, "between 1 and 48"},
      {"/process/arc/control", "plasma", "must be one of"},
      {"/export/line_ending", "cr", "must be one of"},
      {"/export/job_name", "MUCHTOOLONG", "max_name_length"},
      {"/export/job_name", "A B", "letters, digits"},
      {"/export/max_lines_per_job", 5, "between 20"},
      {"/export/coordinated", "yes", "true or false"},
      // version 2 fields
      {"/version", 4, "between 1 and 3"},
      // physical bounds: unit slips and values beyond a controller's integer ranges
      {"/positioner/rotation/pulses_per_degree", 1e300, "32-bit range"},
      {"/positioner/tilt/pulses_per_degree", 1e12, "32-bit range at 95 deg"},
      {"/home/positioner_deg", Json::parse("[0, 1e308]"), "within +-3600 degrees"},
      {"/process/layer_dwell_s", 1e300, "must be between 0 and 86400"},
      {"/robot/joints/0/max_speed_deg_s", 1e-9, "must be between 0.1 and 10000"},
      {"/robot/joints/5/limits_deg", Json::parse("[-1e6, 1e6]"), "within +-3600 degrees"},
      {"/tool/tcp/xyz_mm", Json::parse("[0, 0, -400]"), "on or behind the flange"},
      // the whole-cell collision model (cell version 3)
      {"/robot/link_capsules_mm", nullptr, "is missing"},
      {"/robot/link_capsules_mm/forearm", nullptr, "is missing"},
      {"/robot/link_capsules_mm/wrist", -5, "must be positive"},
      {"/robot/link_capsules_mm/elbow", 5000, "must be at most 1000 mm"},
      {"/robot/link_capsules_mm/upper_arm_offset", 1e9, "within +-1000 mm"},
      {"/robot/link_capsules_mm/shoulder", 100, "is not a known field"},
      {"/positioner/geometry/body_radius_mm", nullptr, "is missing"},
      {"/positioner/geometry/body_radius_mm", 0, "must be positive"},
      {"/tool/envelope", nullptr, "is missing"},
      {"/tool/envelope", 12, "must be an object"},
      {"/tool/envelope/radius_mm", 0, "must be positive"},
      {"/tool/envelope/radius_mm", "wide", "must be a number"},
      {"/tool/envelope/top_radius_mm", -25, "must be positive"},
      {"/tool/envelope/length_mm", nullptr, "is missing"},
      {"/tool/envelope/stickout_mm", -1, "must not be negative"},
      {"/tool/envelope/nozzle_mm", 3, "is not a known field"},
      {"/positioner/geometry", nullptr, "is missing"},
      {"/positioner/geometry/table_radius_mm", 0, "must be positive"},
      {"/positioner/geometry/table_thickness_mm", nullptr, "is missing"},
      {"/positioner/geometry/max_part_radius_mm", -350, "must be positive"},
      {"/positioner/geometry/max_part_height_mm", "tall", "must be a number"},
      {"/home", nullptr, "is missing"},
      {"/home/robot_joints_deg", Json::array({0, 0, 0}), "array of 6"},
      {"/home/robot_joints_deg", Json::array({0, -20, -10, 0, -130, 0}), "joint 5 (B)"},
      {"/home/positioner_deg", Json::array({0}), "array of 2"},
      {"/home/positioner_deg", Json::array({150, 0}), "tilt outside its limits"},
      {"/home/joints_deg", Json::array({0}), "is not a known field"},
      {"/vendor", "motoman", "must be one of yaskawa, kuka, abb, fanuc"},
      {"/vendor", 7, "must be a string"},
      {"/robot/j3_relative_to_horizontal", "yes", "must be true or false"},
      {"/robot/controller_frame/xyz_mm", Json::array({0, 505}), "array of 3"},
      {"/robot/controller_frame/scale", 1, "is not a known field"},
      {"/robot/interference", Json::object(), "must be an array"},
      {"/robot/interference",
       Json::parse(R"([{"name": "L/U", "coefficients": [0, 0, 0, 0, 0, 0], "max_deg": 1}])"),
       "must not all be zero"},
      {"/robot/interference", Json::parse(R"([{"name": "L/U", "coefficients": [0, 1, 1]}])"),
       "array of 6"},
      {"/robot/interference",
       Json::parse(R"([{"name": "L/U", "coefficients": [0, 1, 1, 0, 0, 0]}])"), "is missing"},
      // controller section: LS / JBI blocks (s9-export2)
      {"/controller/ls/arc_start_schedule", nullptr, "is missing"},
      {"/controller/ls/weld_equipment", 3, "between 1 and 2"},
      {"/controller/ls/max_lines_per_program", 5, "between 20"},
      {"/controller/ls", 1, "must be an object"},
      {"/controller/jbi/arc_wait_input", -1, "between 0 and 2048"},
      {"/controller/xyz", Json::object(), "is not a known field"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.pointer);
    Json j = defaultJson();
    const Json::json_pointer ptr(c.pointer);
    if (c.value.is_null()) {
      j[ptr.parent_pointer()].erase(ptr.back());
    } else {
      j[ptr] = c.value;
    }
    expectInvalid(j, {c.pointer, c.needle, "test.json"});
  }
}

// Files written before robot/controller_frame and robot/interference existed load with the
// vendor's controller frame and no interference limit, each named in a note.
TEST(Cell, OldFilesGetTheVendorsControllerFrameAndNoInterferenceWithNotes) {
  Json j = defaultJson();
  j["robot"].erase("controller_frame");
  j["robot"].erase("interference");
  const Cell yaskawa = parseCell(j.dump(), "old.json");
  EXPECT_TRUE(yaskawa.robot.controllerFrame.isApprox(defaultCell().robot.controllerFrame));
  EXPECT_NEAR(yaskawa.robot.controllerFrame.translation().z(), 505.0, 1e-12);
  EXPECT_TRUE(yaskawa.robot.interference.empty());
  ASSERT_EQ(yaskawa.notes.size(), 2u);
  EXPECT_NE(yaskawa.notes[0].find("robot/controller_frame not given: the yaskawa convention "
                                  "taken: on joint 1's axis at the height of joint 2, 505 mm "
                                  "above robot/base"),
            std::string::npos)
      << yaskawa.notes[0];
  EXPECT_NE(yaskawa.notes[1].find("robot/interference not given: no joint interference limit "
                                  "assumed"),
            std::string::npos)
      << yaskawa.notes[1];
  j["vendor"] = "kuka";
  const Cell kuka = parseCell(j.dump(), "old.json");
  EXPECT_TRUE(kuka.robot.controllerFrame.isApprox(Pose::Identity()));
  EXPECT_NE(kuka.notes[0].find("the kuka convention taken: the robot base frame itself"),
            std::string::npos)
      << kuka.notes[0];
  j["vendor"] = "fanuc";
  EXPECT_NEAR(parseCell(j.dump()).robot.controllerFrame.translation().z(), 505.0, 1e-12);
  // Written again, both fields are spelled out and the cell reads without notes.
  EXPECT_TRUE(parseCell(writeCellJson(yaskawa)).notes.empty());
}

TEST(Cell, InterferenceLimitsRoundTripAndGuardTheHome) {
  Cell cell = defaultCell();
  cell.robot.interference.push_back({"L/U", {0, 1, 1, 0, 0, 0}, 100.0 * M_PI / 180.0});
  const std::string text = writeCellJson(cell);
  const Cell back = parseCell(text);
  EXPECT_EQ(writeCellJson(back), text);
  ASSERT_EQ(back.robot.interference.size(), 1u);
  EXPECT_EQ(back.robot.interference[0].name, "L/U");
  EXPECT_NEAR(back.robot.interference[0].max, 100.0 * M_PI / 180.0, 1e-12);
  const double atLimit = 100.0 * M_PI / 180.0 - 1.0;  // L = 1 rad, U at the bound L + U = 100 deg
  EXPECT_EQ(violatedInterference(back.robot, {0, 1.0, atLimit, 0, 0, 0}), nullptr);
  EXPECT_NE(violatedInterference(back.robot, {0, 1.0, atLimit + 1e-6, 0, 0, 0}), nullptr);
  // The home (L = -20 deg) must satisfy them.
  Json j = defaultJson();
  j["robot"]["interference"] =
      Json::parse(R"([{"name": "L/U", "coefficients": [0, 1, 0, 0, 0, 0], "max_deg": -30}])");
  expectInvalid(j, {"/home/robot_joints_deg", "violates the robot's interference limit L/U"});
}

/// The default cell written as version 1: without the version-2 fields.
Json versionOneJson() {
  Json j = defaultJson();
  j["version"] = 1;
  j["robot"].erase("link_capsules_mm");
  j["tool"].erase("envelope");
  j["positioner"].erase("geometry");
  j.erase("home");
  return j;
}

/// The default cell as a version-2 file: without the arm's capsules and the positioner's body.
Json versionTwoJson() {
  Json j = defaultJson();
  j["version"] = 2;
  j["robot"].erase("link_capsules_mm");
  j["positioner"]["geometry"].erase("body_radius_mm");
  return j;
}

TEST(Cell, VersionOneLoadsWithStatedDefaultsAndNotes) {
  const Cell v1 = parseCell(versionOneJson().dump(), "old.json");
  const Cell v2 = defaultCell();
  EXPECT_EQ(v1.tool.envelope.stickout, TorchEnvelope{}.stickout);
  EXPECT_EQ(v1.tool.envelope.radius, 12.5);
  EXPECT_EQ(v1.tool.envelope.topRadius, 25.0);
  EXPECT_EQ(v1.tool.envelope.length, 385.0);
  EXPECT_EQ(v1.positioner.geometry.tableRadius, 300.0);
  EXPECT_EQ(v1.positioner.geometry.maxPartHeight, 500.0);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(v1.home.robot[i], 0.0);
  EXPECT_EQ(v1.home.a1, 0.0);
  // Everything else as read; the defaults are stated in one note per section.
  EXPECT_EQ(v1.robot.model, v2.robot.model);
  EXPECT_TRUE(v1.tool.tcp.isApprox(v2.tool.tcp));
  ASSERT_EQ(v1.notes.size(), 4u);
  EXPECT_NE(v1.notes[0].find("robot arm is not checked"), std::string::npos) << v1.notes[0];
  EXPECT_NE(v1.notes[1].find("cell version 1: default torch envelope assumed"), std::string::npos)
      << v1.notes[1];
  EXPECT_NE(v1.notes[1].find("radius 12.5 mm"), std::string::npos) << v1.notes[1];
  EXPECT_NE(v1.notes[1].find("add tool/envelope"), std::string::npos) << v1.notes[1];
  EXPECT_NE(v1.notes[2].find("positioner/geometry"), std::string::npos) << v1.notes[2];
  EXPECT_NE(v1.notes[3].find("home pose"), std::string::npos) << v1.notes[3];
  EXPECT_TRUE(v2.notes.empty());
  EXPECT_TRUE(readCell(defaultCellFile()).notes.empty());
  // Without "version" a file is version 1 (as before version 2 existed).
  Json noVersion = versionOneJson();
  noVersion.erase("version");
  EXPECT_EQ(parseCell(noVersion.dump()).notes.size(), 4u);
  // Written again, a version-1 cell becomes version 2 with the defaults spelled out (its arm
  // stays unknown, which version 2 reads as such).
  const Json rewritten = Json::parse(writeCellJson(v1));
  EXPECT_EQ(rewritten["version"], 2);
  EXPECT_EQ(rewritten["tool"]["envelope"]["length_mm"], 385.0);
  EXPECT_EQ(parseCell(rewritten.dump()).notes.size(), 2u);  // the arm and the body unchecked
}

TEST(Cell, VersionOneRefusesVersionTwoFields) {
  Json j = versionOneJson();
  j["home"] = defaultJson()["home"];
  expectInvalid(j, {"/home", "needs cell version 2", "\"version\": 2"});
  j = versionOneJson();
  j["tool"]["envelope"] = defaultJson()["tool"]["envelope"];
  expectInvalid(j, {"/tool/envelope", "needs cell version 2"});
  j = versionOneJson();
  j["positioner"]["geometry"] = defaultJson()["positioner"]["geometry"];
  expectInvalid(j, {"/positioner/geometry", "needs cell version 2"});
}

// A version-2 file (before the arm model) loads with the arm and the positioner's body
// unchecked, each named in a note; version-3 fields in it are refused.
TEST(Cell, VersionTwoLoadsWithoutTheArmAndSaysSo) {
  const Cell v2 = parseCell(versionTwoJson().dump(), "v2.json");
  EXPECT_FALSE(v2.robot.links.known());
  EXPECT_EQ(v2.positioner.geometry.bodyRadius, 0.0);
  ASSERT_EQ(v2.notes.size(), 2u);
  EXPECT_NE(v2.notes[0].find("cell version 2: robot/link_capsules_mm not given, so the robot arm "
                             "is not checked for collisions"),
            std::string::npos)
      << v2.notes[0];
  EXPECT_NE(v2.notes[1].find("positioner/geometry/body_radius_mm not given"), std::string::npos)
      << v2.notes[1];
  EXPECT_EQ(Json::parse(writeCellJson(v2))["version"], 2);
  Json j = versionTwoJson();
  j["robot"]["link_capsules_mm"] = defaultJson()["robot"]["link_capsules_mm"];
  expectInvalid(j, {"/robot/link_capsules_mm", "needs cell version 3", "\"version\": 3"});
  j = versionTwoJson();
  j["positioner"]["geometry"]["body_radius_mm"] = 150;
  expectInvalid(j, {"/positioner/geometry/body_radius_mm", "needs cell version 3"});
}

TEST(Cell, VersionThreeRoundTripKeepsEnvelopeGeometryArmAndHome) {
  Cell cell = defaultCell();
  cell.tool.envelope = TorchEnvelope{18.0, 11.0, 31.5, 290.0};
  cell.positioner.geometry = PositionerGeometry{225.0, 25.0, 260.0, 410.5, 0.0};
  cell.home.robot = {0.1, -0.2, 0.3, -0.4, -1.5, 0.6};
  cell.home.a1 = -0.5;
  cell.home.a2 = 7.0;  // the rotation axis is endless: beyond its ±360° is fine
  cell.robot.links = ArmEnvelope{301.5, 99.0, 12.25, 250.0, 120.0, 70.5};
  cell.positioner.geometry.bodyRadius = 140.0;
  const std::string text = writeCellJson(cell);
  EXPECT_NE(text.find("\"version\": 3"), std::string::npos);
  const Cell back = parseCell(text);
  EXPECT_EQ(writeCellJson(back), text);
  EXPECT_DOUBLE_EQ(back.robot.links.column, 301.5);
  EXPECT_DOUBLE_EQ(back.robot.links.upperArmOffset, 12.25);
  EXPECT_DOUBLE_EQ(back.robot.links.wrist, 70.5);
  EXPECT_DOUBLE_EQ(back.positioner.geometry.bodyRadius, 140.0);
  EXPECT_DOUBLE_EQ(back.tool.envelope.stickout, 18.0);
  EXPECT_DOUBLE_EQ(back.tool.envelope.topRadius, 31.5);
  EXPECT_DOUBLE_EQ(back.positioner.geometry.maxPartHeight, 410.5);
  EXPECT_DOUBLE_EQ(back.positioner.geometry.tableThickness, 25.0);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(back.home.robot[i], cell.home.robot[i], 1e-9);
  EXPECT_NEAR(back.home.a1, -0.5, 1e-9);
  EXPECT_NEAR(back.home.a2, 7.0, 7.0 * 1e-9 * 1.5);  // 401.07... deg written to 9 digits
  EXPECT_TRUE(back.notes.empty());
}

TEST(Cell, DefaultHomeIsReachableAndClearOfTableAndWorkingVolume) {
  const Cell cell = defaultCell();
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(cell.robot.joints[i].contains(cell.home.robot[i]));
  const Pose tcp =
      cell.robot.base * computeFlangePose(cell.robot, cell.home.robot) * cell.tool.tcp;  // world
  const Pose table = computeTableInWorld(cell.positioner, cell.home.a1, cell.home.a2);
  const Vec3 z = tcp.rotation().col(2);
  EXPECT_NEAR(z.dot(cell.gravity.normalized()), 1.0, 1e-6) << "torch vertical at home";
  const TorchEnvelope& env = cell.tool.envelope;
  double closest = 1e9;
  for (int k = 0; k <= 100; ++k) {  // the envelope's axis, nozzle to top, and its radius
    const double s = env.length * k / 100.0;
    const Vec3 world = tcp.translation() - (env.stickout + s) * z;
    const double radius = env.radius + (env.topRadius - env.radius) * k / 100.0;
    closest = std::min(
        closest,
        distanceFromTableAndVolume(cell.positioner.geometry, table.inverse() * world) - radius);
  }
  EXPECT_GT(closest, 50.0) << "the torch at home keeps 50 mm from the table and working volume";
  // The TCP itself: outside the working volume's radius.
  const Vec3 tcpInTable = table.inverse() * tcp.translation();
  EXPECT_GT(std::hypot(tcpInTable.x(), tcpInTable.y()), cell.positioner.geometry.maxPartRadius);
}

TEST(Cell, CrossFieldRules) {
  {
    Json j = defaultJson();
    j["export"]["position_type"] = "pulse";  // the default cell has no robot pulses
    expectInvalid(j, {"/robot/pulses_per_degree", "position_type"});
  }
  {
    Json j = defaultJson();
    j["process"]["arc"]["control"] = "direct";
    j["process"]["arc"].erase("current_a");
    expectInvalid(j, {"/process/arc/current_a", "is missing"});
  }
}

TEST(Cell, NotJsonOrNotAnObject) {
  EXPECT_THROW(parseCell("{ not json", "x.json"), InvalidInput);
  EXPECT_THROW(parseCell("[1, 2]", "x.json"), InvalidInput);
  try {
    parseCell("{ not json", "x.json");
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("not valid JSON"), std::string::npos);
  }
}

TEST(Cell, MissingFileIsIoError) {
  EXPECT_THROW(readCell("/nonexistent/cell.json"), IoError);
}

TEST(Cell, ValidateCellBuiltInCode) {
  Cell cell = defaultCell();
  EXPECT_NO_THROW(validateCell(cell));
  cell.process.weldSpeed = -1;
  try {
    validateCell(cell);
    ADD_FAILURE() << "negative weld speed accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("/process/weld_speed_mm_s"), std::string::npos);
  }
}

}  // namespace
}  // namespace curvedslicer
