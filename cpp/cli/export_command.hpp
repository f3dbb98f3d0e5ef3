// The `curvedslicer export` command: read a plan (plan.json) and a cell description, plan the
// positioner angles and robot joints (robot/motion.hpp) and write a robot program or a neutral
// per-point file (export/exporter.hpp), all or nothing.
#pragma once

#include <string>

#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "option_binding.hpp"

namespace curvedslicer::cli {

/// The command's arguments as typed (checked by `runExportCommand`).
struct ExportArguments {
  std::string plan;
  std::string cell;  ///< empty = the default cell (Motoman HP20D + tilt-rotate positioner)
  std::string format;
  std::string output;
  std::string name;          ///< program / job name; empty = the output file's stem
  std::string gcodeMode;     ///< empty = ExportOptions{}.gcodeMode
  std::string gcodeDialect;  ///< empty = ExportOptions{}.gcodeDialect
  int gcodeLinesPerFile = ExportOptions{}.gcodeMaxLinesPerFile;
  std::string date;  ///< empty = the fixed default (reproducible files)
  bool warnUnreachable = false;
  bool allowForeignCell = false;  ///< write one vendor's language with another vendor's cell
  bool quiet = false;
  /// --clearance, --allow-collisions, --no-home, --merge-tolerance, --max-a2-step, --placement:
  /// one binding per motion option (export_options.cpp); options not given keep
  /// MotionOptions{}'s values.
  OptionBindings<MotionOptions> motion;
};

/// Runs the command; progress and errors on stderr, a summary on stdout. @return the exit code.
int runExportCommand(const ExportArguments& args);

}  // namespace curvedslicer::cli
