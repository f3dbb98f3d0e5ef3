// Cell description: the default cell equals its resource file, round trips, and every bad field
// gives its own error naming the JSON path.
#include "curvedslicer/robot/cell.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

using Json = nlohmann::json;

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
      {"/robot/joints/4/max_speed_deg_s", 0, "must be positive"},
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
      {"/process/layer_dwell_s", -5, "must not be negative"},
      {"/process/arc/start_condition", 0, "between 1 and 48"},
      {"/process/arc/control", "plasma", "must be one of"},
      {"/export/line_ending", "cr", "must be one of"},
      {"/export/job_name", "MUCHTOOLONG", "max_name_length"},
      {"/export/job_name", "A B", "letters, digits"},
      {"/export/max_lines_per_job", 5, "between 20"},
      {"/export/coordinated", "yes", "true or false"},
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
