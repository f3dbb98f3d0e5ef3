// Writing the result of a plan job (pipeline/plan_job.hpp) into an output folder, all or nothing
// (staged as in pipeline/layer_output.hpp): the layer surfaces (layer_0001.ply …), the eq. 13
// voxel sets (voxel_sets.ply), plan.json and plan.csv (plan/plan_io.hpp) and report.json — the
// layer job's report (pipeline/report_json.hpp) plus a "plan" section with the planner's
// statistics, per-layer paths and warnings; for a thin wall (no volume layers) the report holds
// the wall's inputs, the read time and the "plan" section, and no layer or voxel-set file is
// written. Cost: O(output size).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"

namespace curvedslicer {

inline constexpr const char* kVoxelSetsFileName = "voxel_sets.ply";
inline constexpr const char* kReportFileName = "report.json";
inline constexpr const char* kPlanJsonFileName = "plan.json";
inline constexpr const char* kPlanCsvFileName = "plan.csv";

/// What the report needs beyond the job's options and result.
struct PlanOutputInputs {
  std::string modelPath;               ///< as given by the user
  std::size_t modelFileTriangles = 0;  ///< triangles read from the file (before cleaning)
  double tessellationTolerance = 0.0;  ///< mm, CAD models only (0: a mesh file, not reported)
  double readSeconds = 0.0;            ///< wall time of reading the inputs, s (stage "read")
};

/// The "plan" section of report.json: counts, lengths, deposition statistics, the planner's stage
/// times, one entry per layer, and the planner inputs recorded in the plan.
nlohmann::ordered_json makePlanReportSection(const PlanResult& planned);

/// The whole report.json of a plan job. Adds the "read" stage (inputs.readSeconds) and the
/// current peak memory to `result.layers` first (they are reported there).
nlohmann::ordered_json makePlanJobReport(const PlanOutputInputs& inputs,
                                         const PlanJobOptions& options, PlanJobResult& result);

/// Writes every output file into `dir` (see the file comment); nothing appears in `dir` unless
/// all files were written. Stale layer files of an earlier run are removed. Calls
/// makePlanJobReport (so `result.layers` gets the read stage and peak memory).
/// @param progress  "write" stage; its last report is the last chance to cancel
/// @throws IoError for a folder or file that cannot be written; Cancelled.
void writePlanOutput(const std::filesystem::path& dir, const PlanOutputInputs& inputs,
                     const PlanJobOptions& options, PlanJobResult& result,
                     const Progress& progress = {});

}  // namespace curvedslicer
