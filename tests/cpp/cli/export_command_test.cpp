// End-to-end tests of `curvedslicer export`: exit codes, outputs, all-or-nothing on errors.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/test_paths.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "export/export_test_support.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using namespace testing;

/// Runs the CLI with `arguments`; stderr goes to `dir`/stderr.txt. @return the exit code.
int runCli(const fs::path& dir, const std::string& arguments) {
  const std::string command = "'" + cliPath().string() + "' " + arguments + " > '" +
                              (dir / "stdout.txt").string() + "' 2> '" +
                              (dir / "stderr.txt").string() + "'";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(ExportCommand, WritesEachFormatFromAPlanFile) {
  const fs::path dir = freshTempDir();
  const fs::path plan = dir / "plan.json";
  writePlanJson(plan, makeConePlan(2, 16));
  for (const char* format : {"jbi", "krl", "rapid", "ls", "gcode", "csv", "json"}) {
    const fs::path out = dir / (std::string("out.") + format);
    EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --format " + format + " -q -o '" +
                              out.string() + "'"),
              0)
        << format << ": " << readFile((dir / "stderr.txt").string());
    EXPECT_GT(fs::file_size(out), 500u) << format;
  }
  EXPECT_NE(readFile((dir / "out.jbi").string()).find("//NAME WAAM\r\n"), std::string::npos);
}

TEST(ExportCommand, SplitsAJbiProgramIntoSiblingJobFiles) {
  const fs::path dir = freshTempDir();
  const fs::path plan = dir / "plan.json";
  writePlanJson(plan, makeConePlan(3, 30));
  Cell cell = defaultCell();
  cell.exportOptions.maxLinesPerJob = 50;
  { std::ofstream(dir / "cell.json") << writeCellJson(cell); }
  ASSERT_EQ(runCli(dir, "export '" + plan.string() + "' --cell '" + (dir / "cell.json").string() +
                            "' --format jbi --name part --date '2026/11/22 07:00' -o '" +
                            (dir / "PART.JBI").string() + "'"),
            0)
      << readFile((dir / "stderr.txt").string());
  const std::string main = readFile((dir / "PART.JBI").string());
  EXPECT_NE(main.find("CALL JOB:PART1\r\n"), std::string::npos) << main;
  EXPECT_NE(main.find("///DATE 2026/11/22 07:00\r\n"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "PART1.JBI"));
  EXPECT_TRUE(fs::exists(dir / "PART2.JBI"));
}

TEST(ExportCommand, BadInputsFailCleanlyWithoutOutput) {
  const fs::path dir = freshTempDir();
  const fs::path plan = dir / "plan.json";
  writePlanJson(plan, makeSmallPlan());
  const fs::path out = dir / "W.JBI";
  // A cell with an invalid field: exit 2, message names the field, nothing written.
  { std::ofstream(dir / "bad_cell.json") << "{\"name\": 3}"; }
  EXPECT_EQ(
      runCli(dir, "export '" + plan.string() + "' --cell '" + (dir / "bad_cell.json").string() +
                      "' --format jbi -o '" + out.string() + "'"),
      2);
  EXPECT_NE(readFile((dir / "stderr.txt").string()).find("curvedslicer: error: "),
            std::string::npos);
  EXPECT_FALSE(fs::exists(out));
  // A plan the robot cannot reach (5 m away from the table): exit 2, nothing written.
  Plan far = makeSmallPlan();
  for (auto& layer : far.layers) {
    for (auto& path : layer.paths) {
      for (auto& p : path.points) p.position.x() += 5000.0;
    }
  }
  writePlanJson(dir / "far.json", far);
  EXPECT_EQ(runCli(dir, "export '" + (dir / "far.json").string() + "' --format jbi -o '" +
                            out.string() + "'"),
            2);
  EXPECT_NE(readFile((dir / "stderr.txt").string()).find("misses by"), std::string::npos)
      << readFile((dir / "stderr.txt").string());
  EXPECT_FALSE(fs::exists(out));
  // Unknown format, bad date, bad G-code mode, missing folder.
  EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --format xyz -o '" + out.string() + "'"),
            2);
  EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --format jbi --date 2026 -o '" +
                            out.string() + "'"),
            2);
  EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --format gcode --gcode-mode x -o '" +
                            out.string() + "'"),
            2);
  EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --format jbi -o '" +
                            (dir / "missing" / "W.JBI").string() + "'"),
            3);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace curvedslicer
