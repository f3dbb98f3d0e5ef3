// The strict readers of program_readers.hpp applied to the LS, JBI, G-code and CSV/JSON exports:
// every file parsed, structure, declarations against uses, names against file names, line limits
// and finite numbers checked, and the positions read reproduce the plan's points through the
// cell's forward kinematics within 0.01 mm (round trip). Also the file-name rule, the cell's
// controller section (a missing vendor block is named with its file), the JBI arc wait, the LS
// weld schedules, and the G-code dialects (dwell units, TCP codes, inverse-time feed keeping the
// weld speed relative to the part).
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/sanitized_build.hpp"
#include "common/small_part.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "export_test_support.hpp"
#include "model_plans.hpp"
#include "program_readers.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

/// mm: reader positions → forward kinematics → plan points.
constexpr double kRoundTrip = 0.01;

/// One export to read back: format and options.
struct Variant {
  ExportFormat format;
  ExportOptions options;
  std::string label;
};

std::vector<Variant> myVariants() {
  std::vector<Variant> v;
  v.push_back({ExportFormat::Jbi, {}, "jbi"});
  v.push_back({ExportFormat::Ls, {}, "ls"});
  for (GcodeDialect d : {GcodeDialect::Generic, GcodeDialect::LinuxCnc}) {
    for (GcodeMode m : {GcodeMode::Tcp, GcodeMode::Machine}) {
      ExportOptions o;
      o.gcodeDialect = d;
      o.gcodeMode = m;
      v.push_back({ExportFormat::Gcode, o,
                   "gcode " + std::string(toString(d)) + " " + std::string(toString(m))});
    }
  }
  v.push_back({ExportFormat::Csv, {}, "csv"});
  v.push_back({ExportFormat::Json, {}, "json"});
  return v;
}

ReadProgram readStrictly(const ExportResult& r, const Cell& cell) {
  switch (r.format) {
    case ExportFormat::Jbi:
      return readJbiProgram(r, cell);
    case ExportFormat::Ls:
      return readLsProgram(r, cell,
                           static_cast<std::size_t>(cell.controller.ls->maxLinesPerProgram));
    case ExportFormat::Gcode:
      return readGcodeProgram(r, cell);
    case ExportFormat::Csv:
    case ExportFormat::Json:
      return readNeutralProgram(r, cell);
    default:
      break;
  }
  ADD_FAILURE() << "no strict reader here for " << toString(r.format);
  return {};
}

/// Exports `motion` in every variant with the placed cell, reads each back strictly and checks
/// moves, welds, the round trip of every point, speeds where the format states them, the JBI
/// line limit and the program file sizes (under `maxFileBytes`; CSV/JSON are not programs).
void expectStrictRoundTrip(const MotionPlan& motion, const Cell& cell,
                           std::size_t maxFileBytes = 4u << 20) {
  const Cell placed = placedCell(cell, motion);
  for (const Variant& v : myVariants()) {
    SCOPED_TRACE(v.label);
    const ExportResult r = exportProgram(motion, placed, v.format, v.options);
    const bool isProgram = v.format != ExportFormat::Csv && v.format != ExportFormat::Json;
    for (const ExportFile& f : r.files) {
      // controller programs only: the neutral files are data for analysis, one file per plan
      if (isProgram) {
        EXPECT_LT(f.text.size(), maxFileBytes) << f.name;
      }
      if (v.format == ExportFormat::Jbi) {
        EXPECT_LE(parseJbi(f.text).instructions.size(),
                  static_cast<std::size_t>(cell.exportOptions.maxLinesPerJob))
            << f.name;
      }
    }
    const ReadProgram program = readStrictly(r, placed);
    ASSERT_EQ(program.moves.size(), motion.points.size());
    ASSERT_EQ(program.welds.size(), motion.paths.size());
    for (std::size_t w = 0; w < motion.paths.size(); ++w) {
      EXPECT_EQ(program.welds[w].first, motion.paths[w].begin);
      EXPECT_EQ(program.welds[w].second, motion.paths[w].end - 1);
    }
    std::size_t far = 0, speedOff = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < motion.points.size(); ++i) {
      const ProgramMove& m = program.moves[i];
      ASSERT_TRUE(m.partPoint.has_value()) << m.line;
      const double d = (*m.partPoint - motion.points[i].position).norm();
      worst = std::max(worst, d);
      if (d > kRoundTrip && far++ < 3) {
        ADD_FAILURE() << "point " << i << " read back " << d << " mm off: " << m.line;
      }
      // Part-relative speed of welds (G-code; machine mode through inverse time) on moves with
      // a part-frame length (a move that only turns the table has none to keep).
      const MotionPoint& p = motion.points[i];
      const bool hasLength = i > 0 && (p.position - motion.points[i - 1].position).norm() > 0.1;
      if (p.arcOn && hasLength && std::isfinite(m.speed) && v.format == ExportFormat::Gcode &&
          std::abs(m.speed - p.speed) > 0.005 * p.speed && speedOff++ < 3) {
        ADD_FAILURE() << "weld speed " << m.speed << " mm/s, planned " << p.speed << ": " << m.line;
      }
    }
    EXPECT_EQ(far, 0u) << "worst " << worst << " mm";
    EXPECT_EQ(speedOff, 0u);
  }
}

