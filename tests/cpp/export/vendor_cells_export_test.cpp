// Each vendor's own cell: the four cells of resources/cells/ each move the
// curved example and the cylinder (planned coarse, as model_exports_test.cpp plans them) and
// export that vendor's language (yaskawa → JBI, kuka → KRL, abb → RAPID, fanuc → LS) and G-code.
// Every file is read back by the strict readers WITH THAT CELL: one move per motion point, one weld
// per motion path, every position through that cell's forward kinematics within 0.01 mm of the
// plan point, every program within the cell's line limit and every file under 4 MB; KRL and
// RAPID positions also turn the tool as planned, in the vendor's tool-frame convention.
// CURVEDSLICER_VENDOR_PLANS=a.json[,b.json] (run by hand, not in CI) does the same for saved
// plan files at full resolution and prints file counts and sizes (tests/bench/README.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "common/sanitized_build.hpp"
#include "common/small_part.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "export_test_support.hpp"
#include "model_plans.hpp"
#include "program_readers.hpp"
#include "program_readers_krl_rapid.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

constexpr double kRoundTrip = 0.01;              ///< mm, reader → FK → plan point
constexpr std::size_t kMaxFileBytes = 4u << 20;  ///< "no single file over a few MB"

struct VendorCase {
  const char* file;
  ExportFormat language;
};

const VendorCase kVendorCells[] = {
    {"motoman_hp20d_tilt_rotate.json", ExportFormat::Jbi},
    {"kuka_kr16_r1610_2_dkp400.json", ExportFormat::Krl},
    {"abb_irb1660id_irbp_a250.json", ExportFormat::Rapid},
    {"fanuc_arcmate100ic_2axis_positioner.json", ExportFormat::Ls},
};

Cell vendorCell(const char* file) {
  return readCell(std::filesystem::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "cells" / file);
}

/// What one export looked like (for the measurement).
struct ExportSize {
  std::size_t files = 0, largestBytes = 0, totalBytes = 0, maxLines = 0;
  std::string largestName;
};

ExportSize sizeOf(const ExportResult& r) {
  ExportSize s;
  s.files = r.files.size();
  for (const ExportFile& f : r.files) {
    s.totalBytes += f.text.size();
    s.maxLines = std::max(s.maxLines, f.lines);
    if (f.text.size() > s.largestBytes) s.largestBytes = f.text.size(), s.largestName = f.name;
  }
  return s;
}

/// The line limit of `format`'s programs in `cell` (G-code: the exporter's sub-program option).
std::size_t lineLimit(const Cell& cell, ExportFormat format, const ExportOptions& options) {
  switch (format) {
    case ExportFormat::Krl:
      return static_cast<std::size_t>(cell.controller.krl->maxLinesPerFile > 0
                                          ? cell.controller.krl->maxLinesPerFile
                                          : cell.exportOptions.maxLinesPerJob);
    case ExportFormat::Rapid:
      return static_cast<std::size_t>(cell.controller.rapid->maxLinesPerModule > 0
                                          ? cell.controller.rapid->maxLinesPerModule
                                          : cell.exportOptions.maxLinesPerJob);
    case ExportFormat::Ls:
      return static_cast<std::size_t>(cell.controller.ls->maxLinesPerProgram);
    case ExportFormat::Gcode:
      return static_cast<std::size_t>(options.gcodeMaxLinesPerFile);
    default:
      return static_cast<std::size_t>(cell.exportOptions.maxLinesPerJob);
  }
}

/// Moves one per point, welds one per path, every read point within kRoundTrip of the plan.
void expectMovesWeldsAndRoundTrip(const ReadProgram& program, const MotionPlan& motion) {
  ASSERT_EQ(program.moves.size(), motion.points.size());
  ASSERT_EQ(program.welds.size(), motion.paths.size());
  for (std::size_t w = 0; w < motion.paths.size(); ++w) {
    EXPECT_EQ(program.welds[w].first, motion.paths[w].begin);
    EXPECT_EQ(program.welds[w].second, motion.paths[w].end - 1);
  }
  std::size_t far = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const ProgramMove& m = program.moves[i];
    ASSERT_TRUE(m.partPoint.has_value()) << m.line;
    const double d = (*m.partPoint - motion.points[i].position).norm();
    worst = std::max(worst, d);
    if (d > kRoundTrip && far++ < 3) {
      ADD_FAILURE() << "point " << i << " read back " << d << " mm off: " << m.line;
    }
  }
  EXPECT_EQ(far, 0u) << "worst " << worst << " mm";
}

