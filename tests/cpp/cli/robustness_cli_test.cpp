// The command line on hostile input (issue 13): outputs onto devices and FIFOs exit with code 3
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
#include <string>
#include <vector>

#include "cli_test_support.hpp"
#include "common/shapes.hpp"
#include "common/test_paths.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using testing::runCli;
using Args = std::vector<std::string>;

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

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
    if (node != fifo) EXPECT_EQ(st.st_rdev, ::makedev(1, 3));
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
}

}  // namespace
}  // namespace curvedslicer
