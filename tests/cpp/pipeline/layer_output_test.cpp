// Unit tests of pipeline/layer_output.hpp: file names, the voxel-set PLY and all-or-nothing
// staging of the output folder.
#include "curvedslicer/pipeline/layer_output.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/cli_test_support.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::listFolder;
using testing::readWholeFile;
using Names = std::vector<std::string>;

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST(LayerOutput, LayerFileNamesArePaddedToFourDigitsOrMore) {
  EXPECT_EQ(layerFileName(1, 12, LayerFileFormat::Ply), "layer_0001.ply");
  EXPECT_EQ(layerFileName(37, 9999, LayerFileFormat::Obj), "layer_0037.obj");
  EXPECT_EQ(layerFileName(7, 12345, LayerFileFormat::Ply), "layer_00007.ply");
  LayersResult layers;
  layers.surfaces.resize(2);
  layers.surfaces[0].index = 1;
  layers.surfaces[1].index = 2;
  EXPECT_EQ(layerFileNames(layers, LayerFileFormat::Obj),
            (Names{"layer_0001.obj", "layer_0002.obj"}));
}

TEST(LayerOutput, RecognisesLayerFilesOfEarlierRuns) {
  for (const char* name : {"layer_0001.ply", "layer_12.obj", "layer_123456.ply"}) {
    EXPECT_TRUE(isLayerFileName(name)) << name;
  }
  for (const char* name : {"layer_.ply", "layer_0001.stl", "layer_01a.ply", "player_0001.ply",
                           "layer_0001.ply.bak", "voxel_sets.ply", "report.json", "layer_0001"}) {
    EXPECT_FALSE(isLayerFileName(name)) << name;
  }
}

TEST(LayerOutput, VoxelSetsPlyHoldsCentresLayersAndDistances) {
  DistanceField field;
  GridGeometry& g = field.geometry;
  g.frame.rotation = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  g.frame.origin = Vec3(10, -5, 2);
  g.corner = Vec3(-1, -2, -3);
  g.voxelSize = 0.5;
  g.dims = Vec3i(3, 4, 5);
  field.distance.resize(g.cellCount());
  for (std::size_t n = 0; n < field.distance.size(); ++n) field.distance[n] = 0.25f * n;
  LayersResult layers;
  layers.voxelSets.push_back({1, 0.5, {0, 7}});
  layers.voxelSets.push_back({2, 1.0, {7, 59}});

  const fs::path path = freshTempDir() / "voxel_sets.ply";
  writeFileAtomically(
      path, [&](std::ostream& out) { writeVoxelSetsPly(out, layers, field); }, true);
  const testing::PlyData ply = testing::readBinaryPly(path);
  ASSERT_EQ(ply.elements.size(), 1u);
  const auto& v = ply.elements[0];
  EXPECT_EQ(v.name, "vertex");
  EXPECT_EQ(v.properties, (Names{"x", "y", "z", "layer", "distance"}));
  ASSERT_EQ(v.count, 4u);
  const std::vector<std::pair<int, std::size_t>> expected{{1, 0}, {1, 7}, {2, 7}, {2, 59}};
  for (std::size_t r = 0; r < expected.size(); ++r) {
    const Vec3 c = g.centerInPart(expected[r].second);
    EXPECT_FLOAT_EQ(v.value(r, 0), static_cast<float>(c.x()));
    EXPECT_FLOAT_EQ(v.value(r, 1), static_cast<float>(c.y()));
    EXPECT_FLOAT_EQ(v.value(r, 2), static_cast<float>(c.z()));
    EXPECT_EQ(v.value(r, 3), expected[r].first);
    EXPECT_FLOAT_EQ(v.value(r, 4), 0.25f * expected[r].second);
  }
}

TEST(LayerOutput, EmptyVoxelSetsGiveAValidEmptyCloud) {
  DistanceField field;
  const fs::path path = freshTempDir() / "voxel_sets.ply";
  writeFileAtomically(
      path, [&](std::ostream& out) { writeVoxelSetsPly(out, {}, field); }, true);
  const testing::PlyData ply = testing::readBinaryPly(path);
  ASSERT_EQ(ply.elements.size(), 1u);
  EXPECT_EQ(ply.elements[0].count, 0u);
}

