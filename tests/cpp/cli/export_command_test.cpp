// End-to-end tests of `curvedslicer export`: exit codes, outputs, all-or-nothing on errors.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/sanitized_build.hpp"
#include "common/small_part.hpp"
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
    // The default cell is a Yaskawa cell: the other vendors' languages need the option.
    const std::string foreign = vendorOfFormat(format) == RobotVendor::Kuka ||
                                        vendorOfFormat(format) == RobotVendor::Abb ||
                                        vendorOfFormat(format) == RobotVendor::Fanuc
                                    ? " --allow-foreign-cell"
                                    : "";
    EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --format " + format + foreign +
                              " -q -o '" + out.string() + "'"),
              0)
        << format << ": " << readFile((dir / "stderr.txt").string());
    EXPECT_GT(fs::file_size(out), 500u) << format;
  }
  // the file-name rule: the program is named after the output file (JBI upper-cases it)
  EXPECT_NE(readFile((dir / "out.jbi").string()).find("//NAME OUT\r\n"), std::string::npos);
  EXPECT_NE(readFile((dir / "out.ls").string()).find("/PROG  OUT\r\n"), std::string::npos);
}

TEST(ExportCommand, RefusesAFileNameThatDisagreesWithTheProgramName) {
  const fs::path dir = freshTempDir();
  const fs::path plan = dir / "plan.json";
  writePlanJson(plan, makeConePlan(2, 16));
  const fs::path out = dir / "CYL.JBI";
  EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --format jbi --name CYLINDER_PART -o '" +
                            out.string() + "'"),
            2);
  const std::string err = readFile((dir / "stderr.txt").string());
  EXPECT_NE(err.find("name the file CYLINDER.JBI"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(dir / "CYLINDER.JBI"));
  // the name the error asks for is accepted, and without --name the file's name is taken
  EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --format jbi --name CYLINDER_PART -q -o '" +
                            (dir / "CYLINDER.JBI").string() + "'"),
            0)
      << readFile((dir / "stderr.txt").string());
  EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --format jbi -q -o '" + out.string() + "'"),
            0)
      << readFile((dir / "stderr.txt").string());
  EXPECT_NE(readFile(out.string()).find("//NAME CYL\r\n"), std::string::npos);
}