/// Exports `motion` in `format` with the (placed) vendor cell, reads it back strictly with that
/// cell and checks limits, sizes, welds and the round trip; returns the export's sizes.
ExportSize expectVendorExport(const MotionPlan& motion, const Cell& cell, ExportFormat format) {
  SCOPED_TRACE(cell.name + " " + std::string(toString(format)));
  const Cell placed = placedCell(cell, motion);
  const ExportOptions options;
  const ExportResult r = exportProgram(motion, placed, format, options);
  const std::size_t limit = lineLimit(cell, format, options);
  EXPECT_FALSE(r.files.empty());
  for (const ExportFile& f : r.files) {
    EXPECT_LT(f.text.size(), kMaxFileBytes) << f.name;
    if (format == ExportFormat::Jbi) {
      EXPECT_LE(parseJbi(f.text).instructions.size(), limit) << f.name;
    } else if (format == ExportFormat::Gcode) {
      EXPECT_LE(f.lines, limit) << f.name;
    }
  }
  switch (format) {
    case ExportFormat::Jbi:
      expectMovesWeldsAndRoundTrip(readJbiProgram(r, placed), motion);
      break;
    case ExportFormat::Ls:
      expectMovesWeldsAndRoundTrip(readLsProgram(r, placed, limit), motion);
      break;
    case ExportFormat::Gcode:
      expectMovesWeldsAndRoundTrip(readGcodeProgram(r, placed), motion);
      break;
    case ExportFormat::Krl:
    case ExportFormat::Rapid: {  // these readers check every file's lines against the limit
      const ReadExport read =
          format == ExportFormat::Krl ? readKrlExport(r, placed) : readRapidExport(r, placed);
      EXPECT_EQ(read.program.welds.size(), motion.paths.size());
      expectRoundTrip(read, motion, placed, kRoundTrip);
      expectToolOrientation(read, motion, placed, format == ExportFormat::Krl);
      break;
    }
    default:
      ADD_FAILURE() << "not a program language: " << toString(format);
  }
  return sizeOf(r);
}

/// Every vendor cell moves `plan` and exports its own language and G-code; `report` (if set)
/// collects a line per export with file count, largest file and total size.
void expectEveryVendorExports(const Plan& plan, std::ostream* report = nullptr) {
  for (const VendorCase& v : kVendorCells) {
    const Cell cell = vendorCell(v.file);
    const MotionPlan motion = planMotion(plan, cell);
    ASSERT_GT(motion.paths.size(), 0u) << v.file;
    for (ExportFormat format : {v.language, ExportFormat::Gcode}) {
      const ExportSize s = expectVendorExport(motion, cell, format);
      if (report != nullptr) {
        *report << v.file << " " << toString(format) << ": " << motion.points.size() << " points, "
                << s.files << " files, largest " << s.largestName << " " << s.largestBytes
                << " B, total " << s.totalBytes << " B, most lines " << s.maxLines << "\n";
      }
    }
  }
}

TEST(VendorCellsExport, CurvedExampleWithEveryVendorCell) {
  CURVEDSLICER_SKIP_IF_SANITIZED("VendorCellsExport.SmallPartWithEveryVendorCell");
  const Plan plan = planModelCase(curvedExampleCase()).planned.plan;
  ASSERT_GT(plan.layers.size(), 10u);
  expectEveryVendorExports(plan);
}

TEST(VendorCellsExport, CylinderWithEveryVendorCell) {
  CURVEDSLICER_SKIP_IF_SANITIZED("VendorCellsExport.SmallPartWithEveryVendorCell");
  const Plan plan = planModelCase(cylinderCase()).planned.plan;
  ASSERT_GT(plan.layers.size(), 10u);
  expectEveryVendorExports(plan);
}

/// The same on the small part of common/small_part.hpp (the sanitizer build runs this one).
TEST(VendorCellsExport, SmallPartWithEveryVendorCell) {
  const Plan plan = planSmallPart().planned.plan;
  ASSERT_GT(plan.layers.size(), 5u);
  expectEveryVendorExports(plan);
}

/// A measurement at full resolution, run by hand: CURVEDSLICER_VENDOR_PLANS=plan.json[,…].
TEST(VendorCellsExport, PlanFilesGivenByTheEnvironment) {
  const char* plans = std::getenv("CURVEDSLICER_VENDOR_PLANS");
  if (plans == nullptr || *plans == '\0') GTEST_SKIP() << "set CURVEDSLICER_VENDOR_PLANS";
  std::istringstream list(plans);
  for (std::string path; std::getline(list, path, ',');) {
    SCOPED_TRACE(path);
    std::ostringstream report;
    expectEveryVendorExports(readPlanJson(std::filesystem::path(path)), &report);
    std::cout << path << "\n" << report.str();
  }
}

}  // namespace
}  // namespace curvedslicer
