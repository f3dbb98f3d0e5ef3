// The `curvedslicer layers` command: read a model, run the layer job, write the layer surfaces,
// the eq. 13 voxel sets and report.json into an output folder (all or nothing, see
// pipeline/layer_output.hpp).
#pragma once

#include <string>

#include "curvedslicer/pipeline/layer_pipeline.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"

namespace CLI {
class App;
}

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
/// every message has the core's "<what>: <value>; <what to do>" form). Empty texts mean the
/// default of LayerJobOptions{}.
struct LayersArguments {
  std::string model;
  std::string start = "plane:bottom";  ///< the spec recorded as given (StartSurface{} default)
  std::string layerThickness;
  std::string voxelSize;
  std::string method;
  std::string grid;
  std::string format;
  std::string memoryBudgetMb;
  std::string tessellationTolerance;  ///< CAD models only; empty: voxel/4
  std::string layerTolerance;         ///< layer simplification ε, mm; empty: 0.05 × voxel
  bool simplifyLayers = false;        ///< layer simplification with the default ε (the default)
  bool fullResolutionLayers = false;  ///< no layer simplification
  bool capHoles = false;
  bool quiet = false;
  std::string output;
};

/// The layer job as the arguments describe it (files not read yet).
struct LayerJobArguments {
  LayerJobOptions options;  ///< start surface left at the default until loadStartSurface(start)
  StartSurfaceSpec start;
  LayerFileFormat format = LayerFileFormat::Ply;
  double tessellationTolerance = 0.0;  ///< mm; 0: automatic (model_input.hpp)
};

/// Parses every layer-job argument (not validated: validateLayerJobOptions). Texts left empty
/// keep LayerJobOptions{}'s values.
/// @throws InvalidInput naming the argument and its value.
LayerJobArguments parseLayerJobArguments(const LayersArguments& args);

/// Adds --tessellation-tolerance (bound to `args.tessellationTolerance`) to `command`
/// (layers_options.cpp; used by `layers` and `plan`).
void addTessellationOption(CLI::App& command, LayersArguments& args);

/// Adds --simplify-layers, --layer-tolerance and --full-resolution-layers (bound to `args`) to
/// `command`
/// (layers_options.cpp; used by `layers` and `plan`).
void addLayerSimplificationOptions(CLI::App& command, LayersArguments& args);

/// Runs the command; prints progress and errors on stderr, a summary on stdout.
/// @return the exit code.
int runLayersCommand(const LayersArguments& args);

}  // namespace curvedslicer::cli
