// The command line on hostile input: outputs onto devices and FIFOs exit with code 3
// and leave the node as it was; a grid beyond the cell limit exits with code 4 before anything is
// allocated; two overlapping closed cubes give their union, reported in report.json.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_test_support.hpp"
#include "common/shapes.hpp"
#include "common/test_paths.hpp"
#include "common/text_assertions.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using testing::runCli;
using Args = std::vector<std::string>;

using testing::contains;

/// `a` and `b` as one triangle soup.
TriMesh combined(const TriMesh& a, const TriMesh& b) {
  TriMesh out = a;
  const int offset = static_cast<int>(a.vertices.size());
  out.vertices.insert(out.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const Vec3i& t : b.triangles) out.triangles.push_back(t + Vec3i::Constant(offset));
  out.faceIds.clear();
  return out;
}

/// A plan of a 20 x 16 x 6 mm box (plan.json in `dir`/plan).
fs::path makeBoxPlan(const fs::path& dir) {
  const fs::path box = dir / "box.stl";
  testing::writeBinaryStl(box,
                          testing::trianglesOf(testing::makeBox(Vec3(0, 0, 0), Vec3(20, 16, 6))));
  const CliRun run = runCli({"plan", box.string(), "--layer-thickness", "2", "--voxel", "1",
                             "--bead-spacing", "4", "-o", (dir / "plan").string(), "-q"});
  EXPECT_EQ(run.exitCode, 0) << run.err;
  return dir / "plan" / "plan.json";
}

TEST(CliRobustness, ExportOntoAFifoOrACharacterDeviceExitsThreeAndKeepsTheNode) {
  const fs::path dir = testing::freshTempDir();
  const fs::path plan = makeBoxPlan(dir);
  const fs::path fifo = dir / "pipe.jbi";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  std::vector<fs::path> nodes{fifo};
  if (::geteuid() == 0) {  // mknod needs root; the numbers of /dev/null, harmless if written
    const fs::path device = dir / "device.jbi";
    ASSERT_EQ(::mknod(device.c_str(), S_IFCHR | 0600, ::makedev(1, 3)), 0);
    nodes.push_back(device);
  }
  for (const fs::path& node : nodes) {
    SCOPED_TRACE(node.string());
    const CliRun run = runCli({"export", plan.string(), "--format", "jbi", "-o", node.string()});
    EXPECT_EQ(run.exitCode, 3) << run.err;
    EXPECT_TRUE(contains(run.err, "curvedslicer: error: output path is a "));
    EXPECT_TRUE(contains(run.err, "not a regular file: '" + node.string() + "'"));
    struct stat st {};
    ASSERT_EQ(::lstat(node.c_str(), &st), 0);
    EXPECT_TRUE(node == fifo ? S_ISFIFO(st.st_mode) : S_ISCHR(st.st_mode));
    if (node != fifo) {
      EXPECT_EQ(st.st_rdev, ::makedev(1, 3));
    }
  }
  EXPECT_EQ(testing::listFolder(dir).size(), 3u + (nodes.size() - 1));  // no temporary left
}

