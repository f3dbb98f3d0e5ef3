// The export job (pipeline/export_job.hpp) and the table of program formats: the job gives the
// motion planMotion plans and the program exportProgram writes for the placed part, writes the
// files only when asked and only when every step succeeded; every format's name, extension and
// parse agree with the table.
#include "curvedslicer/pipeline/export_job.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>

#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/placement.hpp"
#include "export/export_test_support.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::makeSmallPlan;
using testing::readFile;

TEST(ExportJob, GivesThePlannedMotionAndItsProgramAndWritesOnlyWhenAsked) {
  const Plan plan = makeSmallPlan();
  const Cell cell = defaultCell();
  ExportJobOptions options;
  options.format = ExportFormat::Csv;
  const ExportJobResult inMemory = runExportJob(plan, cell, options);
  // the same as the chain by hand: planMotion, then the writer for the cell with the part placed
  const MotionPlan motion = planMotion(plan, cell, options.motion);
  ASSERT_EQ(inMemory.motion.points.size(), motion.points.size());
  EXPECT_TRUE(inMemory.motion.tableToPart.isApprox(motion.tableToPart));
  const ExportResult program = exportProgram(motion, withPartPlacement(cell, motion.tableToPart),
                                             ExportFormat::Csv, options.program);
  ASSERT_EQ(inMemory.program.files.size(), program.files.size());
  EXPECT_EQ(inMemory.program.files.front().text, program.files.front().text);
  // with an output file: the same text on disk
  const fs::path dir = freshTempDir("export_job");
  const ExportJobResult written = runExportJob(plan, cell, options, dir / "OUT.csv");
  EXPECT_EQ(readFile((dir / "OUT.csv").string()), written.program.files.front().text);
}

TEST(ExportJob, ARefusedJobWritesNothing) {
  const Plan plan = makeSmallPlan();
  const fs::path dir = freshTempDir("export_job_refused");
  ExportJobOptions options;
  options.format = ExportFormat::Krl;  // KUKA's language for the Yaskawa default cell
  EXPECT_THROW(runExportJob(plan, defaultCell(), options, dir / "P.src"), InvalidInput);
  EXPECT_FALSE(fs::exists(dir / "P.src"));
  options.allowForeignCell = true;  // then the cell's missing KRL settings stop it, still unwritten
  EXPECT_THROW(runExportJob(plan, defaultCell(), options, dir / "P.src"), InvalidInput);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(ExportFormats, NamesExtensionsAndParsingComeFromOneTable) {
  std::set<std::string> names, extensions;
  for (const ExportFormatInfo& f : exportFormats()) {
    EXPECT_EQ(toString(f.format), f.name);
    EXPECT_EQ(fileExtension(f.format), f.extension);
    EXPECT_EQ(parseExportFormat(f.name), f.format);
    EXPECT_FALSE(f.description.empty());
    names.insert(std::string(f.name));
    extensions.insert(std::string(f.extension));
  }
  EXPECT_EQ(names.size(), 7u);
  EXPECT_EQ(extensions.size(), 7u);
  try {
    parseExportFormat("step");
    ADD_FAILURE() << "no error for an unknown format";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("use one of jbi, krl, rapid, ls, gcode, csv, json"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace curvedslicer
