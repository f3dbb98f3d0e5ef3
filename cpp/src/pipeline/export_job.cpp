// The export job (pipeline/export_job.hpp): checks, motion, program, files.
#include "curvedslicer/pipeline/export_job.hpp"

#include "curvedslicer/robot/placement.hpp"

namespace curvedslicer {

ExportJobResult runExportJob(const Plan& plan, const Cell& cell, const ExportJobOptions& options,
                             const std::optional<std::filesystem::path>& output,
                             const Progress& progress) {
  // the cheap refusals first: a program too large for memory, another vendor's language
  checkExportSize(plan.pointCount());
  checkCellVendor(cell, toString(options.format), options.allowForeignCell);
  ExportJobResult result;
  result.motion = planMotion(plan, cell, options.motion, progress.sub(0.0, 0.7));
  // the program is written for the cell with the part where the motion placed it
  result.program = exportProgram(result.motion, withPartPlacement(cell, result.motion.tableToPart),
                                 options.format, options.program, progress.sub(0.7, 0.95));
  if (output) {
    progress.report(0.97, "write");
    writeExportFiles(result.program, *output);
  }
  progress.report(1.0, "export");
  return result;
}

}  // namespace curvedslicer
