#include "export_command.hpp"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <system_error>
#include <utility>

#include "command_errors.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/pipeline/export_job.hpp"
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
  // The file-name rule (exporter.hpp): the program is named after the output file unless --name.
  options.programName = programNameForFile(fs::path(args.output), args.name);
  if (!args.date.empty()) options.date = args.date;
  if (!args.gcodeMode.empty()) options.gcodeMode = parseGcodeMode(args.gcodeMode);
  if (!args.gcodeDialect.empty()) options.gcodeDialect = parseGcodeDialect(args.gcodeDialect);
  options.gcodeMaxLinesPerFile = args.gcodeLinesPerFile;
  validateExportOptions(options);  // the core's checks, shared with the workbench API
  return options;
}

/// Speed reductions and collisions are listed up to this many; then a count of the rest.
constexpr std::size_t kListedAtMost = 10;

void printPlacement(const MotionPlan& motion, PartPlacement placement) {
  const Vec3 t = motion.tableToPart.translation();
  const Vec3 rpy = rollPitchYaw(motion.tableToPart.rotation()) * (180.0 / 3.14159265358979323846);
  std::printf(
      "curvedslicer: part on the table (placement %s): table_to_part xyz %.3f, %.3f, %.3f mm, "
      "rpy %.3f, %.3f, %.3f deg\n",
      std::string(toString(placement)).c_str(), t.x(), t.y(), t.z(), rpy.x() + 0.0, rpy.y() + 0.0,
      rpy.z() + 0.0);
  const FixtureGeometry& f = motion.fixture;
  if (f.hasRiser() || f.hasSubstrate()) {
    std::printf(
        "curvedslicer: fixture: riser %.1f mm high, %.1f mm across; substrate plate %.1f mm "
        "thick, %.1f mm square; the part rests %.1f mm above the table\n",
        f.riserHeight, f.riserDiameter, f.substrateThickness, f.substrateSize, f.top());
  }
}

/// Collisions left, the largest torch angle off gravity and gravity deviation of the deposit,
/// and the layer where each is largest.
void printClearance(const MotionPlan& motion) {
  constexpr double kToDeg = 180.0 / 3.14159265358979323846;
  std::size_t torchLayer = 0, gravityLayer = 0;
  for (std::size_t l = 0; l < motion.layers.size(); ++l) {
    if (motion.layers[l].maxTorchAngle > motion.layers[torchLayer].maxTorchAngle) torchLayer = l;
    if (motion.layers[l].maxGravityDeviation > motion.layers[gravityLayer].maxGravityDeviation) {
      gravityLayer = l;
    }
  }
  std::printf(
      "curvedslicer: collisions: %zu; largest torch angle off gravity %.1f deg (layer %zu), "
      "largest gravity deviation of the deposit %.1f deg (layer %zu)\n",
      motion.collisions.size(), motion.total.maxTorchAngle * kToDeg, torchLayer,
      motion.total.maxGravityDeviation * kToDeg, gravityLayer);
}

void printSpeedReductions(const MotionPlan& motion) {
  if (motion.speedReductions.empty()) return;
  std::printf("curvedslicer: weld speed reduced in %zu stretch%s (axis speed limits):\n",
              motion.speedReductions.size(), motion.speedReductions.size() == 1 ? "" : "es");
  for (std::size_t k = 0; k < motion.speedReductions.size() && k < kListedAtMost; ++k) {
    const SpeedReduction& r = motion.speedReductions[k];
    std::printf("  layer %d path %d points %d-%d: down to %.2f mm/s, limited by %s\n", r.layer,
                r.path, r.firstIndex, r.lastIndex, r.minSpeed, r.axis.c_str());
  }
  if (motion.speedReductions.size() > kListedAtMost) {
    std::printf("  ... and %zu more\n", motion.speedReductions.size() - kListedAtMost);
  }
}

void printCollisions(const MotionPlan& motion) {
  for (std::size_t k = 0; k < motion.collisions.size() && k < kListedAtMost; ++k) {
    const CollisionReport& c = motion.collisions[k];
    if (c.point >= motion.points.size()) continue;
    const MotionPoint& p = motion.points[c.point];
    std::fprintf(stderr,
                 "curvedslicer: warning: collision (--allow-collisions): %s move to motion point "
                 "%zu (layer %d path %d): %s, %.2f mm deep\n",
                 std::string(toString(p.kind)).c_str(), c.point, p.layer, p.path, c.what.c_str(),
                 c.depth);
  }
  if (motion.collisions.size() > kListedAtMost) {
    std::fprintf(stderr, "curvedslicer: warning: ... and %zu more collisions\n",
                 motion.collisions.size() - kListedAtMost);
  }
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
    // the program never replaces one of its inputs (same file, by any name or link)
    for (const auto& [input, what] : {std::pair{args.plan, "plan"}, std::pair{args.cell, "cell"}}) {
      std::error_code ec;
      if (!input.empty() && fs::equivalent(output, fs::path(input), ec)) {
        throw InvalidInput("the output '" + output.string() + "' is the " + what +
                           " file being read ('" + input + "'); choose another output file");
      }
    }
    const Progress progress([&display](double fraction, std::string_view stage) {
      return display.update(fraction, stage);
    });

    // ---- read ----------------------------------------------------------------------------------
    progress.report(0.0, "read");
    const Plan plan = readPlanJson(fs::path(args.plan));
    const Cell cell = args.cell.empty() ? defaultCell() : readCell(fs::path(args.cell));

    // ---- motion, program, files (pipeline/export_job.hpp) -----------------------------------
    ExportJobOptions job;
    job.format = format;
    job.program = options;
    job.allowForeignCell = args.allowForeignCell;
    if (args.warnUnreachable) job.motion.unreachable = UnreachablePolicy::Warn;
    args.motion.applyTo(job.motion);
    const MotionOptions& motionOptions = job.motion;
    const ExportJobResult done = runExportJob(plan, cell, job, output, progress.sub(0.05, 1.0));
    const MotionPlan& motion = done.motion;
    const ExportResult& result = done.program;
    display.finishLine();
    if (!args.quiet) {
      for (const std::string& w : motion.warnings) {
        std::fprintf(stderr, "curvedslicer: warning: %s\n", w.c_str());
      }
      printCollisions(motion);
      for (const std::string& w : result.warnings) {
        std::fprintf(stderr, "curvedslicer: note: %s\n", w.c_str());
      }
      for (const std::string& n : motion.notes) {
        std::fprintf(stderr, "curvedslicer: note: %s\n", n.c_str());
      }
      printPlacement(motion, motionOptions.placement);
      printSpeedReductions(motion);
      printClearance(motion);
      std::printf(
          "curvedslicer: wrote %s (%zu file%s, %zu bytes): %zu motions, %zu paths; arc time "
          "%.0f s, dwell %.0f s, total time %.0f s, wire %.2f m, deposit %.1f g\n",
          output.string().c_str(), result.files.size(), result.files.size() == 1 ? "" : "s",
          result.totalBytes(), result.motionCount, result.arcCount, motion.total.arcTime,
          motion.total.dwellTime, motion.total.totalTime, motion.total.wireLength / 1000.0,
          motion.total.depositedMass);
      std::printf("curvedslicer: minimum layer time %.0f s: %zu layer(s) wait %.0f s in all\n",
                  cell.process.minLayerTime, motion.total.cooledLayers, motion.total.coolingWait);
    }
    return kExitOk;
  } catch (...) {
    return failWithCurrentException(display, args.output,
                                    "out of memory while exporting; free memory");
  }
}

}  // namespace curvedslicer::cli