TEST(StrictReaders, ConeMotionRoundTripsInEveryFormat) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeConePlan(3, 24), cell);
  expectStrictRoundTrip(motion, cell);
}

TEST(StrictReaders, SplitLsAndJbiProgramsRoundTripAndStayUnderTheirLimits) {
  Cell cell = defaultCell();
  cell.controller.ls->maxLinesPerProgram = 40;
  cell.exportOptions.maxLinesPerJob = 40;
  const MotionPlan motion = planMotion(makeConePlan(3, 24), cell);
  const ExportResult ls = exportProgram(motion, placedCell(cell, motion), ExportFormat::Ls);
  ASSERT_GT(ls.files.size(), 3u);
  EXPECT_EQ(ls.files[0].name, "WAAM.LS");
  EXPECT_NE(ls.files[0].text.find("   1:  CALL WAAM1 ;"), std::string::npos);
  expectStrictRoundTrip(motion, cell);
}

TEST(StrictReaders, SplitGcodeRoundTripsThroughItsCallsInBothDialects) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeConePlan(3, 24), cell);
  const Cell placed = placedCell(cell, motion);
  for (GcodeDialect d : {GcodeDialect::Generic, GcodeDialect::LinuxCnc}) {
    for (GcodeMode m : {GcodeMode::Tcp, GcodeMode::Machine}) {
      SCOPED_TRACE(std::string(toString(d)) + " " + std::string(toString(m)));
      ExportOptions o;
      o.gcodeDialect = d;
      o.gcodeMode = m;
      o.gcodeMaxLinesPerFile = 30;
      const ExportResult r = exportProgram(motion, placed, ExportFormat::Gcode, o);
      ASSERT_GT(r.files.size(), 3u);
      EXPECT_EQ(r.files[1].name, d == GcodeDialect::LinuxCnc ? "waam_1.ngc" : "O1001.ngc");
      for (std::size_t k = 1; k < r.files.size(); ++k) EXPECT_LE(r.files[k].lines, 30u);
      const ReadProgram program = readGcodeProgram(r, placed);
      ASSERT_EQ(program.moves.size(), motion.points.size());
      EXPECT_EQ(program.welds.size(), motion.paths.size());
      for (std::size_t i = 0; i < motion.points.size(); ++i) {
        ASSERT_TRUE(program.moves[i].partPoint.has_value());
        EXPECT_LT((*program.moves[i].partPoint - motion.points[i].position).norm(), kRoundTrip);
      }
    }
  }
}

