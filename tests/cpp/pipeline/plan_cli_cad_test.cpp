// `curvedslicer layers|plan` with a CAD model (STEP/BREP, tessellated through OpenCASCADE):
// a plan from a BREP box, --start faces: with FreeCAD's 1-based face numbers, the
// --tessellation-tolerance option and its bad values; without OpenCASCADE, exit 2 and a clear
// message. Test files (tests/cpp/pipeline/data, written by FreeCAD's Part module):
//   cad_box.brep    box 30 x 20 x 12 mm at the origin; Face5 is z = 0, Face6 is z = 12
//   cad_boss.step   the box with a cylindrical boss r = 6, h = 8 on its top (8 faces)
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/cli_test_support.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/plan/plan_io.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;

const fs::path kData = fs::path(CURVEDSLICER_SOURCE_DIR) / "tests/cpp/pipeline/data";

#ifdef CURVEDSLICER_CLI_HAS_OCC

nlohmann::json readJson(const fs::path& path) {
  return nlohmann::json::parse(testing::readWholeFile(path));
}

TEST(PlanCliCad, PlansABrepBox) {
  const fs::path dir = testing::freshTempDir();
  const testing::CliRun run =
      testing::runCli({"plan", (kData / "cad_box.brep").string(), "--layer-thickness", "3",
                       "--voxel", "1", "--bead-spacing", "3", "-o", (dir / "out").string(), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const Plan plan = readPlanJson(dir / "out/plan.json");
  EXPECT_EQ(plan.layers.size(), 3u);  // 3, 6, 9 mm above the plate (12 is the top face)
  EXPECT_GT(plan.pathCount(), 0u);
  const nlohmann::json report = readJson(dir / "out/report.json");
  EXPECT_EQ(report["mesh"]["file_triangles"], 12);  // six planar faces, two triangles each
  EXPECT_EQ(report["mesh"]["closed"], true);
}

/// Lowest and highest z of the first layer of `layers` run from `start` on the box.
std::pair<double, double> firstLayerZRange(const std::string& start) {
  const fs::path dir = testing::freshTempDir(start.substr(start.find(':') + 1));
  const testing::CliRun run = testing::runCli(
      {"layers", (kData / "cad_box.brep").string(), "--start", start, "--layer-thickness", "3",
       "--voxel", "1", "--format", "obj", "-o", (dir / "out").string(), "-q"});
  EXPECT_EQ(run.exitCode, 0) << run.err;
  const TriMesh layer = readMesh(dir / "out/layer_0001.obj");
  double lo = 1e9, hi = -1e9;
  for (const Vec3& v : layer.vertices) {
    lo = std::min(lo, v.z());
    hi = std::max(hi, v.z());
  }
  return {lo, hi};
}

TEST(PlanCliCad, StartFacesAreFreeCadFaceNumbers) {
  // Face5 is the bottom (z = 0): the first layer is the plane z = 3. Face6 is the top (z = 12):
  // the first layer is z = 9. Tolerance: one voxel.
  const auto [bottomLo, bottomHi] = firstLayerZRange("faces:5");
  EXPECT_NEAR(bottomLo, 3.0, 1.0);
  EXPECT_NEAR(bottomHi, 3.0, 1.0);
  const auto [topLo, topHi] = firstLayerZRange("faces:6");
  EXPECT_NEAR(topLo, 9.0, 1.0);
  EXPECT_NEAR(topHi, 9.0, 1.0);
  // There is no Face0 (numbers are 1-based) nor Face7.
  const fs::path dir = testing::freshTempDir("bad");
  for (const std::string ids : {"faces:0", "faces:7"}) {
    const testing::CliRun run = testing::runCli(
        {"layers", (kData / "cad_box.brep").string(), "--start", ids, "--layer-thickness", "3",
         "--voxel", "1", "-o", (dir / "out").string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << ids << ": " << run.err;
    EXPECT_NE(run.err.find("valid ids are 1..6"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
}

TEST(PlanCliCad, TessellationToleranceSetsTheChordError) {
  const auto triangles = [](const std::string& tolerance) {
    const fs::path dir = testing::freshTempDir(tolerance);
    std::vector<std::string> args = {"layers",
                                     (kData / "cad_boss.step").string(),
                                     "--layer-thickness",
                                     "4",
                                     "--voxel",
                                     "2",
                                     "-o",
                                     (dir / "out").string(),
                                     "-q"};
    if (!tolerance.empty()) args.insert(args.end(), {"--tessellation-tolerance", tolerance});
    const testing::CliRun run = testing::runCli(args);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json report = readJson(dir / "out/report.json");
    const double recorded = report["inputs"]["tessellation_tolerance_mm"].get<double>();
    EXPECT_EQ(recorded, tolerance.empty() ? 0.5 : std::stod(tolerance));
    return report["mesh"]["file_triangles"].get<int>();
  };
  const int coarse = triangles("1");
  const int fine = triangles("0.01");
  const int automatic = triangles("");  // voxel / 4 = 0.5 mm
  EXPECT_GT(fine, 2 * coarse) << "a finer chord error gives more triangles on the boss";
  EXPECT_GE(automatic, coarse);
  EXPECT_LE(automatic, fine);
}

#else

TEST(PlanCliCad, CadInputNeedsTheOpenCascadeBuild) {
  const fs::path dir = testing::freshTempDir();
  const testing::CliRun run =
      testing::runCli({"plan", (kData / "cad_box.brep").string(), "--layer-thickness", "3",
                       "--voxel", "1", "--bead-spacing", "3", "-o", (dir / "out").string(), "-q"});
  EXPECT_EQ(run.exitCode, 2) << run.err;
  EXPECT_NE(run.err.find("CAD input needs the OpenCASCADE build"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

#endif

TEST(PlanCliCad, BadTessellationToleranceExitsWithItsMessage) {
  const fs::path dir = testing::freshTempDir();
  for (const std::string bad : {"0", "-0.5", "nan", "fine"}) {
    const testing::CliRun run =
        testing::runCli({"plan", (kData / "cad_box.brep").string(), "--layer-thickness", "3",
                         "--voxel", "1", "--bead-spacing", "3", "--tessellation-tolerance", bad,
                         "-o", (dir / "out").string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << bad << ": " << run.err;
    EXPECT_NE(run.err.find("curvedslicer: error: tessellation tolerance"), std::string::npos)
        << run.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
}

}  // namespace
}  // namespace curvedslicer
