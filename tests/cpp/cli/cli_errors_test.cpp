// The `curvedslicer` binary on bad input: each case exits with its specific code and message on
// stderr ("curvedslicer: error: …") and leaves nothing in the output folder.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "cli_test_support.hpp"
#include "common/shapes.hpp"
#include "common/test_paths.hpp"
#include "common/text_assertions.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using testing::freshTempDir;
using testing::listFolder;
using testing::runCli;
using testing::trianglesOf;
using testing::writeBinaryStl;
using Args = std::vector<std::string>;

constexpr int kInvalidInput = 2;
constexpr int kIoError = 3;
constexpr int kResourceLimit = 4;

using testing::contains;

/// A folder with a 10 mm cube as binary STL (box.stl) and an empty output folder (out/).
struct Workspace {
  fs::path dir = freshTempDir();
  fs::path out = dir / "out";
  fs::path box = dir / "box.stl";
  Workspace() {
    fs::create_directories(out);
    writeBinaryStl(box, trianglesOf(testing::makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10))));
  }
  /// `layers MODEL --layer-thickness 2 --voxel 0.5 -o out` with `extra` appended.
  Args layers(const fs::path& model, const Args& extra = {}) const {
    Args args{"layers", model.string(), "--layer-thickness", "2", "--voxel",
              "0.5",    "-o",           out.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }
};

/// Runs the CLI and checks exit code, the error message and that `out` stayed empty.
void expectFailure(const Workspace& ws, const Args& args, int exitCode,
                   const std::vector<std::string>& messageParts) {
  const CliRun run = runCli(args);
  EXPECT_EQ(run.exitCode, exitCode) << run.err;
  EXPECT_TRUE(contains(run.err, "curvedslicer: error: "));
  for (const std::string& part : messageParts) EXPECT_TRUE(contains(run.err, part));
  EXPECT_EQ(run.out, "");
  EXPECT_TRUE(listFolder(ws.out).empty()) << "output folder not empty: " << listFolder(ws.out)[0];
}

TEST(CliErrors, MissingModelFile) {
  Workspace ws;
  expectFailure(ws, ws.layers(ws.dir / "missing.stl"), kInvalidInput,
                {"mesh file not found", "missing.stl"});
}

TEST(CliErrors, EmptyModelFile) {
  Workspace ws;
  std::ofstream(ws.dir / "empty.stl").close();
  expectFailure(ws, ws.layers(ws.dir / "empty.stl"), kInvalidInput,
                {"mesh file is empty", "empty.stl"});
}

TEST(CliErrors, TruncatedBinaryStl) {
  Workspace ws;
  const auto triangles = trianglesOf(testing::makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10)));
  writeBinaryStl(ws.dir / "cut.stl", triangles, -1, 84 + 50 * 5 + 17);  // mid-record
  expectFailure(
      ws, ws.layers(ws.dir / "cut.stl"), kInvalidInput,
      {"binary STL size disagrees with its triangle count", "declares 12 triangles", "truncated"});
  writeBinaryStl(ws.dir / "stub.stl", triangles, -1, 50);  // not even a header
  expectFailure(ws, ws.layers(ws.dir / "stub.stl"), kInvalidInput,
                {"binary STL is truncated", "84-byte header"});
}

TEST(CliErrors, BinaryStlCountDisagreesWithSize) {
  Workspace ws;
  writeBinaryStl(ws.dir / "count.stl",
                 trianglesOf(testing::makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10))), 1000);
  expectFailure(ws, ws.layers(ws.dir / "count.stl"), kInvalidInput,
                {"binary STL size disagrees with its triangle count", "declares 1000 triangles"});
}

TEST(CliErrors, NonFiniteCoordinates) {
  Workspace ws;
  for (float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    auto triangles = trianglesOf(testing::makeBox(Vec3(0, 0, 0), Vec3(10, 10, 10)));
    triangles[3][1].y() = bad;
    writeBinaryStl(ws.dir / "nan.stl", triangles);
    expectFailure(ws, ws.layers(ws.dir / "nan.stl"), kInvalidInput, {"non-finite coordinate"});
  }
}

TEST(CliErrors, FlatModelEnclosesNoVolume) {
  Workspace ws;
  writeBinaryStl(ws.dir / "flat.stl",
                 trianglesOf(testing::makeBox(Vec3(0, 0, 0), Vec3(10, 10, 0))));
  expectFailure(ws, ws.layers(ws.dir / "flat.stl"), kInvalidInput,
                {"model encloses no volume", "closed solid"});
}

