// The export job: from a plan and a cell to a robot program in one call — the checks (program
// size, the cell's vendor against the format), the motion (robot/motion.hpp planMotion: part
// placement, positioner angles, torch angles, inverse kinematics, travel, collisions, timing),
// the program text in the cell with the part placed (export/exporter.hpp) and, given an output
// file, the files written all or nothing (writeExportFiles). The one place where this chain is
// assembled: the command line and the Python module translate their inputs into
// ExportJobOptions and call it, as they call runPlanJob (plan_job.hpp) for a plan.
//
// Stages (progress stage names, share of the overall progress):
//   the motion's stages (0–0.7), export (0.7–0.95), write (0.97; the last chance to cancel:
//   nothing is in place yet).
// Errors: ResourceLimit from checkExportSize, InvalidInput from checkCellVendor, planMotion and
// the writer, IoError from writing, Cancelled; nothing is written unless every step succeeded.
#pragma once

#include <filesystem>
#include <optional>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/plan/plan.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"

namespace curvedslicer {

struct ExportJobOptions {
  ExportFormat format = ExportFormat::Jbi;
  ExportOptions program;          ///< the writer's options (program name, date, G-code mode, …)
  MotionOptions motion;           ///< the motion planner's options (placement, clearance, …)
  bool allowForeignCell = false;  ///< write one vendor's language for another vendor's cell
};

struct ExportJobResult {
  MotionPlan motion;     ///< as planned: placement, fixture, warnings, notes, estimates
  ExportResult program;  ///< the files' names and text
};

/// Runs the export job (see the file comment); writes the files to `output` (the main file;
/// further files, e.g. JBI sub-jobs, beside it) when given.
ExportJobResult runExportJob(const Plan& plan, const Cell& cell, const ExportJobOptions& options,
                             const std::optional<std::filesystem::path>& output = std::nullopt,
                             const Progress& progress = {});

}  // namespace curvedslicer
