// The `curvedslicer plan` command: the `layers` job followed by path planning (paths/planner.hpp)
// — or, with --thin-wall, path planning on a wall surface without volume layers — writing the
// layer files, plan.json, plan.csv and report.json into an output folder, all or nothing (see
// pipeline/layer_output.hpp). Exit codes as `layers` (layers_command.hpp).
#pragma once

#include <string>

#include "layers_command.hpp"

namespace curvedslicer::cli {

/// The command's arguments as typed (parsed and checked by `runPlanCommand`).
struct PlanArguments {
  LayersArguments layers;  ///< MODEL, --start, --layer-thickness, --voxel, … and -o, -q
  std::string beadSpacing;
  std::string pointSpacing = "2";
  std::string fitTolerance = "0.05";
  std::string cornerAngle = "30";
  std::string initialCurve = "boundary";
  std::string surfaceMethod = "accurate";
  std::string narrowStrips = "centre_bead";
  std::string thinWall;  ///< empty: volume layers; else the edge spec (lowest[:AXIS]|nearest:P)
};

/// Runs the command; prints progress and errors on stderr, a summary on stdout.
/// @return the exit code.
int runPlanCommand(const PlanArguments& args);

}  // namespace curvedslicer::cli
