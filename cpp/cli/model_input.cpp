#include "model_input.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#ifdef CURVEDSLICER_CLI_HAS_OCC
#include "curvedslicer/occ/shape_tessellation.hpp"
#endif

namespace curvedslicer::cli {

bool isCadFile(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".step" || ext == ".stp" || ext == ".iges" || ext == ".igs" || ext == ".brep" ||
         ext == ".brp";
}

double parseTessellationTolerance(const std::string& text) {
  if (text.empty()) return 0.0;
  const double tolerance = parseLength(text, "tessellation tolerance");
  if (!std::isfinite(tolerance) || tolerance <= 0.0) {
    throw InvalidInput("tessellation tolerance must be a positive number of mm: '" + text +
                       "'; pass e.g. --tessellation-tolerance 0.1, or leave it out (voxel/4)");
  }
  return tolerance;
}

ModelInput readModel(const std::filesystem::path& path, double tolerance, double voxelSize) {
  if (!isCadFile(path)) return ModelInput{readMesh(path), 0.0};
#ifdef CURVEDSLICER_CLI_HAS_OCC
  TessellationOptions options;
  if (tolerance > 0.0) {
    options.linearDeflection = tolerance;
  } else if (voxelSize > 0.0) {
    options.linearDeflection = deflectionForVoxelSize(voxelSize);
  }
  return ModelInput{tessellateCadFile(path, CadFormat::Auto, options), options.linearDeflection};
#else
  (void)tolerance;
  (void)voxelSize;
  throw InvalidInput("CAD input needs the OpenCASCADE build: '" + path.string() +
                     "'; convert the model to STL or OBJ, or build with CURVEDSLICER_BUILD_OCC=ON");
#endif
}

}  // namespace curvedslicer::cli