TEST(LayerOutput, CommitMovesFilesInAndRemovesStaleLayerFiles) {
  const fs::path dir = freshTempDir();
  for (const char* old : {"layer_0001.ply", "layer_0002.ply", "layer_0003.obj", "notes.txt"}) {
    writeText(dir / old, "old");
  }
  {
    OutputStaging staging(dir);
    staging.stage("layer_0001.ply", [](const fs::path& p) { writeText(p, "new layer"); });
    staging.stage("report.json", [](const fs::path& p) { writeTextFileAtomically(p, "{}"); });
    // Before the commit the old files are untouched; only the hidden staging folder is new.
    const Names during = listFolder(dir);
    ASSERT_EQ(during.size(), 5u);
    EXPECT_EQ(during[0].rfind(".curvedslicer-staging-", 0), 0u) << during[0];
    EXPECT_EQ(readWholeFile(dir / "layer_0001.ply"), "old");
    staging.commit(isLayerFileName);
    EXPECT_EQ(staging.stagedNames(), (Names{"layer_0001.ply", "report.json"}));
  }
  EXPECT_EQ(listFolder(dir), (Names{"layer_0001.ply", "notes.txt", "report.json"}));
  EXPECT_EQ(readWholeFile(dir / "layer_0001.ply"), "new layer");
  EXPECT_EQ(readWholeFile(dir / "notes.txt"), "old");
}

TEST(LayerOutput, StagingFoldersOfDeadRunsAreRemovedOthersKept) {
  const fs::path dir = freshTempDir();
  // A process that has exited (and been reaped): its id names no process now.
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);
  const std::string dead = ".curvedslicer-staging-" + std::to_string(child) + "-0";
  const std::string alive = ".curvedslicer-staging-" + std::to_string(::getppid()) + "-3";
  for (const std::string& name : {dead, alive, std::string(".curvedslicer-staging-x")}) {
    fs::create_directory(dir / name);
    writeText(dir / name / "layer_0001.ply", "half-written");
  }
  EXPECT_EQ(stagingFolderPid(dead), child);
  EXPECT_EQ(stagingFolderPid(".curvedslicer-staging-x"), 0);
  EXPECT_EQ(stagingFolderPid(".curvedslicer-staging-12-"), 0);
  EXPECT_EQ(stagingFolderPid("layer_0001.ply"), 0);
  {
    OutputStaging staging(dir);
    staging.stage("report.json", [](const fs::path& p) { writeText(p, "{}"); });
    EXPECT_EQ(staging.removedStagings(), (Names{dead}));
    staging.commit();
  }
  EXPECT_EQ(listFolder(dir), (Names{alive, ".curvedslicer-staging-x", "report.json"}));
}

TEST(LayerOutput, OneRunWritesIntoAFolderAtATime) {
  const fs::path dir = freshTempDir();
  {
    OutputStaging first(dir);
    first.stage("report.json", [](const fs::path& p) { writeText(p, "first"); });
    try {
      OutputStaging second(dir);
      second.stage("report.json", [](const fs::path& p) { writeText(p, "second"); });
      ADD_FAILURE() << "two runs staged into one folder at once";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(
                    "another curvedslicer run (process " + std::to_string(::getpid()) +
                    ") is writing into the output folder '" + dir.string() + "' now"),
                std::string::npos)
          << e.what();
    }
    first.commit();
  }
  // the lock ends with the commit
  OutputStaging third(dir);
  third.stage("report.json", [](const fs::path& p) { writeText(p, "third"); });
  third.commit();
  EXPECT_EQ(readWholeFile(dir / "report.json"), "third");
  EXPECT_EQ(listFolder(dir), (Names{"report.json"}));
}