TEST(StrictReaders, LsWritesTheCellsSchedulesAndChangesThemWithinAWeld) {
  Cell cell = defaultCell();
  cell.controller.ls = LsControllerSettings{2, 7, 9, 2000};
  MotionPlan motion = planMotion(makeConePlan(1, 12), cell);
  ASSERT_EQ(motion.paths.size(), 1u);
  const MotionPathSpan span = motion.paths[0];
  for (std::size_t i = span.begin + 4; i < span.end; ++i) motion.points[i].weldSchedule = 11;
  const ExportResult r = exportProgram(motion, placedCell(cell, motion), ExportFormat::Ls);
  const std::string& text = r.files[0].text;
  EXPECT_NE(text.find("  ARC Welding Equipment : 2,*,*,*,*;"), std::string::npos);
  const std::size_t start = text.find("Arc Start[7] ;");
  const std::size_t change = text.find("Arc Start[11] ;");
  const std::size_t end = text.find("Arc End[9] ;");
  ASSERT_NE(start, std::string::npos);
  ASSERT_NE(change, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  EXPECT_TRUE(start < change && change < end);
  const ReadProgram program = readLsProgram(r, placedCell(cell, motion));
  EXPECT_EQ(program.welds.size(), 1u);
  EXPECT_EQ(program.moves.size(), motion.points.size());
}

TEST(StrictReaders, JbiWaitsForTheArcInputTheCellNames) {
  Cell cell = defaultCell();
  cell.controller.jbi->arcWaitInput = 12;
  const MotionPlan motion = planMotion(makeConePlan(2, 12), cell);
  const ExportResult r = exportProgram(motion, placedCell(cell, motion), ExportFormat::Jbi);
  const JbiJob job = parseJbi(r.files[0].text);
  std::size_t waits = 0;
  for (std::size_t k = 0; k < job.instructions.size(); ++k) {
    if (startsWith(job.instructions[k], "ARCON")) {
      ASSERT_LT(k + 1, job.instructions.size());
      EXPECT_EQ(job.instructions[k + 1], "WAIT IN#(12)=ON");
      ++waits;
    }
  }
  EXPECT_EQ(waits, motion.paths.size());
  EXPECT_EQ(readJbiProgram(r, placedCell(cell, motion)).welds.size(), motion.paths.size());
}

TEST(StrictReaders, GcodeDwellUnitsAndTcpCodesFollowTheDialect) {
  Cell cell = defaultCell();  // layer dwell 60 s
  const MotionPlan motion = planMotion(makeConePlan(2, 12), cell);
  const Cell placed = placedCell(cell, motion);
  ExportOptions o;
  const std::string generic = exportProgram(motion, placed, ExportFormat::Gcode, o).files[0].text;
  EXPECT_NE(generic.find("\nG4 P60000\r"), std::string::npos);
  EXPECT_NE(generic.find("\nG43.4 H1\r"), std::string::npos);
  EXPECT_NE(generic.find("\nM30\r"), std::string::npos);
  o.gcodeDialect = GcodeDialect::LinuxCnc;
  const std::string linuxcnc = exportProgram(motion, placed, ExportFormat::Gcode, o).files[0].text;
  EXPECT_NE(linuxcnc.find("\nG4 P60.00\r"), std::string::npos);
  EXPECT_NE(linuxcnc.find("\nM429\r"), std::string::npos);
  EXPECT_NE(linuxcnc.find("\nM2\r"), std::string::npos);
  o.gcodeMode = GcodeMode::Machine;
  const std::string machine = exportProgram(motion, placed, ExportFormat::Gcode, o).files[0].text;
  EXPECT_NE(machine.find("\nG21 G90 G93\r"), std::string::npos);
  EXPECT_EQ(machine.find("M429"), std::string::npos);
  EXPECT_EQ(parseGcodeDialect("linuxcnc"), GcodeDialect::LinuxCnc);
  EXPECT_THROW(parseGcodeDialect("fanuc"), InvalidInput);
}

TEST(StrictReaders, LsWithoutControllerSectionNamesTheFieldAndTheFile) {
  Cell cell = parseCell(writeCellJson(defaultCell()), "foreign.json");
  ASSERT_TRUE(cell.controller.ls.has_value());
  cell.controller.ls.reset();
  const MotionPlan motion = planMotion(makeConePlan(1, 12), cell);
  try {
    exportProgram(motion, placedCell(cell, motion), ExportFormat::Ls);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("foreign.json: /controller/ls is missing"),
              std::string::npos)
        << e.what();
  }
  // the parser names a missing field of the block
  std::string json = writeCellJson(defaultCell());
  const std::size_t at = json.find("\"arc_end_schedule\"");
  ASSERT_NE(at, std::string::npos);
  json.replace(at, 18, "\"arc_end_schedulX\"");
  try {
    parseCell(json, "mine.json");
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("mine.json: field /controller/ls/arc_end_schedule is "
                                         "missing"),
              std::string::npos)
        << e.what();
  }
}