TEST(CliRobustness, GridBeyondTheCellLimitExitsFourWithinSeconds) {
  const fs::path dir = testing::freshTempDir();
  const auto start = std::chrono::steady_clock::now();
  const CliRun run = runCli({"layers", testing::modelPath("custom_base_geom_to_slice.obj").string(),
                             "--layer-thickness", "1.5", "--voxel", "0.01", "--memory-budget",
                             "1e30", "-o", (dir / "out").string(), "-q"});
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(run.exitCode, 4) << run.err;
  EXPECT_TRUE(contains(run.err, "2,147,483,647 cells in all"));
  EXPECT_TRUE(contains(run.err, "use a voxel size of at least"));
  EXPECT_LT(seconds, 5.0);
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(CliRobustness, OverlappingCubesGiveTheUnionAndAReportEntry) {
  const fs::path dir = testing::freshTempDir();
  const fs::path model = dir / "two_boxes.stl";
  // 20 x 30 x 20 mm each, overlapping in 15 x 30 x 20: union 15,000 voxels of 1 mm.
  testing::writeBinaryStl(
      model, testing::trianglesOf(combined(testing::makeBox(Vec3(0, 0, 0), Vec3(20, 30, 20)),
                                           testing::makeBox(Vec3(5, 0, 0), Vec3(25, 30, 20)))));
  const CliRun run = runCli({"layers", model.string(), "--layer-thickness", "2", "--voxel", "1",
                             "--grid", "model", "-o", (dir / "out").string(), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  std::ifstream in(dir / "out" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["grid"]["inside_voxels"], 15000);
  EXPECT_EQ(report["grid"]["overlap_voxels"], 9000);
  EXPECT_EQ(report["grid"]["fill_rule"], "nonzero");
  // Ambiguous geometry is said, with where: the overlap's voxel centres span x 5.5..19.5.
  const std::string warning =
      "curvedslicer: warning: 9000 voxels lie inside two or more shells of the model (overlapping "
      "or nested bodies) around x 5.5..19.5, y 0.5..29.5, z 0.5..19.5 mm; they were filled as the "
      "union of the shells";
  EXPECT_TRUE(contains(run.err, warning));
  ASSERT_EQ(report["warnings"].size(), 1u);
  EXPECT_TRUE(contains(report["warnings"][0].get<std::string>(), "around x 5.5..19.5"));
  EXPECT_EQ(report["grid"]["overlap_bounds"]["min_mm"], nlohmann::json::array({5.5, 0.5, 0.5}));
}

/// The box (0,0,0)-(20,16,10) without the triangles of its top face (z = 10).
TriMesh boxWithoutTop() {
  TriMesh box = testing::makeBox(Vec3(0, 0, 0), Vec3(20, 16, 10));
  std::erase_if(box.triangles, [&box](const Vec3i& t) {
    return box.vertices[t[0]].z() == 10 && box.vertices[t[1]].z() == 10 &&
           box.vertices[t[2]].z() == 10;
  });
  return box;
}

TEST(CliRobustness, BoxWithOneFaceMissingIsSlicedWithAWarningThatSaysWhere) {
  const fs::path dir = testing::freshTempDir();
  const fs::path model = dir / "open_box.stl";
  testing::writeBinaryStl(model, testing::trianglesOf(boxWithoutTop()));
  const CliRun run = runCli({"layers", model.string(), "--layer-thickness", "2", "--voxel", "1",
                             "--grid", "model", "-o", (dir / "out").string(), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_TRUE(contains(run.err,
                       "curvedslicer: warning: the model is open: 4 boundary edges and 0 "
                       "non-manifold edges around x 0..20, y 0..16, z 10..10 mm"));
  EXPECT_TRUE(contains(run.err, "pass --cap-holes (CapHoles) or close the model"));
  std::ifstream in(dir / "out" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  ASSERT_EQ(report["warnings"].size(), 1u);
  EXPECT_TRUE(contains(report["warnings"][0].get<std::string>(), "the model is open"));
  // With the hole capped the model is closed: no warning.
  const CliRun capped =
      runCli({"layers", model.string(), "--layer-thickness", "2", "--voxel", "1", "--grid", "model",
              "--cap-holes", "-o", (dir / "capped").string(), "-q"});
  ASSERT_EQ(capped.exitCode, 0) << capped.err;
  EXPECT_FALSE(contains(capped.err, "warning"));
}

TEST(CliRobustness, FlippedTriangleIsFilledByParityWithAWarningThatSaysWhere) {
  const fs::path dir = testing::freshTempDir();
  TriMesh box = testing::makeBox(Vec3(0, 0, 0), Vec3(20, 16, 10));
  std::swap(box.triangles[4][1], box.triangles[4][2]);
  Aabb flipped;
  for (int k = 0; k < 3; ++k) flipped.extend(box.vertices[box.triangles[4][k]]);
  const fs::path model = dir / "flipped.stl";
  testing::writeBinaryStl(model, testing::trianglesOf(box));
  const CliRun run = runCli({"layers", model.string(), "--layer-thickness", "2", "--voxel", "1",
                             "--grid", "model", "-o", (dir / "out").string(), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const auto range = [&flipped](int a) {
    std::ostringstream s;
    s << flipped.min[a] << ".." << flipped.max[a];
    return s.str();
  };
  EXPECT_TRUE(contains(run.err,
                       "curvedslicer: warning: the model's surface is inconsistently "
                       "oriented: 3 edges where neighbouring triangles disagree, around x " +
                           range(0) + ", y " + range(1) + ", z " + range(2) + " mm"));
  std::ifstream in(dir / "out" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["grid"]["fill_rule"], "parity");
  EXPECT_EQ(report["grid"]["inside_voxels"], 20 * 16 * 10);
  EXPECT_EQ(report["warnings"].size(), 1u);
}

TEST(CliRobustness, InsideOutModelIsTurnedOutwardAndPlansAsTheBoxDoes) {
  // every triangle of a closed box reversed (a negative volume): the plan is the box's, with a
  // warning that says what was turned
  const fs::path dir = testing::freshTempDir();
  const TriMesh box = testing::makeBox(Vec3(0, 0, 0), Vec3(20, 16, 10));
  TriMesh inverted = box;
  for (Vec3i& t : inverted.triangles) std::swap(t[1], t[2]);
  testing::writeBinaryStl(dir / "box.stl", testing::trianglesOf(box));
  testing::writeBinaryStl(dir / "inverted.stl", testing::trianglesOf(inverted));
  const auto plan = [&dir](const std::string& name) {
    return runCli({"plan", (dir / (name + ".stl")).string(), "--layer-thickness", "2", "--voxel",
                   "1", "--bead-spacing", "3.7", "-o", (dir / name).string(), "-q"});
  };
  const CliRun normal = plan("box");
  const CliRun run = plan("inverted");
  ASSERT_EQ(normal.exitCode, 0) << normal.err;
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_TRUE(contains(run.err,
                       "curvedslicer: warning: the model's triangles all face inward (a signed "
                       "volume of -3200 mm^3: the surface was saved inside out); they were turned "
                       "to face outward"))
      << run.err;
  const auto read = [&dir](const std::string& name) {
    std::ifstream in(dir / name / "plan.json");
    return nlohmann::json::parse(in);
  };
  const nlohmann::json a = read("box"), b = read("inverted");
  ASSERT_EQ(a["layers"].size(), b["layers"].size());
  for (std::size_t l = 0; l < a["layers"].size(); ++l) {
    EXPECT_EQ(a["layers"][l]["paths"], b["layers"][l]["paths"]) << "layer " << l;
  }
}

TEST(CliRobustness, BodyNotConnectedToTheStartSurfaceIsAnErrorAndASliverAWarning) {
  // a second box floating 5 mm above the first: the bottom plane reaches only the first, so half
  // the part would have no layer
  const fs::path dir = testing::freshTempDir();
  TriMesh two = testing::makeBox(Vec3(0, 0, 0), Vec3(20, 16, 10));
  appendMesh(two, testing::makeBox(Vec3(0, 0, 15), Vec3(20, 16, 25)));
  testing::writeBinaryStl(dir / "two.stl", testing::trianglesOf(two));
  const CliRun run = runCli({"layers", (dir / "two.stl").string(), "--layer-thickness", "2",
                             "--voxel", "1", "-o", (dir / "two").string(), "-q"});
  EXPECT_EQ(run.exitCode, 2) << run.err;
  EXPECT_TRUE(contains(run.err,
                       "curvedslicer: error: part not reachable from the start surface: 3200 of "
                       "6400 inside voxels (50 %), in 1 piece(s) around x 0.5..19.5, y 0.5..15.5, "
                       "z 15..24 mm, are not connected to the start surface"))
      << run.err;
  EXPECT_FALSE(fs::exists(dir / "two"));
  // a 2 mm cube beside it: 8 of 3208 voxels, a warning naming the separate bodies
  TriMesh sliver = testing::makeBox(Vec3(0, 0, 0), Vec3(20, 16, 10));
  appendMesh(sliver, testing::makeBox(Vec3(30, 0, 5), Vec3(32, 2, 7)));
  testing::writeBinaryStl(dir / "sliver.stl", testing::trianglesOf(sliver));
  const CliRun small =
      runCli({"layers", (dir / "sliver.stl").string(), "--layer-thickness", "2", "--voxel", "1",
              "--grid", "model", "-o", (dir / "sliver").string(), "-q"});
  EXPECT_EQ(small.exitCode, 0) << small.err;
  EXPECT_TRUE(contains(small.err, "curvedslicer: warning: 8 of 3208 inside voxels")) << small.err;
  EXPECT_TRUE(contains(small.err, "no layer covers them; the model is 2 separate bodies"))
      << small.err;
}

TEST(CliRobustness, OpenTubeSaysTheModelIsOpenNotThatTheVoxelIsTooCoarse) {
  const fs::path dir = testing::freshTempDir();
  TriMesh tube = testing::makeCylinder(Vec3(50, 0, 0), 10.0, 20.0, 32);
  // Without its caps: only the triangles with a vertex at each end height.
  std::erase_if(tube.triangles, [&tube](const Vec3i& t) {
    const double z0 = tube.vertices[t[0]].z(), z1 = tube.vertices[t[1]].z(),
                 z2 = tube.vertices[t[2]].z();
    return z0 == z1 && z1 == z2;
  });
  const fs::path model = dir / "tube.stl";
  testing::writeBinaryStl(model, testing::trianglesOf(tube));
  for (const char* voxel : {"1", "0.5"}) {
    const CliRun run = runCli({"layers", model.string(), "--layer-thickness", "2", "--voxel", voxel,
                               "-o", (dir / "out").string(), "-q"});
    EXPECT_EQ(run.exitCode, 2) << run.err;
    EXPECT_TRUE(contains(run.err, "curvedslicer: error: the model is open: 64 boundary edges"));
    EXPECT_TRUE(contains(run.err, "; pass --cap-holes (CapHoles) or close the model"));
    EXPECT_FALSE(contains(run.err, "too coarse"));
  }
}

TEST(CliRobustness, PointSpacingThatExplodesThePlanExitsFourWithinSeconds) {
  const fs::path dir = testing::freshTempDir();
  const auto start = std::chrono::steady_clock::now();
  const CliRun run =
      runCli({"plan", testing::modelPath("custom_base_geom_to_slice.obj").string(), "--start",
              "mesh:" + testing::modelPath("custom_base_surface.obj").string(), "--cap-holes",
              "--layer-thickness", "1.5", "--voxel", "0.5", "--bead-spacing", "3.7",
              "--point-spacing", "1e-9", "-o", (dir / "out").string(), "-q"});
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(run.exitCode, 4) << run.err;
  EXPECT_TRUE(contains(run.err, "curvedslicer: error: the plan would hold about "));
  EXPECT_TRUE(contains(run.err, "at a point spacing of 1e-09 mm"));
  EXPECT_TRUE(contains(run.err, "use a point spacing of at least "));
  EXPECT_LT(seconds, 5.0);
  EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace
}  // namespace curvedslicer