TEST(LayerOutput, CommitOfARunKilledWhileCommittingIsFinishedByTheNextRun) {
  // the folder as SIGKILL left it in the middle of a commit: layer 1 already moved, layer 2 and
  // plan.json still in the staging folder, the stale layer 3 not yet removed
  const fs::path dir = freshTempDir();
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);
  const fs::path staging = dir / (".curvedslicer-staging-" + std::to_string(child) + "-0");
  fs::create_directory(staging);
  writeText(dir / "layer_0001.ply", "new 1");
  writeText(dir / "layer_0002.ply", "old 2");
  writeText(dir / "layer_0003.ply", "old 3");
  writeText(dir / "plan.json", "old plan");
  writeText(dir / "notes.txt", "the user's");
  writeText(staging / "layer_0002.ply", "new 2");
  writeText(staging / "plan.json", "new plan");
  writeText(staging / ".commit",
            "move layer_0001.ply\nmove layer_0002.ply\nmove plan.json\nremove layer_0003.ply\n"
            "remove ../escape\n");
  // and a run killed before its commit: its staged files never reach the folder
  const fs::path early = dir / (".curvedslicer-staging-" + std::to_string(child) + "-1");
  fs::create_directory(early);
  writeText(early / "plan.json", "never committed");
  {
    OutputStaging next(dir);
    next.reserve("report.json");  // the first write clears what dead runs left
    EXPECT_EQ(next.removedStagings().size(), 2u);
    EXPECT_EQ(readWholeFile(dir / "layer_0001.ply"), "new 1");
    EXPECT_EQ(readWholeFile(dir / "layer_0002.ply"), "new 2");
    EXPECT_EQ(readWholeFile(dir / "plan.json"), "new plan");
    EXPECT_FALSE(fs::exists(dir / "layer_0003.ply"));
    EXPECT_EQ(readWholeFile(dir / "notes.txt"), "the user's");
  }
  EXPECT_EQ(listFolder(dir), (Names{"layer_0001.ply", "layer_0002.ply", "notes.txt", "plan.json"}));
}

TEST(LayerOutput, CommitNeverRenamesOntoAFifoNamedLikeALayerFile) {
  const fs::path dir = freshTempDir();
  writeText(dir / "layer_0001.ply", "old");
  ASSERT_EQ(::mkfifo((dir / "layer_0002.ply").c_str(), 0600), 0);
  try {
    OutputStaging staging(dir);
    staging.stage("layer_0001.ply", [](const fs::path& p) { writeText(p, "new"); });
    staging.stage("layer_0002.ply", [](const fs::path& p) { writeText(p, "new"); });
    staging.commit(isLayerFileName);
    ADD_FAILURE() << "a FIFO was replaced";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("output path is a FIFO (named pipe), not a regular file"),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(dir / "layer_0002.ply")));
  EXPECT_EQ(readWholeFile(dir / "layer_0001.ply"), "old");  // checked before anything moved
  EXPECT_EQ(listFolder(dir), (Names{"layer_0001.ply", "layer_0002.ply"}));
}

TEST(LayerOutput, FailureBeforeCommitLeavesTheFolderAsItWas) {
  const fs::path dir = freshTempDir();
  writeText(dir / "layer_0001.ply", "old");
  EXPECT_THROW(
      {
        OutputStaging staging(dir);
        staging.stage("layer_0001.ply", [](const fs::path& p) { writeText(p, "new"); });
        staging.stage("layer_0002.ply",
                      [](const fs::path&) { throw IoError("disk full: simulated; free space"); });
        staging.commit(isLayerFileName);
      },
      IoError);
  EXPECT_EQ(listFolder(dir), (Names{"layer_0001.ply"}));
  EXPECT_EQ(readWholeFile(dir / "layer_0001.ply"), "old");
}

TEST(LayerOutput, UncommittedStagingDoesNotCreateTheFolder) {
  const fs::path dir = freshTempDir() / "new" / "out";
  fs::create_directories(dir.parent_path());
  {
    OutputStaging staging(dir);
    staging.stage("report.json", [](const fs::path& p) { writeText(p, "{}"); });
    EXPECT_TRUE(fs::is_directory(dir));  // the staging folder lives inside it meanwhile
  }
  EXPECT_FALSE(fs::exists(dir));
  {
    OutputStaging staging(dir);
    staging.stage("report.json", [](const fs::path& p) { writeText(p, "{}"); });
    staging.commit();
  }
  EXPECT_EQ(listFolder(dir), (Names{"report.json"}));
}

TEST(LayerOutput, CheckOutputFolderRejectsFilesInTheWay) {
  const fs::path base = freshTempDir();
  writeText(base / "file", "x");
  EXPECT_NO_THROW(checkOutputFolder(base));
  EXPECT_NO_THROW(checkOutputFolder(base / "missing" / "deeper"));
  EXPECT_THROW(checkOutputFolder(base / "file"), IoError);
  EXPECT_THROW(checkOutputFolder(base / "file" / "sub"), IoError);
  EXPECT_THROW(checkOutputFolder(""), IoError);
  EXPECT_FALSE(fs::exists(base / "missing"));  // checking creates nothing
}

}  // namespace
}  // namespace curvedslicer