TEST(ExportCommand, AnotherVendorsLanguageNeedsTheOptionOrExitsTwo) {
  const fs::path dir = freshTempDir();
  const fs::path plan = dir / "plan.json";
  writePlanJson(plan, makeConePlan(2, 16));
  const fs::path out = dir / "part.src";
  const std::string command =
      "export '" + plan.string() + "' --format krl -q -o '" + out.string() + "'";
  EXPECT_EQ(runCli(dir, command), 2);  // the default cell is Yaskawa's
  const std::string err = readFile((dir / "stderr.txt").string());
  EXPECT_NE(err.find("the cell is for a yaskawa controller but the format krl is for kuka"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("--allow-foreign-cell"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(runCli(dir, command + " --allow-foreign-cell"), 0)
      << readFile((dir / "stderr.txt").string());
  EXPECT_TRUE(fs::exists(out));
  // A KUKA cell writes KRL without the option and refuses JBI.
  const std::string kuka =
      (fs::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "cells" / "kuka_kr16_r1610_2_dkp400.json")
          .string();
  fs::remove(out);
  EXPECT_EQ(runCli(dir, command + " --cell '" + kuka + "'"), 0)
      << readFile((dir / "stderr.txt").string());
  EXPECT_TRUE(fs::exists(out));
  EXPECT_EQ(runCli(dir, "export '" + plan.string() + "' --cell '" + kuka +
                            "' --format jbi -q -o '" + (dir / "W.JBI").string() + "'"),
            2);
  EXPECT_NE(readFile((dir / "stderr.txt").string())
                .find("the cell is for a kuka controller but the format jbi is for yaskawa"),
            std::string::npos);
}

/// Exports `dir`/base/plan.json with each vendor's cell of resources/cells/ to CSV and the cell's
/// own language: each exits 0 (every point reachable within the joint limits, no collision, part
/// within the working volume; each of these stops an export with exit 2) and writes its file.
void expectExportsWithEachVendorsCell(const fs::path& dir) {
  const std::pair<const char*, const char*> cells[] = {
      {"motoman_hp20d_tilt_rotate.json", "jbi"},
      {"kuka_kr16_r1610_2_dkp400.json", "krl"},
      {"abb_irb1660id_irbp_a250.json", "rapid"},
      {"fanuc_arcmate100ic_2axis_positioner.json", "ls"}};
  for (const auto& [file, language] : cells) {
    const std::string cell =
        (fs::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "cells" / file).string();
    for (const char* format : {"csv", language}) {
      SCOPED_TRACE(std::string(file) + " " + format);
      // One folder per cell; the file's stem is the program name (the export's name rule).
      fs::create_directories(dir / file);
      const fs::path out = dir / file / (std::string("BASE.") + format);
      EXPECT_EQ(runCli(dir, "export '" + (dir / "base" / "plan.json").string() + "' --cell '" +
                                cell + "' --format " + format + " -o '" + out.string() + "'"),
                0)
          << readFile((dir / "stderr.txt").string());
      EXPECT_TRUE(fs::exists(out));
      const std::string err = readFile((dir / "stderr.txt").string());
      EXPECT_EQ(err.find("cell names no vendor"), std::string::npos) << err;
    }
  }
}

// The README's curved example (custom base, cap holes, 1.5 mm layers, 3.7 mm beads; voxel 2 mm as
// in ModelExports instead of the README's 0.5 mm, for time) planned by the command line, then
// exported with each vendor's cell of resources/cells/: CSV and the cell's own language succeed
// (exit 0: every point reachable within the joint limits, no collision, part within the working
// volume; each of these stops an export with exit 2).
TEST(ExportCommand, CurvedExampleExportsWithEachVendorsCell) {
  CURVEDSLICER_SKIP_IF_SANITIZED("ExportCommand.SmallPartExportsWithEachVendorsCell");
  const fs::path dir = freshTempDir();
  const fs::path models = fs::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "models";
  ASSERT_EQ(runCli(dir, "plan '" + (models / "custom_base_geom_to_slice.obj").string() +
                            "' --start 'mesh:" + (models / "custom_base_surface.obj").string() +
                            "' --cap-holes --layer-thickness 1.5 --voxel 2 --bead-spacing 3.7 -q "
                            "-o '" +
                            (dir / "base").string() + "'"),
            0)
      << readFile((dir / "stderr.txt").string());
  expectExportsWithEachVendorsCell(dir);
}

/// The same on the small part of common/small_part.hpp (the sanitizer build runs this one).
TEST(ExportCommand, SmallPartExportsWithEachVendorsCell) {
  const fs::path dir = freshTempDir();
  const SmallPartSettings s;
  std::ostringstream plan;
  plan << "plan '" << writeSmallPartStl() << "' --layer-thickness " << s.layerThickness
       << " --voxel " << s.voxel << " --bead-spacing " << s.beadSpacing << " --point-spacing "
       << s.pointSpacing << " -q -o '" << (dir / "base").string() << "'";
  ASSERT_EQ(runCli(dir, plan.str()), 0) << readFile((dir / "stderr.txt").string());
  expectExportsWithEachVendorsCell(dir);
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

// Inputs that are not regular files are refused before they are opened or read: a FIFO (whose
// opening would block until a writer comes), /dev/zero (endless), a folder; the output may not be
// one of the inputs (the plan, the cell), by any name.
TEST(ExportCommand, InputsThatAreNotRegularFilesOrAreTheOutputAreRefused) {
  const fs::path dir = freshTempDir();
  const fs::path plan = dir / "plan.json";
  writePlanJson(plan, makeSmallPlan());
  { std::ofstream(dir / "cell.json") << writeCellJson(defaultCell()); }
  const fs::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path out = dir / "out.csv";
  const auto expectRefused = [&](const std::string& arguments, const std::string& needle) {
    SCOPED_TRACE(arguments);
    // `timeout` ends a run that would block or read forever: exit 124, not 2
    EXPECT_EQ(runCli(dir, "export " + arguments + " --format csv -q"), 2);
    const std::string err = readFile((dir / "stderr.txt").string());
    EXPECT_NE(err.find(needle), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(out));
  };
  const std::string planArg = "'" + plan.string() + "'";
  const std::string outArg = " -o '" + out.string() + "'";
  expectRefused(planArg + " --cell '" + fifo.string() + "'" + outArg,
                "is a FIFO (named pipe), not a regular file");
  expectRefused("'" + fifo.string() + "'" + outArg, "plan file");
  expectRefused(planArg + " --cell /dev/zero" + outArg, "is a device, not a regular file");
  expectRefused(planArg + " --cell '" + dir.string() + "'" + outArg, "is a folder");
  // the output is the plan, also through a symbolic link: refused, the plan left as it was
  const std::string before = readFile(plan.string());
  EXPECT_EQ(runCli(dir, "export " + planArg + " --format json -q -o '" + plan.string() + "'"), 2);
  EXPECT_NE(readFile((dir / "stderr.txt").string()).find("is the plan file being read"),
            std::string::npos);
  fs::create_symlink(plan, dir / "link.json");
  EXPECT_EQ(runCli(dir, "export " + planArg + " --format json -q -o '" +
                            (dir / "link.json").string() + "'"),
            2);
  EXPECT_EQ(runCli(dir, "export " + planArg + " --cell '" + (dir / "cell.json").string() +
                            "' --format json -q -o '" + (dir / "cell.json").string() + "'"),
            2);
  EXPECT_NE(readFile((dir / "stderr.txt").string()).find("is the cell file being read"),
            std::string::npos);
  EXPECT_EQ(readFile(plan.string()), before);
  EXPECT_NO_THROW(readCell(dir / "cell.json"));
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
  // A plan the robot cannot reach (5 m away from the table, in a cell whose working volume
  // allows it): exit 2, nothing written.
  Plan far = makeSmallPlan();
  for (auto& layer : far.layers) {
    for (auto& path : layer.paths) {
      for (auto& p : path.points) p.position.x() += 5000.0;
    }
  }
  writePlanJson(dir / "far.json", far);
  Cell wide = defaultCell();
  wide.positioner.geometry.maxPartRadius = 6000.0;
  { std::ofstream(dir / "wide.json") << writeCellJson(wide); }
  EXPECT_EQ(
      runCli(dir, "export '" + (dir / "far.json").string() + "' --cell '" +
                      (dir / "wide.json").string() + "' --format jbi -o '" + out.string() + "'"),
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

/// makeSmallPlan (weld points 1.5 and 3 mm above the part origin) moved down by `dz` mm.
Plan lowered(double dz) {
  Plan plan = makeSmallPlan();
  plan.parameters.layerThickness = 1.5;
  for (auto& layer : plan.layers) {
    for (auto& path : layer.paths) {
      for (auto& p : path.points) p.position.z() -= dz;
    }
  }
  return plan;
}

TEST(ExportCommand, APartBelowTheTableFailsWithExitTwoNamingTheLowestPoint) {
  const fs::path dir = freshTempDir();
  Plan plan = lowered(9.5);  // weld points at z = -8 and -6.5; the lowest: layer 0 path 1 point 2
  plan.layers[0].paths[1].points[2].position.z() -= 0.75;
  writePlanJson(dir / "plan.json", plan);
  const fs::path out = dir / "W.JBI";
  const std::string command = "export '" + (dir / "plan.json").string() + "' --format jbi -o '" +
                              out.string() + "' --placement cell";
  EXPECT_EQ(runCli(dir, command), 2);
  const std::string err = readFile((dir / "stderr.txt").string());
  EXPECT_NE(err.find("curvedslicer: error: weld points below the table top: layer 0 path 1 point "
                     "2 (part 0.00, 5.00, -8.75 mm) lies 8.750 mm below the table (12 points "
                     "below it)"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("positioner/table_to_part"), std::string::npos) << err;
  EXPECT_NE(err.find("--placement rest"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out));
  // The same plan resting on the table (the default) is written; the summary gives the
  // placement used and the note says what rest did.
  EXPECT_EQ(runCli(dir, "export '" + (dir / "plan.json").string() + "' --format jbi -o '" +
                            out.string() + "'"),
            0)
      << readFile((dir / "stderr.txt").string());
  const std::string summary = readFile((dir / "stdout.txt").string());
  EXPECT_NE(summary.find("part on the table (placement rest): table_to_part xyz 0.000, 0.000, "
                         "10.250 mm"),
            std::string::npos)
      << summary;
  EXPECT_NE(readFile((dir / "stderr.txt").string()).find("note: part placement rest"),
            std::string::npos);
  EXPECT_TRUE(fs::exists(out));
}

TEST(ExportCommand, PlacementAutoSaysWhatRiserItChose) {
  const fs::path dir = freshTempDir();
  writePlanJson(dir / "plan.json", lowered(9.5));
  const fs::path out = dir / "W.JBI";
  ASSERT_EQ(runCli(dir, "export '" + (dir / "plan.json").string() + "' --format jbi -o '" +
                            out.string() + "' --placement auto"),
            0)
      << readFile((dir / "stderr.txt").string());
  // a flat part: the torch clears the table resting on it, no riser raised
  EXPECT_NE(readFile((dir / "stdout.txt").string()).find("part on the table (placement auto)"),
            std::string::npos);
  EXPECT_NE(readFile((dir / "stderr.txt").string())
                .find("note: part placement auto: the torch clears the table on every move "
                      "without raising the cell's riser (0.0 mm)"),
            std::string::npos)
      << readFile((dir / "stderr.txt").string());
  EXPECT_TRUE(fs::exists(out));
}

TEST(ExportCommand, GcodeMachineCoordinatesUseThePlacementOfTheMotion) {
  const fs::path dir = freshTempDir();
  writePlanJson(dir / "plan.json", lowered(9.5));  // rests 8 + 1.5 = 9.5 mm higher
  const fs::path out = dir / "part.gcode";
  ASSERT_EQ(runCli(dir, "export '" + (dir / "plan.json").string() +
                            "' --format gcode --gcode-mode machine -q -o '" + out.string() + "'"),
            0)
      << readFile((dir / "stderr.txt").string());
  const std::string gcode = readFile(out.string());
  EXPECT_NE(gcode.find("; table to part: translation 0.000 0.000 9.500 mm"), std::string::npos)
      << gcode.substr(0, 800);
}

TEST(ExportCommand, APartOutsideTheWorkingVolumeFailsWithExitTwo) {
  const fs::path dir = freshTempDir();
  Plan plan = makeSmallPlan();
  plan.layers[1].paths[0].points[0].position.x() = -400.0;
  writePlanJson(dir / "plan.json", plan);
  EXPECT_EQ(runCli(dir, "export '" + (dir / "plan.json").string() + "' --format csv -o '" +
                            (dir / "out.csv").string() + "'"),
            2);
  const std::string err = readFile((dir / "stderr.txt").string());
  EXPECT_NE(err.find("outside the positioner's working volume: layer 1 path 0 point 0 (part "
                     "-400.00, -5.00, 3.00 mm) lies 400.031 mm from the rotation axis"),
            std::string::npos)
      << err;
}

TEST(ExportCommand, MotionOptionsAreParsedAndBadValuesNamed) {
  const fs::path dir = freshTempDir();
  writePlanJson(dir / "plan.json", makeSmallPlan());
  const std::string base = "export '" + (dir / "plan.json").string() + "' --format csv -o '" +
                           (dir / "out.csv").string() + "' ";
  EXPECT_EQ(runCli(dir, base + "--clearance 15 --merge-tolerance 0.02 --max-a2-step 4 "
                               "--allow-collisions --no-home --placement cell"),
            0)
      << readFile((dir / "stderr.txt").string());
  EXPECT_NE(readFile((dir / "stdout.txt").string()).find("(placement cell)"), std::string::npos);
  const std::pair<const char*, const char*> bad[] = {
      {"--clearance ten", "clearance"},
      {"--merge-tolerance x", "merge tolerance"},
      {"--max-a2-step 5deg", "maximum a2 step"},
      {"--placement floor", "unknown part placement: 'floor'"},
  };
  for (const auto& [option, needle] : bad) {
    EXPECT_EQ(runCli(dir, base + option), 2) << option;
    const std::string err = readFile((dir / "stderr.txt").string());
    EXPECT_NE(err.find(needle), std::string::npos) << option << ": " << err;
  }
}

TEST(ExportCommand, NotesOfAVersionOneCellArePrinted) {
  const fs::path dir = freshTempDir();
  writePlanJson(dir / "plan.json", makeSmallPlan());
  // The default cell written in the version-1 format: without the version-2 fields.
  nlohmann::json cell = nlohmann::json::parse(writeCellJson(defaultCell()));
  cell["version"] = 1;
  cell["robot"].erase("link_capsules_mm");
  cell["tool"].erase("envelope");
  cell["positioner"].erase("geometry");
  cell.erase("home");
  const fs::path v1 = dir / "v1.json";
  { std::ofstream(v1) << cell.dump(2); }
  ASSERT_EQ(runCli(dir, "export '" + (dir / "plan.json").string() + "' --cell '" + v1.string() +
                            "' --format csv -o '" + (dir / "out.csv").string() + "'"),
            0)
      << readFile((dir / "stderr.txt").string());
  const std::string err = readFile((dir / "stderr.txt").string());
  EXPECT_NE(err.find("note: cell version 1: default torch envelope assumed"), std::string::npos)
      << err;
  EXPECT_NE(err.find("note: cell version 1: default home pose assumed"), std::string::npos) << err;
}

fs::path bundledCell(const std::string& name) {
  return fs::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "cells" / name;
}

// `cell check` prints the frames a controller takes from the cell: for the KR 16 the robot base
// and controller frame at the foot, the flange at all joints 0 (968 mm out, 1450 mm up) and the
// joint, interference and positioner limits; its joint 3 range cannot fold the arm.
TEST(CellCheckCommand, PrintsFramesReachLimitsAndSourcesOfACell) {
  const fs::path dir = freshTempDir();
  const fs::path kuka = bundledCell("kuka_kr16_r1610_2_dkp400.json");
  ASSERT_EQ(runCli(dir, "cell check '" + kuka.string() + "'"), 0)
      << readFile((dir / "stderr.txt").string());
  const std::string out = readFile((dir / "stdout.txt").string());
  for (const char* needle :
       {"robot: KUKA KR 16 R1610-2", "(vendor kuka)",
        "controller's robot frame in the base: xyz 0.0, 0.0, 0.0 mm, rpy 0.00, 0.00, 0.00 deg (the "
        "vendor's convention)",
        "reach: wrist centre up to 1612.", "joint 3: [-138.0, 175.0] deg",
        "interference limits: none", "home: robot 0.0, -105.0, 90.0",
        "sources:", "check: joints 2 and 3 cannot fold the arm within the limits"}) {
    EXPECT_NE(out.find(needle), std::string::npos) << needle << "\n" << out;
  }
}

// Every bundled cell passes the check: within its joint ranges and interference limits joints
// 2 and 3 cannot fold the arm.
TEST(CellCheckCommand, EveryBundledCellKeepsTheElbowOpen) {
  const fs::path dir = freshTempDir();
  for (const char* name :
       {"motoman_hp20d_tilt_rotate.json", "kuka_kr16_r1610_2_dkp400.json",
        "abb_irb1660id_irbp_a250.json", "fanuc_arcmate100ic_2axis_positioner.json"}) {
    EXPECT_EQ(runCli(dir, "cell check '" + bundledCell(name).string() + "'"), 0)
        << name << "\n"
        << readFile((dir / "stderr.txt").string());
    EXPECT_NE(readFile((dir / "stdout.txt").string())
                  .find("check: joints 2 and 3 cannot fold the arm within the limits"),
              std::string::npos)
        << name;
  }
  // The M-10iA's J2/J3 bounds (J3 from the horizontal) and the HP20D's U range relative to L.
  ASSERT_EQ(runCli(dir, "cell check '" +
                            bundledCell("fanuc_arcmate100ic_2axis_positioner.json").string() + "'"),
            0);
  const std::string fanuc = readFile((dir / "stdout.txt").string());
  EXPECT_NE(fanuc.find("interference limit J2/J3 fold below: -J2 - J3 <= 97.0 deg"),
            std::string::npos)
      << fanuc;
  EXPECT_NE(fanuc.find("interference limit J2/J3 fold above: J2 + J3 <= 242.0 deg"),
            std::string::npos)
      << fanuc;
  ASSERT_EQ(
      runCli(dir, "cell check '" + bundledCell("motoman_hp20d_tilt_rotate.json").string() + "'"),
      0);
  EXPECT_NE(readFile((dir / "stdout.txt").string()).find("joint 3: [-86.0, 160.0] deg"),
            std::string::npos);
}

// The HP20D's data-sheet U range (-165/+255 deg, the forearm's angle to the ground) taken as the
// joint's range relative to L folds the forearm onto the upper arm; without an interference limit
// the check exits 2 naming the fields. The controller frame is 505 mm up and the home TCP lies
// 490.1 mm above it.
TEST(CellCheckCommand, RefusesAFoldingJointRangeWithoutAnInterferenceLimit) {
  const fs::path dir = freshTempDir();
  const fs::path hp20d = bundledCell("motoman_hp20d_tilt_rotate.json");
  nlohmann::json cell = nlohmann::json::parse(readFile(hp20d.string()));
  cell["robot"]["joints"][2]["limits_deg"] = nlohmann::json::array({-165, 255});
  const fs::path datasheet = dir / "datasheet_u.json";
  { std::ofstream(datasheet) << cell.dump(2); }
  EXPECT_EQ(runCli(dir, "cell check '" + datasheet.string() + "'"), 2);
  const std::string out = readFile((dir / "stdout.txt").string());
  EXPECT_NE(out.find("controller's robot frame in the base: xyz 0.0, 0.0, 505.0 mm"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("in world, xyz 648.7, 0.0, 490.1 mm"), std::string::npos) << out;
  const std::string err = readFile((dir / "stderr.txt").string());
  EXPECT_NE(err.find("robot/joints/1 and robot/joints/2 (joints 2 and 3) allow a folded arm"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("no robot/interference limit excludes it"), std::string::npos) << err;
  // With limits that keep the elbow open (U within -60 .. 150 deg), the check passes.
  cell["robot"]["interference"] = nlohmann::json::parse(
      R"([{"name": "U max", "coefficients": [0, 0, 1, 0, 0, 0], "max_deg": 150},
          {"name": "U min", "coefficients": [0, 0, -1, 0, 0, 0], "max_deg": 60}])");
  const fs::path limited = dir / "limited.json";
  { std::ofstream(limited) << cell.dump(2); }
  EXPECT_EQ(runCli(dir, "cell check '" + limited.string() + "'"), 0)
      << readFile((dir / "stderr.txt").string());
  EXPECT_NE(
      readFile((dir / "stdout.txt").string()).find("interference limit U min: -J3 <= 60.0 deg"),
      std::string::npos);
  // An unreadable cell: exit 2 naming the field.
  cell["robot"]["interference"] = 5;
  { std::ofstream(limited) << cell.dump(2); }
  EXPECT_EQ(runCli(dir, "cell check '" + limited.string() + "'"), 2);
  EXPECT_NE(readFile((dir / "stderr.txt").string()).find("/robot/interference must be an array"),
            std::string::npos);
}

TEST(ExportCommand, HelpGivesTheMotionDefaultsFromTheOptionsStruct) {
  const fs::path dir = freshTempDir();
  ASSERT_EQ(runCli(dir, "export --help"), 0);
  const std::string help = readFile((dir / "stdout.txt").string());
  for (const char* needle :
       {"--clearance MM", "(default 10)", "--merge-tolerance MM", "(default 0.01)",
        "--max-a2-step DEG", "degrees (default 5)", "--allow-collisions", "--no-home",
        "--placement MODE", "Default rest."}) {
    EXPECT_NE(help.find(needle), std::string::npos) << needle;
  }
}

}  // namespace
}  // namespace curvedslicer
