// `curvedslicer plan` end to end: every bundled model gives a plan (coarse voxels and big spacing
// so that each run takes a few seconds), the plan validates against its schema and round-trips
// byte-identically; thin-wall mode; bad input exit codes and messages; all-or-nothing output.
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_test_support.hpp"
#include "common/sanitized_build.hpp"
#include "common/shapes.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "plan/json_schema_subset.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::CliRun;
using testing::freshTempDir;
using testing::modelPath;
using testing::runCli;
using Args = std::vector<std::string>;

constexpr double kPi = 3.14159265358979323846;

/// Voxel edge for 40 cells on the longest side (coarse: CI speed), rounded to 3 digits.
double coarseVoxel(const fs::path& model) {
  const double size = readMesh(model).bounds().size().maxCoeff();
  std::ostringstream s;
  s.precision(3);
  s << size / 40.0;
  return std::stod(s.str());
}

std::string arg(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

const testing::SchemaSubsetValidator& schemaValidator() {
  static const testing::SchemaSubsetValidator validator = [] {
    std::ifstream in(fs::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "schema" /
                     "plan.schema.json");
    return testing::SchemaSubsetValidator(json::parse(in));
  }();
  return validator;
}

/// Checks plan.json (schema, reader, byte-identical round trip), plan.csv and report.json.
Plan expectValidPlanOutput(const fs::path& out) {
  const std::string text = testing::readWholeFile(out / "plan.json");
  const auto errors = schemaValidator().validate(json::parse(text));
  EXPECT_TRUE(errors.empty()) << (errors.empty() ? "" : errors.front());
  const Plan plan = parsePlanJson(text, "plan.json");
  EXPECT_EQ(formatPlanJson(plan), text) << "plan.json does not round-trip byte-identically";
  EXPECT_GT(plan.pathCount(), 0u);
  EXPECT_EQ(testing::readWholeFile(out / "plan.csv"), formatPlanCsv(plan));
  const json report = json::parse(testing::readWholeFile(out / "report.json"));
  EXPECT_EQ(report.at("plan").at("paths").get<std::size_t>(), plan.pathCount());
  EXPECT_EQ(report.at("plan").at("layers").size(), plan.layers.size());
  for (const PlanLayer& layer : plan.layers) {
    // A layer without paths always says why.
    if (layer.paths.empty()) {
      EXPECT_FALSE(layer.warnings.empty()) << "layer " << layer.index;
    }
    if (!layer.surface.empty()) {
      EXPECT_TRUE(fs::exists(out / layer.surface)) << layer.surface;
    }
  }
  return plan;
}

class PlanCli : public ::testing::TestWithParam<std::string> {};

TEST_P(PlanCli, BundledModelGivesAValidPlan) {
  const fs::path model = modelPath(GetParam());
  // 40 cells on the longest side, layers 4 cells thick, beads 2.4 cells apart — except for the
  // branches, 70 rods of about 3 mm diameter: 2 mm voxels and 1.5 mm beads.
  const bool rods = GetParam() == "branches_70_closed_low_res.stl";
  const double L = rods ? 2.0 : coarseVoxel(model);
  const double s = rods ? 1.5 : std::stod(arg(2.4 * L));
  const fs::path out = freshTempDir() / "out";
  const CliRun run =
      runCli({"plan", model.string(), "--layer-thickness", arg(4 * L), "--voxel", arg(L),
              "--bead-spacing", arg(s), "--point-spacing", arg(rods ? 1.0 : 1.6 * L),
              "--fit-tolerance", arg(rods ? 0.05 : 0.1 * L), "-o", out.string(), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const Plan plan = expectValidPlanOutput(out);
  EXPECT_EQ(plan.parameters.beadSpacing, s);
  EXPECT_EQ(plan.parameters.initialCurve, "boundary");
  EXPECT_EQ(plan.parameters.cornerAngle, 30.0);  // the default
  EXPECT_EQ(plan.start, "plane:bottom");
  EXPECT_TRUE(fs::exists(out / "layer_0001.ply"));
}

INSTANTIATE_TEST_SUITE_P(
    BundledModels, PlanCli,
    ::testing::Values("branches_70_closed_low_res.stl", "bunny_closed_low_res.stl",
                      "distorted_v_closed_mid_res.stl", "overhang_coin_closed_low_res.stl",
                      "simple_box_closed_low_res.stl", "simple_cylinder_closed_mid_res.stl"));

TEST(PlanCliCases, EveryBundledStlIsListed) {
  std::vector<std::string> stl;
  for (const auto& e : fs::directory_iterator(modelPath(""))) {
    if (e.path().extension() == ".stl") stl.push_back(e.path().filename().string());
  }
  EXPECT_EQ(stl.size(), 6u) << "a model was added or removed: update INSTANTIATE_TEST_SUITE_P";
}

TEST(PlanCliCases, CurvedBasePairWithPlaneInitialCurve) {
  const fs::path model = modelPath("custom_base_geom_to_slice.obj");
  const fs::path base = modelPath("custom_base_surface.obj");
  const double L = coarseVoxel(model);
  const fs::path out = freshTempDir() / "out";
  const Vec3 c = readMesh(model).bounds().center();
  const CliRun run = runCli({"plan", model.string(), "--start", "mesh:" + base.string(),
                             "--cap-holes", "--layer-thickness", arg(4 * L), "--voxel", arg(L),
                             "--bead-spacing", arg(2 * L), "--initial-curve",
                             "plane:" + arg(c.x()) + "," + arg(c.y()) + "," + arg(c.z()) + ",1,0,0",
                             "-o", out.string(), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const Plan plan = expectValidPlanOutput(out);
  EXPECT_EQ(plan.parameters.initialCurve.rfind("plane:", 0), 0u);
}

TEST(PlanCliCases, ThinWallCylinder) {
  // An open cylinder side, radius 30, height 12, as the turbine base's wall.
  TriMesh wall;
  const int segments = 90, rows = 12;
  for (int j = 0; j <= rows; ++j) {
    for (int i = 0; i < segments; ++i) {
      const double a = 2.0 * kPi * i / segments;
      wall.vertices.emplace_back(30 * std::cos(a), 30 * std::sin(a), 12.0 * j / rows);
    }
  }
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < segments; ++i) {
      const int a = j * segments + i, b = j * segments + (i + 1) % segments;
      wall.triangles.emplace_back(a, b, b + segments);
      wall.triangles.emplace_back(a, b + segments, a + segments);
    }
  }
  const std::string file = testing::writeTempStl(wall, "thin_wall.stl");
  const fs::path out = freshTempDir() / "out";
  const CliRun run = runCli({"plan", file, "--thin-wall", "lowest", "--bead-spacing", "1.65",
                             "--corner-angle", "45", "-o", out.string(), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const Plan plan = expectValidPlanOutput(out);
  EXPECT_EQ(plan.layers.size(), 7u);  // 1.65 … 11.55 mm
  EXPECT_EQ(plan.start, "thin-wall:lowest");
  EXPECT_EQ(plan.parameters.cornerAngle, 45.0);
  EXPECT_FALSE(fs::exists(out / "layer_0001.ply"));
}

TEST(PlanCliCases, CoverageOptionsAreRecordedAndSummarised) {
  // The box at coarse settings: the plan records the coverage options and every layer's
  // coverage, the summary prints the totals; --no-coverage leaves the layers unmeasured. Under
  // the sanitizers the grid, layers and beads are twice as coarse (the same checks).
  const double k = testing::coarseningUnderSanitizers();
  const double s = 12.0 * k;
  const fs::path model = modelPath("simple_box_closed_low_res.stl");
  const fs::path out = freshTempDir() / "out";
  const Args base = {"plan",    model.string(), "--layer-thickness", arg(20 * k),
                     "--voxel", arg(5 * k),     "--bead-spacing",    arg(s)};
  Args args = base;
  for (const char* a : {"--min-feature-width", "4", "--bead-width-range", "0.8,1.25",
                        "--no-connect-insets", "--no-gap-fill", "--min-gap-area", "20",
                        "--corner-overdeposit", "1.5", "--corner-fill-angle", "120", "-o"}) {
    args.push_back(a);
  }
  args.push_back(out.string());
  const CliRun run = runCli(args);
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("curvedslicer: coverage: "), std::string::npos) << run.out;
  EXPECT_NE(run.out.find(" arc starts"), std::string::npos) << run.out;
  const Plan plan = expectValidPlanOutput(out);
  EXPECT_EQ(plan.parameters.minFeatureWidth, 4.0);
  EXPECT_EQ(plan.parameters.beadWidthRange, (std::array<double, 2>{0.8, 1.25}));
  EXPECT_EQ(plan.parameters.connectInsets, false);
  EXPECT_EQ(plan.parameters.fillGaps, false);
  EXPECT_EQ(plan.parameters.minGapArea, 20.0);
  EXPECT_EQ(plan.parameters.cornerOverdeposit, 1.5);
  EXPECT_EQ(plan.parameters.cornerFillAngle, 120.0);
  for (const PlanLayer& layer : plan.layers) {
    EXPECT_TRUE(layer.coverage.measured) << layer.index;
    EXPECT_EQ(layer.coverage.arcStarts, layer.paths.size());
  }
  const fs::path out2 = freshTempDir() / "out2";
  Args off = base;
  for (const std::string& a : {std::string("--no-coverage"), std::string("-o"), out2.string()}) {
    off.push_back(a);
  }
  const CliRun run2 = runCli(off);
  ASSERT_EQ(run2.exitCode, 0) << run2.err;
  EXPECT_NE(run2.out.find("coverage not measured"), std::string::npos) << run2.out;
  const Plan unmeasured = expectValidPlanOutput(out2);
  EXPECT_EQ(unmeasured.parameters.minFeatureWidth, 0.5 * s);  // the default, s/2
  EXPECT_EQ(unmeasured.parameters.beadWidthRange, (std::array<double, 2>{1.0, 1.0}));
  EXPECT_EQ(unmeasured.parameters.connectInsets, true);
  EXPECT_EQ(unmeasured.parameters.fillGaps, true);
  EXPECT_EQ(unmeasured.parameters.minGapArea, s * s);            // the default, s²
  EXPECT_EQ(unmeasured.parameters.cornerOverdeposit, 0.25 * s);  // the default, s/4
  EXPECT_EQ(unmeasured.parameters.cornerFillAngle, 85.0);        // the default: acute corners
  for (const PlanLayer& layer : unmeasured.layers) EXPECT_FALSE(layer.coverage.measured);
}

TEST(PlanCliCases, BadInputsExitWithTheirMessage) {
  const fs::path model = modelPath("simple_box_closed_low_res.stl");
  const fs::path out = freshTempDir() / "out";
  const auto expectError = [&](const Args& extra, const std::string& message) {
    Args args = {"plan", model.string(), "-o", out.string(), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliRun run = runCli(args);
    EXPECT_EQ(run.exitCode, 2) << run.err;
    EXPECT_NE(run.err.find("curvedslicer: error: " + message), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(out)) << "output written despite the error";
  };
  expectError({"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "-3"},
              "bead spacing must be a positive number of mm: -3");
  expectError({"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "0"},
              "bead spacing must be a positive number of mm: 0");
  expectError({"--voxel", "5", "--bead-spacing", "3"}, "missing --layer-thickness");
  expectError({"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "3", "--initial-curve",
               "plane:1,2,3"},
              "initial plane needs 6 comma-separated numbers");
  expectError({"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "3", "--initial-curve",
               "spiral"},
              "unknown initial curve: 'spiral'");
  expectError({"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "3", "--surface-method",
               "exact"},
              "unknown surface geodesic method: 'exact'");
  expectError({"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "3", "--narrow-strips",
               "merge"},
              "unknown narrow-strip mode: \"merge\"; pass centre_bead");
  expectError(
      {"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "3", "--corner-angle", "sharp"},
      "corner angle is not a number: 'sharp'; pass an angle in degrees such as 30");
  expectError(
      {"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "3", "--corner-angle", "0"},
      "corner angle must be in (0, 180] degrees: 0");
  // The box is 200 mm wide: a 500 mm bead does not fit any layer.
  expectError({"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "500"},
              "bead spacing is wider than every layer: 500 mm");
  // A plane beside the box misses every layer.
  expectError({"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "12", "--initial-curve",
               "plane:1000,0,0,1,0,0"},
              "no layer got a path: layer 0: the initial plane misses this layer");
  const Args box = {"--layer-thickness", "20", "--voxel", "5", "--bead-spacing", "3"};
  const auto with = [&](Args extra) {
    extra.insert(extra.begin(), box.begin(), box.end());
    return extra;
  };
  expectError(with({"--bead-width-range", "1.1,1.3"}),
              "bead width range (--bead-width-range, BeadWidthMin/BeadWidthMax) excludes the bead "
              "spacing: 1.1,1.3");
  expectError(with({"--bead-width-range", "0.5,0.9"}),
              "bead width range (--bead-width-range, BeadWidthMin/BeadWidthMax) excludes the bead "
              "spacing: 0.5,0.9 × s = 1.5–2.7 mm, s = 3 mm; choose a range with min <= 1 <= max");
  expectError(with({"--bead-width-range", "1.2,0.8"}),
              "bead width range (--bead-width-range, BeadWidthMin/BeadWidthMax) must be two "
              "fractions of the bead spacing with 0 < min <= max: 1.2,0.8");
  expectError(with({"--bead-width-range", "wide"}), "--bead-width-range is not a number: 'wide'");
  expectError(with({"--min-feature-width", "0"}),
              "minimum feature width (--min-feature-width) must be a positive number of mm: 0");
  expectError(with({"--min-feature-width", "-1"}),
              "minimum feature width (--min-feature-width) must be a positive number of mm: -1");
  expectError(with({"--min-gap-area", "0"}),
              "minimum gap area (--min-gap-area) must be a positive number of mm²: 0");
  expectError(
      with({"--corner-overdeposit", "-0.5"}),
      "corner overdeposit (--corner-overdeposit) must be a non-negative number of mm: -0.5");
  expectError({"--thin-wall", "lowest", "--bead-spacing", "2"},
              "thin-wall surface has no boundary edge");
  expectError({"--thin-wall", "upwards", "--bead-spacing", "2"}, "unknown thin-wall edge");
}

}  // namespace
}  // namespace curvedslicer
