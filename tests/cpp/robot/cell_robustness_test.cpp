// The cell reader on hostile files: deep nesting, numbers beyond the double range and
// huge values are InvalidInput naming the file and place, never a crash; the command line exits
// with code 2.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_test_support.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "curvedslicer/robot/cell.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string cellError(const std::string& text) {
  try {
    parseCell(text, "cell.json");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

std::string defaultCellText() {
  return writeCellJson(defaultCell());
}

TEST(CellRobustness, HundredThousandNestedObjectsAreRefusedNotRecursed) {
  std::string deep;
  for (int i = 0; i < 100000; ++i) deep += "{\"robot\":";
  const std::string message = cellError(deep);
  EXPECT_TRUE(contains(message,
                       "cell.json: not valid JSON: arrays and objects nest deeper than "
                       "64 levels at line 1, column 577"));
  EXPECT_TRUE(contains(message, "; fix the syntax of the cell file"));
}

TEST(CellRobustness, NumberBeyondTheDoubleRangeNamesFileAndLine) {
  std::string text = defaultCellText();
  const std::string key = "\"weld_speed_mm_s\": 8.0";
  ASSERT_NE(text.find(key), std::string::npos);
  text.replace(text.find(key), key.size(), "\"weld_speed_mm_s\": -1e999");
  const std::string message = cellError(text);
  EXPECT_TRUE(contains(message, "cell.json: not valid JSON: number overflow parsing '-1e999'"));
  EXPECT_TRUE(contains(message, " at line "));
}

TEST(CellRobustness, HugeValuesAreEchoedShort) {
  Json j = Json::parse(defaultCellText());
  Json big = Json::array();
  for (int i = 0; i < 100000; ++i) big.push_back(i);
  j["gravity"] = big;
  const std::string gravity = cellError(j.dump());
  EXPECT_TRUE(contains(gravity, "field /gravity must be an array of 3 numbers: [0,1,2,"));
  EXPECT_LT(gravity.size(), 300u);
  j = Json::parse(defaultCellText());
  j["export"]["job_name"] = std::string(100000, 'A');
  const std::string name = cellError(j.dump());
  EXPECT_TRUE(contains(name, "field /export/job_name must have 1 to max_name_length"));
  EXPECT_LT(name.size(), 300u);
  j = Json::parse(defaultCellText());
  j[std::string(100000, 'k')] = 1;
  const std::string key = cellError(j.dump());
  EXPECT_TRUE(contains(key, "is not a known field: \"kkkk"));
  EXPECT_LT(key.size(), 400u);
}

TEST(CellRobustness, SpeedsThatWouldBeWrittenAsZeroAreRefused) {
  Json j = Json::parse(defaultCellText());
  j["process"]["weld_speed_mm_s"] = 1e-300;
  EXPECT_TRUE(contains(cellError(j.dump()),
                       "field /process/weld_speed_mm_s would be written as 0 "
                       "in mm/s: 1e-300; give at least 0.05 mm/s"));
  j["process"]["weld_speed_mm_s"] = 0.05;
  EXPECT_EQ(cellError(j.dump()), "");
  j["process"]["speed_unit"] = "cm/min";
  EXPECT_TRUE(contains(cellError(j.dump()), "weld_speed_mm_s would be written as 0 in cm/min"));
  j["process"]["weld_speed_mm_s"] = 8;
  j["process"]["travel_speed_mm_s"] = 0.001;
  j["process"]["speed_unit"] = "mm/min";
  EXPECT_TRUE(contains(cellError(j.dump()), "travel_speed_mm_s would be written as 0 in mm/min"));
}

TEST(CellRobustness, CommandLineExitsWithTwoNamingTheFile) {
  const fs::path dir = testing::freshTempDir();
  Plan plan;
  plan.model = "model.stl";
  plan.start = "plane:bottom";
  plan.parameters = PlanParameters{1.5, 0.5, 3.7, 2.0, 0.05, "anyangle", "accurate", "boundary", "",
                                   {},  {},  {},  {},  {},   {},         {},         {}};
  PlanLayer layer;
  layer.index = 0;
  layer.height = 1.5;
  plan.layers.push_back(layer);
  writePlanJson(dir / "plan.json", plan);
  const fs::path deep = dir / "deep_cell.json";
  {
    std::ofstream out(deep);
    for (int i = 0; i < 100000; ++i) out << "[";
  }
  std::string text = defaultCellText();
  const std::string key = "\"travel_speed_mm_s\": 50.0";
  ASSERT_NE(text.find(key), std::string::npos);
  text.replace(text.find(key), key.size(), "\"travel_speed_mm_s\": 1e999");
  const fs::path overflow = dir / "overflow_cell.json";
  std::ofstream(overflow) << text;
  for (const fs::path& cell : {deep, overflow}) {
    const testing::CliRun run =
        testing::runCli({"export", (dir / "plan.json").string(), "--cell", cell.string(),
                         "--format", "jbi", "-o", (dir / "out.jbi").string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << run.err;
    EXPECT_TRUE(contains(
        run.err, "curvedslicer: error: " + cell.filename().string() + ": not valid JSON: "));
    EXPECT_FALSE(fs::exists(dir / "out.jbi"));
  }
}

}  // namespace
}  // namespace curvedslicer
