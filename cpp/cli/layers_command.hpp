// The `curvedslicer layers` command: read a model, run the layer job, write the layer surfaces,
// the eq. 13 voxel sets and report.json into an output folder (all or nothing, see
// pipeline/layer_output.hpp).
#pragma once

#include <string>

namespace curvedslicer::cli {

/// Exit codes of the command line.
enum ExitCode : int {
  kExitOk = 0,
  kExitOther = 1,
  kExitInvalidInput = 2,  ///< also command-line usage errors
  kExitIo = 3,
  kExitResourceLimit = 4,
  kExitNumericalFailure = 5,
  kExitInterruptedBase = 128,  ///< + signal number (SIGINT: 130)
};

/// The command's arguments as typed (numbers are parsed and checked by `runLayersCommand`, so
/// every message has the core's "<what>: <value>; <what to do>" form).
struct LayersArguments {
  std::string model;
  std::string start = "plane:bottom";
  std::string layerThickness;
  std::string voxelSize;
  std::string method = "anyangle";
  std::string grid = "pca";
  std::string format = "ply";
  std::string memoryBudgetMb = "0";
  bool capHoles = false;
  bool quiet = false;
  std::string output;
};

/// Runs the command; prints progress and errors on stderr, a summary on stdout.
/// @return the exit code.
int runLayersCommand(const LayersArguments& args);

}  // namespace curvedslicer::cli
