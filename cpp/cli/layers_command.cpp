#include "layers_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>
#include <vector>

#include "command_errors.hpp"
#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/pipeline/layer_output.hpp"
#include "curvedslicer/pipeline/layer_pipeline.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/report_json.hpp"
#include "model_input.hpp"
#include "terminal_progress.hpp"

namespace curvedslicer::cli {

namespace fs = std::filesystem;

namespace {

/// --simplify-layers, --layer-tolerance and --full-resolution-layers into the layer options
/// (none given: LayerSimplificationOptions{}, simplified within 0.05 × voxel).
void parseLayerSimplification(const LayersArguments& args, LayerSimplificationOptions& options) {
  if (args.fullResolutionLayers && !args.layerTolerance.empty()) {
    throw InvalidInput("--layer-tolerance does not apply with --full-resolution-layers: '" +
                       args.layerTolerance + "'; pass one of the two");
  }
  if (args.fullResolutionLayers && args.simplifyLayers) {
    throw InvalidInput(
        "--simplify-layers does not apply with --full-resolution-layers: both given; pass one of "
        "the two");
  }
  if (args.fullResolutionLayers) options.enabled = false;
  if (args.simplifyLayers) options.enabled = true;
  if (args.layerTolerance.empty()) return;
  options.enabled = true;
  const double tolerance = parseLength(args.layerTolerance, "layer tolerance");
  if (!std::isfinite(tolerance) || tolerance <= 0.0) {
    throw InvalidInput(
        "--layer-tolerance must be a positive number of mm: '" + args.layerTolerance +
        "'; pass e.g. --layer-tolerance 0.025, or --simplify-layers for 0.05 × voxel");
  }
  options.tolerance = tolerance;
}

}  // namespace

LayerJobArguments parseLayerJobArguments(const LayersArguments& args) {
  LayerJobArguments job;
  LayerJobOptions& o = job.options;
  o.layers.layerThickness = parseLength(args.layerThickness, "layer thickness");
  o.voxelize.voxelSize = parseLength(args.voxelSize, "voxel size");
  if (!args.method.empty()) o.geodesic.method = parseGeodesicMethod(args.method);
  if (!args.grid.empty()) o.voxelize.alignment = parseGridAlignment(args.grid);
  if (!args.format.empty()) job.format = parseLayerFileFormat(args.format);
  job.start = parseStartSurfaceSpec(args.start);
  if (!args.memoryBudgetMb.empty()) {
    const double budgetMb = parseLength(args.memoryBudgetMb, "memory budget");
    if (!std::isfinite(budgetMb) || budgetMb < 0.0 || (budgetMb > 0.0 && budgetMb < 1.0)) {
      throw InvalidInput("memory budget must be 0 (automatic) or at least 1 MB: '" +
                         args.memoryBudgetMb.substr(0, 40) + "'; pass e.g. --memory-budget 4096");
    }
    o.voxelize.memoryBudgetBytes = budgetMb * 1024.0 * 1024.0;
  }
  o.capHoles = args.capHoles;
  parseLayerSimplification(args, o.layers.simplification);
  job.tessellationTolerance = parseTessellationTolerance(args.tessellationTolerance);
  return job;
}

namespace {

constexpr const char* kVoxelSetsFile = "voxel_sets.ply";
constexpr const char* kReportFile = "report.json";

void printUnreachedWarning(const GeodesicResult& field) {
  const UnreachedVoxels& u = field.unreached;
  if (u.count == 0) return;
  std::fprintf(stderr,
               "curvedslicer: warning: %zu inside voxels (%zu separate region%s) cannot be "
               "reached from the start surface and belong to no layer, e.g. near (%.3g, %.3g, "
               "%.3g) mm; see report.json field.unreached\n",
               u.count, u.components, u.components == 1 ? "" : "s", u.example.x(), u.example.y(),
               u.example.z());
}

/// Writes each layer surface into the staging folder as soon as the extraction finishes it, and
/// the eq. 13 voxel sets into voxel_sets.ply as they arrive, so that no more than one batch of
/// layers is ever held in memory.
class StagingLayerSink final : public LayerSink {
 public:
  StagingLayerSink(OutputStaging& staging, LayerFileFormat format)
      : staging_(staging), format_(format) {}

  void begin(int layerCount, const std::vector<std::size_t>& voxelSetSizes,
             const GridGeometry& geometry) override {
    const auto start = Clock::now();
    count_ = static_cast<std::size_t>(layerCount);
    geometry_ = geometry;
    std::size_t points = 0;
    for (std::size_t size : voxelSetSizes) points += size;
    voxelSetsPath_ = staging_.reserve(kVoxelSetsFile);
    voxelSets_.open(voxelSetsPath_, std::ios::binary | std::ios::trunc);
    writeVoxelSetsPlyHeader(voxelSets_, points);
    checkVoxelSets();
    seconds_ += secondsSince(start);
  }

  void acceptSurface(LayerSurface&& surface) override {
    const auto start = Clock::now();
    const std::string name = layerFileName(surface.index, count_, format_);
    const MeshFormat meshFormat =
        format_ == LayerFileFormat::Ply ? MeshFormat::Ply : MeshFormat::Obj;
    staging_.stage(name, [&](const fs::path& path) { writeMesh(path, surface.mesh, meshFormat); });
    names_.push_back(name);
    surface.mesh = TriMesh{};
    seconds_ += secondsSince(start);
  }

