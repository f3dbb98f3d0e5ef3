// `curvedslicer plan` translates its arguments into PlanJobOptions and nothing more: defaults and
// the --help text come from PlannerOptions{}; range checks (a zero plane normal, an initial curve
// with a thin wall) are the core's, with the core's messages.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_test_support.hpp"
#include "common/sanitized_build.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/plan/plan_io.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;

std::string g(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", value);
  return buffer;
}

/// Bead spacing of the coarse box (twice as coarse under the sanitizers, as its grid and layers).
constexpr double kBoxBeadSpacing = 12.0 * testing::coarseningUnderSanitizers();

std::vector<std::string> coarseBox(const fs::path& out) {
  const double scale = testing::coarseningUnderSanitizers();
  return {"plan",
          testing::modelPath("simple_box_closed_low_res.stl").string(),
          "--layer-thickness",
          g(20.0 * scale),
          "--voxel",
          g(5.0 * scale),
          "--bead-spacing",
          g(kBoxBeadSpacing),
          "-o",
          out.string(),
          "-q"};
}

TEST(PlanCliOptions, HelpShowsThePlannerDefaults) {
  const fs::path dir = testing::freshTempDir();
  const testing::CliRun help = testing::runCli({"plan", "--help"});
  ASSERT_EQ(help.exitCode, 0) << help.err;
  const PlannerOptions defaults;
  for (const std::string& part : std::vector<std::string>{
           "(default " + g(defaults.pointSpacing) + ")",
           "(default " + g(defaults.fitTolerance) + ")",
           "(default " + g(defaults.cornerAngle) + ")",
           "default " + std::string(toString(defaults.geodesic.method)),
           "Default " + narrowStripModeName(defaults.narrowStrips), std::string("Default boundary"),
           std::string("--tessellation-tolerance")}) {
    EXPECT_NE(help.out.find(part), std::string::npos) << part << "\n" << help.out;
  }
}

TEST(PlanCliOptions, OptionsNotGivenAreThePlannerDefaults) {
  const fs::path dir = testing::freshTempDir();
  const testing::CliRun run = testing::runCli(coarseBox(dir / "out"));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const Plan plan = readPlanJson(dir / "out/plan.json");
  const PlannerOptions defaults;
  EXPECT_EQ(plan.parameters.beadSpacing, kBoxBeadSpacing);
  EXPECT_EQ(plan.parameters.pointSpacing, defaults.pointSpacing);
  EXPECT_EQ(plan.parameters.fitTolerance, defaults.fitTolerance);
  EXPECT_EQ(plan.parameters.cornerAngle, defaults.cornerAngle);
  EXPECT_EQ(plan.parameters.surfaceMethod, toString(defaults.geodesic.method));
  EXPECT_EQ(plan.parameters.narrowStrips, narrowStripModeName(defaults.narrowStrips));
  EXPECT_EQ(plan.parameters.initialCurve, "boundary");
  EXPECT_EQ(plan.start, "plane:bottom");
}

TEST(PlanCliOptions, RangeChecksAreTheCores) {
  const fs::path dir = testing::freshTempDir();
  const auto expectError = [&](std::vector<std::string> args, const std::string& message) {
    const testing::CliRun run = testing::runCli(args);
    EXPECT_EQ(run.exitCode, 2) << run.err;
    EXPECT_NE(run.err.find("curvedslicer: error: " + message), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
  };
  std::vector<std::string> args = coarseBox(dir / "out");
  args.insert(args.end(), {"--initial-curve", "plane:0,0,0,0,0,0"});
  expectError(args, "initial plane needs a finite point and a non-zero normal");
  expectError({"plan", testing::modelPath("simple_box_closed_low_res.stl").string(), "--thin-wall",
               "lowest", "--bead-spacing", "2", "--initial-curve", "plane:0,0,0,1,0,0", "-o",
               (dir / "out").string(), "-q"},
              "an initial curve does not apply to a thin wall");
  args = coarseBox(dir / "out");
  args.insert(args.end(), {"--point-spacing", "0"});
  expectError(args, "point spacing must be a positive number of mm: 0");
}

}  // namespace
}  // namespace curvedslicer
