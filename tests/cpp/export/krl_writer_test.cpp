// Tests of export/krl_writer.hpp, read back by the strict reader of program_readers_krl_rapid.hpp:
// .src/.dat pairs whose declared E6POS/E6AXIS positions with E1/E2 land on the planned path
// through the cell's forward kinematics; BAS, $APO, the arc by the cell's output with the
// arc-established wait or by TRIGGER; the split into called programs at the cell's line limit;
// the wire feed on an analog output; a cell without KRL settings.
#include "curvedslicer/export/krl_writer.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "export_test_support.hpp"
#include "program_readers_krl_rapid.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

/// How many lines of the export's files start with `prefix`.
std::size_t countLines(const ExportResult& result, const std::string& prefix) {
  std::size_t n = 0;
  for (const ExportFile& f : result.files) {
    bool ok = false;
    for (const std::string& line :
         splitLines(f.text, f.text.find('\r') != std::string::npos, &ok)) {
      if (line.rfind(prefix, 0) == 0) ++n;
    }
  }
  return n;
}

TEST(KrlWriter, PositionsAndExternalAxesLandOnThePlannedPath) {
  Cell cell = defaultCell();
  cell.exportOptions.lineEnding = LineEnding::Lf;
  const Plan plan = makeConePlan(3, 24);
  const MotionPlan motion = planMotion(plan, cell);
  const ExportResult result = KrlWriter().write(motion, cell, {}, {});
  ASSERT_EQ(result.files.size(), 2u);
  EXPECT_EQ(result.files[0].name, "WAAM.src");
  EXPECT_EQ(result.files[1].name, "WAAM.dat");
  const ReadExport read = readKrlExport(result, cell);
  expectRoundTrip(read, motion, placedCell(cell, motion));
  ASSERT_EQ(read.program.moves.size(), motion.points.size());
  EXPECT_TRUE(read.program.moves[0].joint) << "first motion must be PTP";
  for (std::size_t i = 1; i < motion.points.size(); ++i) {
    const bool home = motion.points[i].kind == MoveKind::Home;
    EXPECT_EQ(read.program.moves[i].jointTarget, home) << read.program.moves[i].line;
    EXPECT_EQ(read.program.moves[i].joint, home) << read.program.moves[i].line;
  }
  EXPECT_EQ(read.program.welds.size(), plan.pathCount());
  EXPECT_EQ(read.arcWaits, plan.pathCount()) << "the cell names arc-established input 1";
  const std::string& src = result.files[0].text;
  EXPECT_NE(src.find("$BASE=EK(MACHINE_DEF[2].ROOT,MACHINE_DEF[2].MECH_TYPE,BASE_DATA[1])"),
            std::string::npos);
  EXPECT_NE(src.find("$ACT_EX_AX=2"), std::string::npos);
  EXPECT_NE(src.find("$APO.CDIS=1.000"), std::string::npos);
  EXPECT_EQ(countLines(result, "WAIT FOR $IN[1]"), plan.pathCount());
  EXPECT_EQ(countLines(result, "$OUT[1]=TRUE"), plan.pathCount());
  EXPECT_EQ(countLines(result, "TRIGGER WHEN DISTANCE=1 DELAY=0 DO $OUT[1]=FALSE"),
            plan.pathCount());
  EXPECT_EQ(countLines(result, "$ANOUT["), 0u) << "the cell names no analog output";
}

TEST(KrlWriter, WithoutArcEstablishedInputTheArcGoesOnByTrigger) {
  Cell cell = defaultCell();
  cell.controller.krl->arcOnOutput = 7;
  cell.controller.krl->arcEstablishedInput = 0;
  const Plan plan = makeConePlan(2, 16);
  const MotionPlan motion = planMotion(plan, cell);
  const ExportResult result = KrlWriter().write(motion, cell, {}, {});
  const ReadExport read = readKrlExport(result, cell);
  expectRoundTrip(read, motion, placedCell(cell, motion));
  EXPECT_EQ(read.program.welds.size(), plan.pathCount());
  EXPECT_EQ(read.arcWaits, 0u);
  EXPECT_EQ(countLines(result, "TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[7]=TRUE"),
            plan.pathCount());
  EXPECT_EQ(countLines(result, "$OUT["), 0u) << "no plain output (it stops the advance run)";
}

TEST(KrlWriter, WorldPositionsWithoutCoordination) {
  Cell cell = defaultCell();
  cell.exportOptions.coordinated = false;
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  const ExportResult result = KrlWriter().write(motion, cell, {}, {});
  EXPECT_NE(result.files[0].text.find("$BASE=$NULLFRAME"), std::string::npos);
  const ReadExport read = readKrlExport(result, cell);  // the cell's CRLF
  expectRoundTrip(read, motion, placedCell(cell, motion));
  EXPECT_THROW(KrlWriter().write(MotionPlan{}, cell, {}, {}), InvalidInput);
}