/// One eighth of a sphere as an open sheet (triangles with their centroid in x, y, z > 0): rays
/// along every axis through the region it bounds cross it once, so no ray direction can decide.
TriMesh makeSphereOctantSheet() {
  const TriMesh sphere = testing::makeSphere(Vec3(0, 0, 0), 10.0, 3);
  TriMesh sheet;
  sheet.vertices = sphere.vertices;
  for (std::size_t t = 0; t < sphere.triangleCount(); ++t) {
    const Vec3 c = sphere.corner(t, 0) + sphere.corner(t, 1) + sphere.corner(t, 2);
    if ((c.array() > 0.0).all()) sheet.triangles.push_back(sphere.triangles[t]);
  }
  return sheet;
}

TEST(CliErrors, OpenMeshBeyondRepair) {
  Workspace ws;
  writeBinaryStl(ws.dir / "dome.stl", trianglesOf(makeSphereOctantSheet()));
  expectFailure(ws, ws.layers(ws.dir / "dome.stl"), kInvalidInput,
                {"model is open beyond repair", "open", "--cap-holes"});
  // The bundled curved-base part is open at its bottom and top as well.
  expectFailure(ws, ws.layers(testing::modelPath("custom_base_geom_to_slice.obj")), kInvalidInput,
                {"model is open beyond repair"});
}

TEST(CliErrors, StartPlaneFarBelowTheSolid) {
  Workspace ws;
  expectFailure(ws, ws.layers(ws.box, {"--start", "plane:z=-1000"}), kInvalidInput,
                {"the start surface does not touch the solid"});
}

TEST(CliErrors, StartMeshFarAway) {
  Workspace ws;
  // A 10 mm square sheet 500 mm above the cube.
  const std::vector<std::array<Eigen::Vector3f, 3>> sheet{
      {Eigen::Vector3f(0, 0, 500), Eigen::Vector3f(10, 0, 500), Eigen::Vector3f(10, 10, 500)},
      {Eigen::Vector3f(0, 0, 500), Eigen::Vector3f(10, 10, 500), Eigen::Vector3f(0, 10, 500)}};
  writeBinaryStl(ws.dir / "sheet.stl", sheet);
  expectFailure(ws, ws.layers(ws.box, {"--start", "mesh:" + (ws.dir / "sheet.stl").string()}),
                kInvalidInput, {"the start surface does not touch the solid"});
}

TEST(CliErrors, StartMeshFileMissing) {
  Workspace ws;
  expectFailure(ws, ws.layers(ws.box, {"--start", "mesh:" + (ws.dir / "nobase.obj").string()}),
                kInvalidInput, {"start surface mesh: mesh file not found", "nobase.obj"});
}

TEST(CliErrors, NonPositiveOrNonFiniteLayerThickness) {
  Workspace ws;
  for (const char* h : {"0", "-1.5", "nan", "inf"}) {
    Args args{"layers", ws.box.string(), "--layer-thickness=" + std::string(h), "--voxel", "0.5",
              "-o",     ws.out.string()};
    expectFailure(ws, args, kInvalidInput,
                  {"layer thickness must be a positive number of millimetres: "});
  }
  Args args{"layers", ws.box.string(), "--layer-thickness", "thick", "--voxel", "0.5",
            "-o",     ws.out.string()};
  expectFailure(ws, args, kInvalidInput, {"layer thickness is not a number: 'thick'"});
}

TEST(CliErrors, NonPositiveOrNonFiniteVoxelSize) {
  Workspace ws;
  for (const char* L : {"0", "-0.5", "nan"}) {
    Args args{"layers", ws.box.string(), "--layer-thickness", "2", "--voxel=" + std::string(L),
              "-o",     ws.out.string()};
    expectFailure(ws, args, kInvalidInput, {"voxel size must be a positive number of millimetres"});
  }
}

TEST(CliErrors, NegativeNumberAsSeparateArgument) {
  Workspace ws;
  Args args{"layers", ws.box.string(), "--layer-thickness", "-2", "--voxel", "0.5",
            "-o",     ws.out.string()};
  const CliRun run = runCli(args);
  EXPECT_EQ(run.exitCode, kInvalidInput) << run.err;
  EXPECT_TRUE(contains(run.err, "curvedslicer: error: "));
  EXPECT_TRUE(listFolder(ws.out).empty());
}