  void acceptVoxelSet(VoxelLayerSet&& set, const std::vector<float>& distance) override {
    const auto start = Clock::now();
    appendVoxelSetPly(voxelSets_, set, geometry_, distance);
    checkVoxelSets();
    seconds_ += secondsSince(start);
  }

  /// Completes voxel_sets.ply. @throws IoError if it could not be written.
  void finish() {
    const auto start = Clock::now();
    if (voxelSets_.is_open()) {
      voxelSets_.close();
      if (voxelSets_.fail()) fail();
    }
    seconds_ += secondsSince(start);
  }

  const std::vector<std::string>& layerFiles() const { return names_; }
  /// Wall time spent writing so far, s.
  double seconds() const { return seconds_; }

 private:
  using Clock = std::chrono::steady_clock;
  static double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
  }
  void checkVoxelSets() {
    if (!voxelSets_) fail();
  }
  [[noreturn]] void fail() const {
    throw IoError("cannot write '" + voxelSetsPath_.string() +
                  "'; check the free space and permissions of the output folder");
  }

  OutputStaging& staging_;
  LayerFileFormat format_;
  std::size_t count_ = 0;
  GridGeometry geometry_;
  fs::path voxelSetsPath_;
  std::ofstream voxelSets_;
  std::vector<std::string> names_;
  double seconds_ = 0.0;
};

/// Completes the timings (the layer stage's time includes the sink's writing, reported as
/// "write") and stages report.json.
void stageReport(OutputStaging& staging, const StagingLayerSink& sink, const LayersArguments& args,
                 const LayerJobArguments& job, const ModelInput& model, LayerJobResult& result,
                 const Progress& writeProgress) {
  using Clock = std::chrono::steady_clock;
  const auto writeBegin = Clock::now();
  for (StageTime& st : result.stageTimes) {
    if (st.name == "layers") st.seconds = std::max(0.0, st.seconds - sink.seconds());
  }
  writeProgress.report(0.0, "write");
  LayerReportInputs reportInputs;
  reportInputs.modelPath = args.model;
  reportInputs.modelFileTriangles = model.mesh.triangleCount();
  reportInputs.tessellationTolerance = model.tessellationTolerance;
  reportInputs.startSpec = args.start;
  reportInputs.layerFormat = job.format;
  reportInputs.layerFiles = sink.layerFiles();
  reportInputs.voxelSetsFile = kVoxelSetsFile;
  result.peakMemoryBytes = peakResidentMemoryBytes();
  const double writeSeconds =
      sink.seconds() + std::chrono::duration<double>(Clock::now() - writeBegin).count();
  result.stageTimes.push_back(StageTime{"write", writeSeconds, result.peakMemoryBytes});
  const std::string report = formatLayerReport(makeLayerReport(reportInputs, job.options, result));
  staging.stage(kReportFile, [&](const fs::path& path) { writeTextFileAtomically(path, report); });
}

}  // namespace

int runLayersCommand(const LayersArguments& args) {
  installInterruptHandlers();
  TerminalProgress display(!args.quiet);
  const fs::path outputDir(args.output);
  try {
    using Clock = std::chrono::steady_clock;
    LayerJobArguments job = parseLayerJobArguments(args);
    validateLayerJobOptions(job.options);
    checkOutputFolder(outputDir);

    const Progress progress([&display](double fraction, std::string_view stage) {
      return display.update(fraction, stage);
    });

    // ---- read ----------------------------------------------------------------------------------
    progress.report(0.0, "read");
    const auto readBegin = Clock::now();
    const ModelInput input =
        readModel(fs::path(args.model), job.tessellationTolerance, job.options.voxelize.voxelSize);
    const TriMesh& model = input.mesh;
    job.options.start = loadStartSurface(job.start);
    const double readSeconds = std::chrono::duration<double>(Clock::now() - readBegin).count();
    const std::size_t readPeak = peakResidentMemoryBytes();

    // Layers go straight into the staging folder while they are extracted (nothing appears in
    // the output folder before the final commit).
    OutputStaging staging(outputDir);
    StagingLayerSink sink(staging, job.format);
    LayerJobResult result = runLayerJob(model, job.options, sink, progress.sub(0.0, 0.95));
    sink.finish();
    result.stageTimes.insert(result.stageTimes.begin(), StageTime{"read", readSeconds, readPeak});
    result.totalSeconds += readSeconds;

    const Progress writeProgress = progress.sub(0.95, 1.0);
    stageReport(staging, sink, args, job, input, result, writeProgress);
    writeProgress.report(1.0, "write");  // last chance to cancel: nothing is in place yet
    staging.commit(isLayerFileName);
    display.finishLine();
    printWarnings(result.warnings);

    if (!args.quiet) {
      printUnreachedWarning(result.field);
      const std::vector<std::string>& layerFiles = sink.layerFiles();
      std::printf("curvedslicer: wrote %zu layers to %s (%s ... %s, %s, %s)\n", layerFiles.size(),
                  outputDir.string().c_str(), layerFiles.front().c_str(), layerFiles.back().c_str(),
                  kVoxelSetsFile, kReportFile);
    }
    return kExitOk;
  } catch (...) {
    return failWithCurrentException(display, outputDir.string(), kJobOutOfMemoryMessage);
  }
}

}  // namespace curvedslicer::cli
