// The plan.json reader on hostile files: deep nesting, numbers beyond the double range,
// negative lengths, huge values echoed in messages. Each is an InvalidInput naming the file and
// the place, never a crash; through the command line each exits with code 2.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_test_support.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/plan/plan_io.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

/// A two-point, one-path, one-layer plan.
Plan makeTinyPlan() {
  Plan plan;
  plan.model = "model.stl";
  plan.start = "plane:bottom";
  plan.parameters = {1.5, 0.5, 3.7, 2.0, 0.05, "anyangle", "accurate", "boundary", "",
                     {},  {},  {},  {},  {},   {},         {},         {}};
  PlanLayer layer;
  layer.index = 0;
  layer.height = 1.5;
  PlanPath path;
  for (int i = 0; i < 2; ++i) {
    PathPoint q;
    q.position = Vec3(i, 0, 1.5);
    q.normal = Vec3::UnitZ();
    q.deposition = -Vec3::UnitZ();
    path.points.push_back(q);
  }
  path.length = 1.0;
  layer.paths.push_back(path);
  plan.layers.push_back(layer);
  return plan;
}

/// The message of the InvalidInput that parsePlanJson(text, "plan.json") throws ("" if none).
std::string readError(const std::string& text) {
  try {
    parsePlanJson(text, "plan.json");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

std::string editedPlan(const std::function<void(Json&)>& edit) {
  Json doc = Json::parse(formatPlanJson(makeTinyPlan()));
  edit(doc);
  return doc.dump();
}

TEST(PlanIoRobustness, HundredThousandNestedArraysAreRefusedNotRecursed) {
  const std::string deep(100000, '[');
  const std::string message = readError(deep + std::string(100000, ']'));
  EXPECT_TRUE(contains(message, "plan.json is not valid JSON"));
  EXPECT_TRUE(contains(message, "nest deeper than 64 levels at line 1, column 65"));
  EXPECT_TRUE(contains(message, "pass a plan.json written by `curvedslicer plan`"));
}

TEST(PlanIoRobustness, DeepObjectsInsideAPlanAreRefusedWithTheirLine) {
  std::string deep = "{\n\"format\": \"curvedslicer-plan\",\n\"model\": ";
  for (int i = 0; i < 100000; ++i) deep += "{\"a\":";
  const std::string message = readError(deep);
  EXPECT_TRUE(contains(message, "nest deeper than 64 levels at line 3, column"));
}

TEST(PlanIoRobustness, BracketsInsideStringsDoNotCountAsNesting) {
  Plan plan = makeTinyPlan();
  plan.model = std::string(500, '[') + "\\\"{" + std::string(500, '{');
  const Plan back = parsePlanJson(formatPlanJson(plan), "plan.json");
  EXPECT_EQ(back.model, plan.model);
}

TEST(PlanIoRobustness, NumberBeyondTheDoubleRangeNamesFileLineAndColumn) {
  std::string text = formatPlanJson(makeTinyPlan());
  const std::string key = "\"height_mm\": 1.5";
  text.replace(text.find(key), key.size(), "\"height_mm\": 1e999");
  const std::string message = readError(text);
  EXPECT_TRUE(contains(message, "plan.json is not valid JSON: number overflow parsing '1e999'"));
  EXPECT_TRUE(contains(message, " at line 20, column 24"));
}

TEST(PlanIoRobustness, NegativeLengthsAreRefusedAsTheSchemaDoes) {
  EXPECT_TRUE(contains(readError(editedPlan([](Json& d) { d["layers"][0]["height_mm"] = -1.5; })),
                       "plan.json: /layers/0/height_mm must not be negative: -1.5"));
  EXPECT_TRUE(
      contains(readError(editedPlan([](Json& d) { d["parameters"]["layer_thickness_mm"] = -2; })),
               "plan.json: /parameters/layer_thickness_mm must not be negative: -2"));
  EXPECT_TRUE(
      contains(readError(editedPlan([](Json& d) { d["parameters"]["voxel_size_mm"] = -0.5; })),
               "/parameters/voxel_size_mm must not be negative"));
}

TEST(PlanIoRobustness, LayersInReverseOrderAreRefused) {
  // three layers renumbered top-down: welded in that order the first bead would hang in the air
  const auto layers = [](std::initializer_list<double> heights) {
    return [heights](Json& d) {
      const Json layer = d["layers"][0];
      d["layers"] = Json::array();
      int index = 0;
      for (double h : heights) {
        Json copy = layer;
        copy["index"] = index;
        copy["height_mm"] = h;
        for (Json& path : copy["paths"]) path["layer"] = index;
        d["layers"].push_back(copy);
        ++index;
      }
    };
  };
  EXPECT_TRUE(contains(readError(editedPlan(layers({4.5, 3.0, 1.5}))),
                       "plan.json: the layer heights fall from /layers/0 (4.5 mm) to the last "
                       "layer (1.5 mm) on 2 of 2 steps: the layers are in reverse order"));
  // two Jobs deposited one after the other start again at the second Job's first layer
  EXPECT_EQ(readError(editedPlan(layers({1.5, 3.0, 4.5, 1.5, 3.0}))), "");
  EXPECT_EQ(readError(editedPlan(layers({1.5, 1.5, 3.0}))), "");
}

TEST(PlanIoRobustness, HugeValuesAreEchoedShort) {
  const std::string huge(1000000, 'x');
  const std::string format = readError(editedPlan([&](Json& d) { d["format"] = huge; }));
  EXPECT_TRUE(contains(format, "not a CurvedSlicer plan (\"format\" is \"xxxx"));
  EXPECT_LT(format.size(), 300u);
  Json bigArray = Json::array();
  for (int i = 0; i < 100000; ++i) bigArray.push_back(i);
  const std::string fields = readError(editedPlan([&](Json& d) { d["point_fields"] = bigArray; }));
  EXPECT_TRUE(contains(fields, "/point_fields is [0,1,2,3"));
  EXPECT_LT(fields.size(), 300u);
  const std::string index =
      readError(editedPlan([&](Json& d) { d["layers"][0]["index"] = bigArray; }));
  EXPECT_TRUE(contains(index, "/layers/0/index must be an integer, found array [0,1,2"));
  EXPECT_LT(index.size(), 300u);
}

TEST(PlanIoRobustness, CommandLineExitsWithTwoNamingTheFile) {
  const fs::path dir = testing::freshTempDir();
  const fs::path deep = dir / "deep_plan.json";
  std::ofstream(deep) << std::string(100000, '[') << std::string(100000, ']');
  std::string text = formatPlanJson(makeTinyPlan());
  const std::string key = "\"length_mm\": 1";
  text.replace(text.find(key), key.size(), "\"length_mm\": 1e999");
  const fs::path overflow = dir / "overflow_plan.json";
  std::ofstream(overflow) << text;
  for (const fs::path& plan : {deep, overflow}) {
    const testing::CliRun run = testing::runCli(
        {"export", plan.string(), "--format", "csv", "-o", (dir / "out.csv").string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << run.err;
    EXPECT_TRUE(contains(run.err, "curvedslicer: error: " + plan.string() + " is not valid JSON"));
    EXPECT_FALSE(fs::exists(dir / "out.csv"));
  }
}

}  // namespace
}  // namespace curvedslicer