TEST(CliErrors, GridBeyondTheMemoryBudget) {
  Workspace ws;
  Args args{"layers",  ws.box.string(), "--layer-thickness", "2",
            "--voxel", "0.01",          "--memory-budget",   "100",
            "-o",      ws.out.string()};
  // 10 mm / 0.01 mm = 1000 cells per axis plus padding: about 1e9 cells.
  expectFailure(ws, args, kResourceLimit,
                {"cells at voxel size 0.01 mm", "memory budget", "use a voxel size of at least"});
  expectFailure(ws, ws.layers(ws.box, {"--memory-budget=-5"}), kInvalidInput,
                {"memory budget must be 0 (automatic) or at least 1 MB: '-5'"});
  // a budget no grid fits would only give absurd advice (a point spacing of 4.7e+302 mm)
  expectFailure(ws, ws.layers(ws.box, {"--memory-budget=1e-300"}), kInvalidInput,
                {"memory budget must be 0 (automatic) or at least 1 MB: '1e-300'"});
}

/// The voxel size in "use a voxel size of at least X mm" (0 when the message has none).
double suggestedVoxelSize(const std::string& message) {
  const std::string marker = "use a voxel size of at least ";
  const auto at = message.find(marker);
  return at == std::string::npos ? 0.0 : std::stod(message.substr(at + marker.size()));
}

// The scale benchmark's part (tests/bench/large_part_bench.cpp: a 600 x 400 x 300 mm open-top box
// with 8 mm walls) at a voxel size far beyond a 24 GiB budget: `layers` and `plan` refuse it
// before allocating anything (the process stays small although the grid has ~4.6e9 cells), and
// the voxel size they name passes the same budget check while the next smaller one does not —
// checked with estimateGrid, which allocates nothing, so the 1.6e9-cell grid is never built.
TEST(CliErrors, LargePartBeyondTheMemoryBudget) {
  Workspace ws;
  const fs::path part = ws.dir / "large_box.stl";
  writeMesh(part, testing::makeOpenBox(Vec3(600, 400, 300), 8.0));
  const std::string budgetMb = "24576";  // 24 GiB
  for (const std::string command : {"layers", "plan"}) {
    Args args{command,   part.string(),  "--layer-thickness", "1.5",
              "--voxel", "0.25",         "--memory-budget",   budgetMb,
              "-o",      ws.out.string()};
    if (command == "plan") args.insert(args.end(), {"--bead-spacing", "3.7"});
    expectFailure(ws, args, kResourceLimit,
                  {"cells at voxel size 0.25 mm", "over the memory budget of 25.8 GB",
                   "use a voxel size of at least 0.36 mm"});
  }
  rusage children{};
  ASSERT_EQ(::getrusage(RUSAGE_CHILDREN, &children), 0);
  EXPECT_LT(children.ru_maxrss, 256 * 1024) << "KiB: the refused grid was allocated";

  // The suggestion fits the budget as the command line checks it (the cleaned model, PCA grid);
  // 0.35 mm, the next smaller two-digit size, does not.
  const CliRun run = runCli({"layers", part.string(), "--layer-thickness", "1.5", "--voxel", "0.25",
                             "--memory-budget", budgetMb, "-o", ws.out.string()});
  const double suggested = suggestedVoxelSize(run.err);
  ASSERT_GT(suggested, 0.25) << run.err;
  const TriMesh model = cleanMesh(readMesh(part)).mesh;
  VoxelizeOptions options;
  options.memoryBudgetBytes = 24.0 * 1024 * 1024 * 1024;
  options.voxelSize = suggested;
  const GridEstimate fitting = estimateGrid(model, options);
  EXPECT_TRUE(fitting.fits) << fitting.message;
  EXPECT_LE(fitting.cells * options.bytesPerCell, options.memoryBudgetBytes);
  EXPECT_GT(fitting.cells, 1.5e9);  // the budget is used, not a far coarser grid
  options.voxelSize = suggested - 0.01;
  EXPECT_FALSE(estimateGrid(model, options).fits);
}

TEST(CliErrors, NonPositiveOrNonFiniteLayerTolerance) {
  Workspace ws;
  for (const char* bad : {"0", "-0.1", "nan", "inf"}) {
    expectFailure(
        ws, ws.layers(ws.box, {std::string("--layer-tolerance=") + bad}), kInvalidInput,
        {"--layer-tolerance must be a positive number of mm: '" + std::string(bad) + "'"});
  }
  expectFailure(ws, ws.layers(ws.box, {"--layer-tolerance", "0.02", "--full-resolution-layers"}),
                kInvalidInput,
                {"--layer-tolerance does not apply with --full-resolution-layers: '0.02'"});
  expectFailure(ws, ws.layers(ws.box, {"--simplify-layers", "--full-resolution-layers"}),
                kInvalidInput,
                {"--simplify-layers does not apply with --full-resolution-layers: both given"});
}

