// Tests of export/rapid_writer.hpp, read back by the strict reader of
// program_readers_krl_rapid.hpp: robtargets with extax land on the planned path through the
// cell's forward kinematics; declared tooldata (the cell's TCP and load) and coordinated wobjdata
// with ActUnit; SetDO/WaitDI/SetAO on the cell's signals; modules per split called from main; a
// cell without RAPID settings or without the mechanical unit.
#include "curvedslicer/export/rapid_writer.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "export_test_support.hpp"
#include "program_readers_krl_rapid.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

std::size_t countText(const ExportResult& result, const std::string& text) {
  std::size_t n = 0;
  for (const ExportFile& f : result.files) {
    for (std::size_t at = f.text.find(text); at != std::string::npos;
         at = f.text.find(text, at + 1)) {
      ++n;
    }
  }
  return n;
}

TEST(RapidWriter, RobtargetsAndExtaxLandOnThePlannedPath) {
  const Cell cell = defaultCell();
  const Plan plan = makeConePlan(3, 24);
  const MotionPlan motion = planMotion(plan, cell);
  const ExportResult result = RapidWriter().write(motion, cell, {}, {});
  ASSERT_EQ(result.files.size(), 1u);
  EXPECT_EQ(result.files[0].name, "WAAM.mod");
  const ReadExport read = readRapidExport(result, cell);
  expectRoundTrip(read, motion, placedCell(cell, motion));
  ASSERT_EQ(read.program.moves.size(), motion.points.size());
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const bool home = motion.points[i].kind == MoveKind::Home;
    EXPECT_EQ(read.program.moves[i].jointTarget, home) << read.program.moves[i].line;
    EXPECT_EQ(read.program.moves[i].joint, home || i == 0) << read.program.moves[i].line;
  }
  EXPECT_EQ(read.program.welds.size(), plan.pathCount());
  EXPECT_EQ(read.arcWaits, plan.pathCount());
  const std::string& text = result.files[0].text;
  EXPECT_NE(text.find("PERS tooldata tWaam1 := [TRUE,[[0.000,0.000,400.000],"), std::string::npos);
  EXPECT_NE(text.find("wobjTable := [FALSE, FALSE, \"STN1\","), std::string::npos);
  EXPECT_EQ(countText(result, "SetDO doArcOn, 1;"), plan.pathCount());
  EXPECT_EQ(countText(result, "SetDO doArcOn, 0;"), plan.pathCount());
  EXPECT_EQ(countText(result, "WaitDI diArcEst, 1;"), plan.pathCount());
  // the wire feed: the cell's process value (the plan sets none), once per weld
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    if (motion.points[i].arcOn) {
      EXPECT_EQ(read.wireFeed[i], cell.process.wireFeed) << i;
    }
  }
  EXPECT_EQ(countText(result, "SetAO aoWireFeed, 5.000;"), plan.pathCount());
  EXPECT_THROW(RapidWriter().write(MotionPlan{}, cell, {}, {}), InvalidInput);
}

TEST(RapidWriter, WithoutOptionalSignalsAndCoordination) {
  Cell cell = defaultCell();
  cell.exportOptions.coordinated = false;
  cell.controller.rapid->arcEstablishedSignal.clear();
  cell.controller.rapid->wireFeedSignal.clear();
  cell.controller.rapid->mechUnit.clear();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  const ExportResult result = RapidWriter().write(motion, cell, {}, {});
  const ReadExport read = readRapidExport(result, cell);
  expectRoundTrip(read, motion, placedCell(cell, motion));
  EXPECT_EQ(read.arcWaits, 0u);
  EXPECT_EQ(countText(result, "SetAO"), 0u);
  EXPECT_EQ(countText(result, "ActUnit"), 0u);
}

TEST(RapidWriter, SplitsIntoModulesMainCallsInOrder) {
  Cell cell = defaultCell();
  cell.controller.rapid->maxLinesPerModule = 50;
  const Plan plan = makeConePlan(4, 24);
  MotionPlan motion = planMotion(plan, cell);
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    if (motion.points[i].arcOn && i % 5 == 0) motion.points[i].wireFeed = 6.5;
  }
  ExportOptions options;
  options.programName = "CONE";
  const ExportResult result = RapidWriter().write(motion, cell, options, {});
  ASSERT_GT(result.files.size(), 3u);
  EXPECT_EQ(result.files[0].name, "CONE.mod");
  const ReadExport read = readRapidExport(result, cell);
  EXPECT_EQ(read.programs + 1, result.files.size()) << "main() only calls";
  expectRoundTrip(read, motion, placedCell(cell, motion));
  EXPECT_EQ(read.program.welds.size(), plan.pathCount());
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const MotionPoint& p = motion.points[i];
    if (p.arcOn) {
      EXPECT_EQ(read.wireFeed[i], p.wireFeed > 0.0 ? p.wireFeed : cell.process.wireFeed) << i;
    }
  }
  cell.controller.rapid->maxLinesPerModule = 0;
  const ReadExport whole = readRapidExport(RapidWriter().write(motion, cell, options, {}), cell);
  EXPECT_EQ(whole.program.welds, read.program.welds);
  EXPECT_EQ(whole.wireFeed.size(), read.wireFeed.size());
}

TEST(RapidWriter, ACellWithoutRapidSettingsIsRefusedNamingTheFieldAndFile) {
  Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  cell.controller.source = "abb.json";
  cell.controller.rapid->mechUnit.clear();
  for (int round = 0; round < 2; ++round) {
    try {
      RapidWriter().write(motion, cell, {}, {});
      ADD_FAILURE() << "exported without the RAPID settings";
    } catch (const InvalidInput& e) {
      const std::string message = e.what();
      const std::string field = round == 0 ? "abb.json: /controller/rapid/mech_unit is missing"
                                           : "abb.json: /controller/rapid is missing";
      EXPECT_EQ(message.rfind(field, 0), 0u) << message;
    }
    cell.controller.rapid.reset();
  }
  // coordinated without a mechanical unit: refused when the cell is read
  std::string json = writeCellJson(defaultCell());
  const std::string field = "\"mech_unit\": \"STN1\",";
  ASSERT_NE(json.find(field), std::string::npos) << json;
  json.erase(json.find(field), field.size());
  try {
    parseCell(json, "abb.json");
    ADD_FAILURE() << "read a coordinated RAPID section without mech_unit";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("abb.json: field /controller/rapid/mech_unit is missing"),
              std::string::npos)
        << e.what();
  }
}

TEST(RapidWriter, ASignalThatIsNoRapidNameIsRefusedWhenTheCellIsRead) {
  std::string json = writeCellJson(defaultCell());
  const std::string field = "\"arc_signal\": \"doArcOn\"";
  ASSERT_NE(json.find(field), std::string::npos) << json;
  json.replace(json.find(field), field.size(), "\"arc_signal\": \"do Arc;\"");
  try {
    parseCell(json, "abb.json");
    ADD_FAILURE() << "read a signal name with a space and a semicolon";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("abb.json: field /controller/rapid/arc_signal must be a "
                                         "RAPID name"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace curvedslicer
