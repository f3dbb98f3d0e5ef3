#include "export_command.hpp"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>

#include "command_errors.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "layers_command.hpp"  // ExitCode
#include "terminal_progress.hpp"

namespace curvedslicer::cli {

namespace fs = std::filesystem;

namespace {

ExportOptions parseExportOptions(const ExportArguments& args) {
  ExportOptions options;
  options.programName = args.name;
  if (!args.date.empty()) options.date = args.date;
  if (!args.gcodeMode.empty()) options.gcodeMode = parseGcodeMode(args.gcodeMode);
  validateExportOptions(options);  // the core's checks, shared with the workbench API
  return options;
}

}  // namespace

int runExportCommand(const ExportArguments& args) {
  installInterruptHandlers();
  TerminalProgress display(!args.quiet);
  try {
    const ExportFormat format = parseExportFormat(args.format);
    const ExportOptions options = parseExportOptions(args);
    const fs::path output(args.output);
    const fs::path folder = output.has_parent_path() ? output.parent_path() : fs::path(".");
    if (!fs::is_directory(folder)) {
      throw IoError("output folder does not exist: '" + folder.string() +
                    "'; create it or choose another output file");
    }
    const Progress progress([&display](double fraction, std::string_view stage) {
      return display.update(fraction, stage);
    });

    // ---- read ----------------------------------------------------------------------------------
    progress.report(0.0, "read");
    const Plan plan = readPlanJson(fs::path(args.plan));
    checkExportSize(plan.pointCount());
    const Cell cell = args.cell.empty() ? defaultCell() : readCell(fs::path(args.cell));

    // ---- motion --------------------------------------------------------------------------------
    MotionOptions motionOptions;
    if (args.warnUnreachable) motionOptions.unreachable = UnreachablePolicy::Warn;
    const MotionPlan motion = planMotion(plan, cell, motionOptions, progress.sub(0.05, 0.7));

    // ---- export --------------------------------------------------------------------------------
    const ExportResult result =
        exportProgram(motion, cell, format, options, progress.sub(0.7, 0.95));

    // ---- write ---------------------------------------------------------------------------------
    progress.report(0.97, "write");  // last chance to cancel: nothing is in place yet
    writeExportFiles(result, output);
    display.finishLine();
    if (!args.quiet) {
      for (const std::string& w : motion.warnings) {
        std::fprintf(stderr, "curvedslicer: warning: %s\n", w.c_str());
      }
      for (const std::string& w : result.warnings) {
        std::fprintf(stderr, "curvedslicer: note: %s\n", w.c_str());
      }
      std::printf(
          "curvedslicer: wrote %s (%zu file%s, %zu bytes): %zu motions, %zu paths; arc time "
          "%.0f s, total time %.0f s, wire %.2f m, deposit %.1f g\n",
          output.string().c_str(), result.files.size(), result.files.size() == 1 ? "" : "s",
          result.totalBytes(), result.motionCount, result.arcCount, motion.total.arcTime,
          motion.total.totalTime, motion.total.wireLength / 1000.0, motion.total.depositedMass);
    }
    return kExitOk;
  } catch (...) {
    return failWithCurrentException(display, args.output,
                                    "out of memory while exporting; free memory");
  }
}

}  // namespace curvedslicer::cli