TEST(CliErrors, UnknownMethodGridAndFormat) {
  Workspace ws;
  expectFailure(ws, ws.layers(ws.box, {"--method", "fast"}), kInvalidInput,
                {"unknown geodesic method: 'fast'", "anyangle", "paper"});
  expectFailure(ws, ws.layers(ws.box, {"--grid", "obb"}), kInvalidInput,
                {"unknown grid alignment: 'obb'"});
  expectFailure(ws, ws.layers(ws.box, {"--format", "stl"}), kInvalidInput,
                {"unknown layer file format: 'stl'"});
}

TEST(CliErrors, BadStartSpecSyntax) {
  Workspace ws;
  expectFailure(ws, ws.layers(ws.box, {"--start", "faces:1-"}), kInvalidInput,
                {"bad face id list '1-'", "0-9,15"});
  expectFailure(ws, ws.layers(ws.box, {"--start", "faces:a,b"}), kInvalidInput,
                {"bad face id list"});
  expectFailure(ws, ws.layers(ws.box, {"--start", "cone:3"}), kInvalidInput,
                {"unknown start surface kind: 'cone:3'", "plane:bottom"});
}

TEST(CliErrors, FaceIdsTheModelDoesNotHave) {
  Workspace ws;
  expectFailure(ws, ws.layers(ws.box, {"--start", "faces:0,500-501"}), kInvalidInput,
                {"start face ids not found in the model: 500", "501"});
}

TEST(CliErrors, UsageErrorsExitWithCodeTwo) {
  Workspace ws;
  // Missing required options, an unknown option, no subcommand.
  expectFailure(ws, {"layers", ws.box.string(), "--voxel", "0.5", "-o", ws.out.string()},
                kInvalidInput, {"--layer-thickness"});
  expectFailure(ws, ws.layers(ws.box, {"--frobnicate"}), kInvalidInput, {"--frobnicate"});
  expectFailure(ws, {}, kInvalidInput, {"subcommand"});
  expectFailure(ws, {"layers", "--layer-thickness", "2", "--voxel", "0.5", "-o", ws.out.string()},
                kInvalidInput, {"MODEL"});
}

TEST(CliErrors, OutputPathIsAFile) {
  Workspace ws;
  const fs::path file = ws.dir / "file.txt";
  std::ofstream(file) << "x";
  Args args{"layers", ws.box.string(), "--layer-thickness", "2", "--voxel", "0.5",
            "-o",     file.string()};
  const CliRun run = runCli(args);
  EXPECT_EQ(run.exitCode, kIoError) << run.err;
  EXPECT_TRUE(contains(run.err, "output path exists and is not a folder"));
  EXPECT_EQ(testing::readWholeFile(file), "x");
}

TEST(CliErrors, FailureDoesNotCreateAMissingOutputFolder) {
  Workspace ws;
  const fs::path out = ws.dir / "never" / "created";
  Args args{"layers", ws.box.string(), "--layer-thickness", "2",  "--voxel",
            "0.5",    "--start",       "plane:z=-1000",     "-o", out.string()};
  const CliRun run = runCli(args);
  EXPECT_EQ(run.exitCode, kInvalidInput) << run.err;
  EXPECT_FALSE(fs::exists(ws.dir / "never"));
}

TEST(CliErrors, VersionAndHelp) {
  const CliRun version = runCli({"--version"});
  EXPECT_EQ(version.exitCode, 0);
  EXPECT_EQ(version.out, std::string("curvedslicer ") + CURVEDSLICER_VERSION + "\n");

  const CliRun help = runCli({"layers", "--help"});
  EXPECT_EQ(help.exitCode, 0) << help.err;
  for (const char* part : {"MODEL",
                           "--start",
                           "plane:bottom",
                           "plane:z=MM",
                           "faces:IDS",
                           "0-based",
                           "0-9,15",
                           "mesh:FILE",
                           "--layer-thickness",
                           "--voxel",
                           "mm",
                           "--method",
                           "anyangle (default",
                           "--grid",
                           "pca (default",
                           "--format",
                           "ply (default",
                           "--memory-budget",
                           "80 %",
                           "--quiet",
                           "--output",
                           "layer_0001.ply",
                           "voxel_sets.ply",
                           "report.json"}) {
    EXPECT_TRUE(contains(help.out, part));
  }
  const CliRun top = runCli({"--help"});
  EXPECT_EQ(top.exitCode, 0);
  EXPECT_TRUE(contains(top.out, "layers"));
}

}  // namespace
}  // namespace curvedslicer
