// The `curvedslicer plan` command: a thin translator from the command line to the core's plan job
// (pipeline/plan_job.hpp: the `layers` job followed by path planning, or with --thin-wall path
// planning on a wall surface) and its output folder (pipeline/plan_output.hpp: layer files,
// plan.json, plan.csv and report.json, all or nothing). Exit codes as `layers`
// (layers_command.hpp).
#pragma once

#include <string>

#include "curvedslicer/paths/planner.hpp"
#include "layers_command.hpp"
#include "option_binding.hpp"

namespace curvedslicer::cli {

/// The command's arguments as typed (parsed and checked by `runPlanCommand`).
struct PlanArguments {
  LayersArguments layers;  ///< MODEL, --start, --layer-thickness, --voxel, … and -o, -q
  /// --bead-spacing, --point-spacing, … : one binding per planner option (plan_options.cpp);
  /// options not given keep PlannerOptions{}'s values.
  OptionBindings<PlannerOptions> planner;
  std::string initialCurve = InitialCurve{}.describe();  ///< spec (parseInitialCurveSpec)
  std::string thinWall;  ///< empty: volume layers; else the edge spec (parseThinWallEdge)
};

/// Runs the command; prints progress and errors on stderr, a summary on stdout.
/// @return the exit code.
int runPlanCommand(const PlanArguments& args);

}  // namespace curvedslicer::cli
