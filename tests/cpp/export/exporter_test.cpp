// Tests of export/exporter.hpp: format names, the writer registry and the all-or-nothing file
// writer.
#include "curvedslicer/export/exporter.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "export_test_support.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using namespace testing;

TEST(Exporter, ParsesFormatNamesAndBuildsEachWriter) {
  for (ExportFormat f :
       {ExportFormat::Jbi, ExportFormat::Krl, ExportFormat::Rapid, ExportFormat::Ls,
        ExportFormat::Gcode, ExportFormat::Csv, ExportFormat::Json}) {
    EXPECT_EQ(parseExportFormat(toString(f)), f);
    EXPECT_EQ(makeExporter(f)->format(), f);
    EXPECT_FALSE(fileExtension(f).empty());
  }
  EXPECT_EQ(parseExportFormat("JBI"), ExportFormat::Jbi);
  try {
    parseExportFormat("gcode2");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("jbi, krl, rapid, ls, gcode, csv, json"),
              std::string::npos);
  }
}

TEST(Exporter, ParsesGcodeModeNames) {
  for (GcodeMode m : {GcodeMode::Tcp, GcodeMode::Machine})
    EXPECT_EQ(parseGcodeMode(toString(m)), m);
  EXPECT_EQ(toString(ExportOptions{}.gcodeMode), "tcp");
  try {
    parseGcodeMode("abs");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "unknown G-code mode: 'abs'; use tcp or machine");
  }
}

TEST(Exporter, EveryFormatWritesTheWholePlan) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeConePlan(2, 12), cell);
  for (ExportFormat f :
       {ExportFormat::Jbi, ExportFormat::Krl, ExportFormat::Rapid, ExportFormat::Ls,
        ExportFormat::Gcode, ExportFormat::Csv, ExportFormat::Json}) {
    const ExportResult r = exportProgram(motion, cell, f);
    EXPECT_EQ(r.format, f);
    EXPECT_EQ(r.motionCount, motion.points.size()) << toString(f);
    EXPECT_EQ(r.arcCount, 2u) << toString(f);
    ASSERT_FALSE(r.files.empty());
    EXPECT_GT(r.files[0].lines, motion.points.size());
    EXPECT_GT(r.totalBytes(), 0u);
  }
}

TEST(Exporter, WritesAllFilesOrNone) {
  const fs::path dir = freshTempDir();
  ExportResult result;
  result.files = {{"OUT.JBI", "main\r\n", 1}, {"SUB1.JBI", "sub\r\n", 1}};
  writeExportFiles(result, dir / "out.JBI");
  EXPECT_EQ(readFile((dir / "out.JBI").string()), "main\r\n");
  EXPECT_EQ(readFile((dir / "SUB1.JBI").string()), "sub\r\n");

  // A file that cannot be created: nothing is replaced and no temporary file is left.
  ExportResult bad;
  bad.files = {{"OUT.JBI", "new main\r\n", 1}, {"missing/SUB2.JBI", "x\r\n", 1}};
  EXPECT_THROW(writeExportFiles(bad, dir / "out.JBI"), IoError);
  EXPECT_EQ(readFile((dir / "out.JBI").string()), "main\r\n");
  // A target that is a folder is refused before anything is written.
  fs::create_directories(dir / "SUB3.JBI");
  bad.files[1].name = "SUB3.JBI";
  EXPECT_THROW(writeExportFiles(bad, dir / "out.JBI"), IoError);
  EXPECT_EQ(readFile((dir / "out.JBI").string()), "main\r\n");
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++entries;
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  }
  EXPECT_EQ(entries, 3u);
  // Same name twice, missing folder, nothing to write.
  bad.files[1].name = "out.JBI";
  EXPECT_THROW(writeExportFiles(bad, dir / "out.JBI"), InvalidInput);
  EXPECT_THROW(writeExportFiles(result, dir / "nope" / "out.JBI"), IoError);
  EXPECT_THROW(writeExportFiles(ExportResult{}, dir / "x.JBI"), InvalidInput);
  // The file-name rule: the main file must carry the program's name (letter case aside).
  EXPECT_THROW(writeExportFiles(result, dir / "other.JBI"), InvalidInput);
  EXPECT_FALSE(fs::exists(dir / "other.JBI"));
}

TEST(Exporter, DateThatIsNotYyyyMmDdHhMmIsRefusedBeforeWriting) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeConePlan(1, 8), cell);
  ExportOptions options;
  options.date = "2026/11/22 07:00\r\nMOVJ VJ=100.00";  // would inject a line into the JBI header
  try {
    exportProgram(motion, cell, ExportFormat::Jbi, options);
    ADD_FAILURE() << "a date with a line break was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()),
              "date must look like \"YYYY/MM/DD HH:MM\": '2026/11/22 07:00\\r\\nMOVJ VJ=100.00'; "
              "e.g. \"2026/11/22 07:00\"");
  }
  for (const char* bad : {"2026", "2026/11/22 7:00", "2026-11-22 07:00", "", "2026/11/22 07:0x"}) {
    options.date = bad;
    EXPECT_THROW(validateExportOptions(options), InvalidInput) << bad;
  }
  options.date = std::string(100000, '9');
  try {
    validateExportOptions(options);
    ADD_FAILURE() << "a long date was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_LT(std::string(e.what()).size(), 120u);
  }
  options.date = "2026/11/22 07:00";
  EXPECT_NO_THROW(validateExportOptions(options));
  EXPECT_NE(exportProgram(motion, cell, ExportFormat::Jbi, options)
                .files[0]
                .text.find("///DATE 2026/11/22 07:00\r\n"),
            std::string::npos);
  EXPECT_NO_THROW(validateExportOptions(ExportOptions{}));
}

TEST(Exporter, ExportBeyondTheMemoryBudgetIsRefusedBeforePlanningTheMotion) {
  const double perPoint = static_cast<double>(sizeof(MotionPoint)) + kExportTextBytesPerPoint;
  EXPECT_NO_THROW(checkExportSize(1000, 1000 * perPoint));
  try {
    checkExportSize(1001, 1000 * perPoint);
    ADD_FAILURE() << "an export over the budget was accepted";
  } catch (const ResourceLimit& e) {
    EXPECT_NE(std::string(e.what()).find("the export of 1001 plan points would need about"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(checkExportSize(std::size_t{1} << 50), ResourceLimit);  // automatic budget
  EXPECT_NO_THROW(checkExportSize(100000));
}

TEST(Exporter, EmptyOutputPathIsRefusedWithItsOwnMessage) {
  const fs::path dir = freshTempDir();
  ExportResult result;
  result.files = {{"MAIN.JBI", "main\r\n", 1}};
  try {
    writeExportFiles(result, fs::path());
    ADD_FAILURE() << "an empty path was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()),
              "output path is empty: ''; pass a file path such as 'PART.JBI'");
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace curvedslicer