TEST(KrlWriter, SplitsAtTheLineLimitIntoProgramsTheMainProgramCalls) {
  Cell cell = defaultCell();
  cell.controller.krl->maxLinesPerFile = 60;
  const Plan plan = makeConePlan(4, 24);
  const MotionPlan motion = planMotion(plan, cell);
  ExportOptions options;
  options.programName = "CONE_PART";
  const ExportResult result = KrlWriter().write(motion, cell, options, {});
  ASSERT_GT(result.files.size(), 6u);
  EXPECT_EQ(result.files[0].name, "CONE_PART.src");
  EXPECT_EQ(result.files[1].name, "CONE_PART.dat");
  const std::size_t programs = result.files.size() / 2 - 1;
  const std::string width = std::to_string(std::to_string(programs).size());
  EXPECT_EQ(result.files[2].name, "CONE_PART" + std::string(width == "1" ? "1" : "01") + ".src");
  const ReadExport read = readKrlExport(result, cell);  // limits, calls, names, declarations
  EXPECT_EQ(read.programs, programs);
  expectRoundTrip(read, motion, placedCell(cell, motion));
  EXPECT_EQ(read.program.welds.size(), plan.pathCount());
  EXPECT_EQ(countLines(result, "BAS(#INITMOV,0)"), 1u);
  bool warned = false;
  for (const std::string& w : result.warnings) warned |= w.find("split into") != std::string::npos;
  EXPECT_TRUE(warned);
  // the same motion unsplit: the same moves
  cell.controller.krl->maxLinesPerFile = 0;
  const ReadExport whole = readKrlExport(KrlWriter().write(motion, cell, options, {}), cell);
  ASSERT_EQ(whole.program.moves.size(), read.program.moves.size());
  EXPECT_EQ(whole.program.welds, read.program.welds);
  EXPECT_EQ(whole.program.dwells, read.program.dwells);
}

TEST(KrlWriter, WireFeedGoesOnTheAnalogOutputPerWeldMove) {
  Cell cell = defaultCell();
  cell.controller.krl->wireFeedAnalogOutput = 3;
  cell.controller.krl->wireFeedFullScale = 20.0;
  const Plan plan = makeConePlan(2, 16);
  MotionPlan motion = planMotion(plan, cell);
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    MotionPoint& p = motion.points[i];
    if (p.arcOn && p.layer == 1) p.wireFeed = 4.0 + 0.5 * static_cast<double>(i % 3);
  }
  const ExportResult result = KrlWriter().write(motion, cell, {}, {});
  const ReadExport read = readKrlExport(result, cell);
  ASSERT_EQ(read.wireFeed.size(), motion.points.size());
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const MotionPoint& p = motion.points[i];
    if (!p.arcOn) continue;
    const double expected = p.wireFeed > 0.0 ? p.wireFeed : cell.process.wireFeed;
    EXPECT_NEAR(read.wireFeed[i], expected, 20.0 * 0.5e-4) << "move " << i;
  }
  // beyond the full scale: refused, naming the field and the cell
  motion.points[motion.paths[0].begin + 1].wireFeed = 25.0;
  cell.controller.source = "kuka.json";
  try {
    KrlWriter().write(motion, cell, {}, {});
    ADD_FAILURE() << "a wire feed beyond the full scale was exported";
  } catch (const InvalidInput& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("wire_feed_full_scale_m_min in kuka.json"), std::string::npos)
        << message;
  }
}

TEST(KrlWriter, ACellWithoutKrlSettingsIsRefusedNamingTheFieldAndFile) {
  Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  cell.controller.krl.reset();
  cell.controller.source = "motoman.json";
  try {
    KrlWriter().write(motion, cell, {}, {});
    ADD_FAILURE() << "exported without /controller/krl";
  } catch (const InvalidInput& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("motoman.json: /controller/krl is missing", 0), 0u) << message;
  }
  // a KRL section without its arc output: refused when the cell is read
  std::string json = writeCellJson(defaultCell());
  const std::string field = "\"arc_on_output\": 1,";
  ASSERT_NE(json.find(field), std::string::npos);
  json.erase(json.find(field), field.size());
  try {
    parseCell(json, "kuka.json");
    ADD_FAILURE() << "read a KRL section without arc_on_output";
  } catch (const InvalidInput& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("kuka.json: field /controller/krl/arc_on_output is missing"),
              std::string::npos)
        << message;
  }
}

}  // namespace
}  // namespace curvedslicer