TEST(FileNameRule, TheFileNameAndTheProgramNameAgree) {
  EXPECT_EQ(programNameForFile("out/CYL.JBI", ""), "CYL");
  EXPECT_EQ(programNameForFile("out/CYL.JBI", "CYLINDER_PART"), "CYLINDER_PART");
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeConePlan(1, 12), cell);
  const Cell placed = placedCell(cell, motion);
  ExportOptions o;
  o.programName = "CYLINDER_PART";
  const ExportResult jbi = exportProgram(motion, placed, ExportFormat::Jbi, o);
  EXPECT_EQ(jbi.files[0].name, "CYLINDER.JBI");  // the cell's 8 characters
  try {
    checkMainFileName(jbi, "out/CYL.JBI");
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("name the file CYLINDER.JBI"), std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(checkMainFileName(jbi, "out/CYLINDER.JBI"));
  EXPECT_NO_THROW(checkMainFileName(jbi, "out/cylinder.jbi"));  // controllers ignore case
  for (ExportFormat f : {ExportFormat::Ls, ExportFormat::Gcode}) {
    o.programName = programNameForFile("out/part 2.x", "");
    const ExportResult r = exportProgram(motion, placed, f, o);
    EXPECT_THROW(checkMainFileName(r, "out/part 2.x"), InvalidInput) << toString(f);
    EXPECT_NO_THROW(checkMainFileName(r, "out/PART_2.x")) << toString(f);
  }
  o.programName = "anything";
  EXPECT_NO_THROW(
      checkMainFileName(exportProgram(motion, placed, ExportFormat::Csv, o), "out/plan.csv"));
}

/// `text` with the first `from` replaced by `to` (which must be there).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// True if running `read` reports a failure whose message contains `needle` (the failures are
/// intercepted, not reported).
template <class Read>
bool readerObjects(Read&& read, const std::string& needle) {
  ::testing::TestPartResultArray results;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
    read();
  }
  for (int k = 0; k < results.size(); ++k) {
    if (std::string(results.GetTestPartResult(k).message()).find(needle) != std::string::npos) {
      return true;
    }
  }
  return false;
}

TEST(StrictReaders, CatchBrokenFiles) {
  Cell cell = defaultCell();
  cell.controller.ls->maxLinesPerProgram = 20;
  const MotionPlan motion = planMotion(makeConePlan(2, 12), cell);
  const Cell placed = placedCell(cell, motion);
  const ExportResult ls = exportProgram(motion, placed, ExportFormat::Ls);
  ASSERT_GT(ls.files.size(), 2u);
  ExportResult bad = ls;
  bad.files[0].text = replaced(bad.files[0].text, "CALL WAAM2 ;", "CALL WAAM9 ;");
  EXPECT_TRUE(readerObjects([&] { readLsProgram(bad, placed); }, "called program missing: WAAM9"));
  bad = ls;
  bad.files[1].text = replaced(bad.files[1].text, "LINE_COUNT\t= ", "LINE_COUNT\t= 1");
  EXPECT_TRUE(readerObjects([&] { readLsProgram(bad, placed); }, "LINE_COUNT"));
  bad = ls;
  bad.files[1].text = replaced(bad.files[1].text, "P[2]{", "P[99]{");
  EXPECT_TRUE(readerObjects([&] { readLsProgram(bad, placed); }, "used but not declared"));
  bad = ls;
  bad.files[1].name = "OTHER.LS";
  EXPECT_TRUE(readerObjects([&] { readLsProgram(bad, placed); }, "file and program name disagree"));
  EXPECT_TRUE(readerObjects([&] { readLsProgram(ls, placed, 10); }, "/MN lines over the limit"));
  ExportResult gcode = exportProgram(motion, placed, ExportFormat::Gcode);
  gcode.files[0].text = replaced(gcode.files[0].text, "G4 P60000", "G4 P60.5");
  EXPECT_TRUE(readerObjects([&] { readGcodeProgram(gcode, placed); }, "P in whole ms"));
  gcode = exportProgram(motion, placed, ExportFormat::Gcode);
  gcode.files[0].text = replaced(gcode.files[0].text, "\nM3\r", "\nM7\r");
  EXPECT_TRUE(readerObjects([&] { readGcodeProgram(gcode, placed); }, "unknown G-code line: M7"));
  ExportResult jbi = exportProgram(motion, placed, ExportFormat::Jbi);
  jbi.files[0].text =
      replaced(jbi.files[0].text, "ARCON ASF#(1)\r\n", "ARCON ASF#(1)\r\nWAIT IN#(3)=ON\r\n");
  EXPECT_TRUE(readerObjects([&] { readJbiProgram(jbi, placed); }, "WAIT IN#(3)=ON"));
  ExportResult csv = exportProgram(motion, placed, ExportFormat::Csv);
  csv.files[0].text = replaced(csv.files[0].text, ",path\n", ",weld\n");
  EXPECT_TRUE(readerObjects([&] { readNeutralProgram(csv, placed); }, "weld row"));
}

