// The JSON report of a layer job (report.json): inputs, mesh diagnostics and repair counts, grid,
// field diagnostics, per-stage wall times, peak memory and one entry per layer. Keys keep a fixed
// order (nlohmann::ordered_json); numbers are JSON numbers with units in the key names (_mm,
// _mm2, _mm3, _seconds, _bytes); values that do not exist (e.g. bounds of an empty set, the
// thickness of a layer without samples) are null. Cost O(layers + stages).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "curvedslicer/pipeline/layer_pipeline.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"

namespace curvedslicer {

/// Version of the report's layout; bumped when keys change meaning or disappear.
inline constexpr int kLayerReportFormatVersion = 1;

/// What the report needs beyond the job's options and result.
struct LayerReportInputs {
  std::string modelPath;               ///< as given by the user
  std::size_t modelFileTriangles = 0;  ///< triangles read from the file (before cleaning)
  /// mm; chord error the CAD model was tessellated with ("tessellation_tolerance_mm");
  /// 0 for a mesh file (then not written)
  double tessellationTolerance = 0.0;
  std::string startSpec;  ///< as given, e.g. "plane:bottom"
  LayerFileFormat layerFormat = LayerFileFormat::Ply;
  std::vector<std::string> layerFiles;  ///< one per surface, same order; empty: not written
  std::string voxelSetsFile;            ///< empty: not written
};

/// Builds the report. `layerFiles` must be empty or have one name per layer surface.
/// @throws InvalidInput if `layerFiles` has another size.
nlohmann::ordered_json makeLayerReport(const LayerReportInputs& inputs,
                                       const LayerJobOptions& options,
                                       const LayerJobResult& result);

/// The report as text: two-space indentation, a final newline.
std::string formatLayerReport(const nlohmann::ordered_json& report);

}  // namespace curvedslicer