/// The acceptance models of model_plans.hpp (coarser than the measurement),
/// in every format of this file: strict readers, round trip, files under 4 MB.
/// `insetLinks`: how many connected-inset links the plan has (each joins two rings into one weld).
MotionPlan planAcceptanceModel(const ModelCase& c, const Cell& cell, std::size_t& insetLinks) {
  const PlanJobResult job = planModelCase(c);
  insetLinks = job.planned.stats.insetLinks;
  return planMotion(job.planned.plan, cell);
}

TEST(StrictReaders, CurvedExampleAndCylinderPassInEveryFormat) {
  CURVEDSLICER_SKIP_IF_SANITIZED("StrictReaders.SmallPartPassesInEveryFormat");
  const Cell cell = defaultCell();
  std::size_t links = 0;
  const MotionPlan curved = planAcceptanceModel(curvedExampleCase(), cell, links);
  ASSERT_GT(curved.paths.size() + links, 100u);  // welds plus the rings joined into them
  expectStrictRoundTrip(curved, cell);
  const MotionPlan cylinder = planAcceptanceModel(cylinderCase(), cell, links);
  ASSERT_GT(cylinder.paths.size() + links, 100u);
  expectStrictRoundTrip(cylinder, cell);
}

/// The same on the small part of common/small_part.hpp (the sanitizer build runs this one): a
/// plan of several layers whose rings are joined into open welds.
TEST(StrictReaders, SmallPartPassesInEveryFormat) {
  const Cell cell = defaultCell();
  const PlanJobResult job = planSmallPart();
  const MotionPlan motion = planMotion(job.planned.plan, cell);
  ASSERT_GT(job.planned.plan.layers.size(), 5u);
  ASSERT_GT(job.planned.stats.insetLinks, 0u);
  expectStrictRoundTrip(motion, cell);
}

}  // namespace
}  // namespace curvedslicer

namespace curvedslicer {
namespace {

/// A measurement at full resolution, run by hand: CURVEDSLICER_STRICT_PLAN=plan.json (e.g. the
/// cylinder at h 2, L 1, s 4) exports that plan with the default cell in every format of this
/// file and reads it back strictly (tests/bench/README.md records the result).
TEST(StrictReaders, PlanFileGivenByTheEnvironment) {
  const char* plan = std::getenv("CURVEDSLICER_STRICT_PLAN");
  if (plan == nullptr || *plan == '\0') GTEST_SKIP() << "set CURVEDSLICER_STRICT_PLAN";
  const Cell cell = defaultCell();
  expectStrictRoundTrip(planMotion(readPlanJson(std::filesystem::path(plan)), cell), cell);
}

}  // namespace
}  // namespace curvedslicer
