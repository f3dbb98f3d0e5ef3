// Reading the model of `layers` and `plan`: an STL or OBJ mesh (mesh/mesh_io.hpp; face ids are
// 0-based triangle positions), or a CAD file — STEP (.step/.stp), IGES (.iges/.igs) or BREP
// (.brep/.brp) — tessellated through OpenCASCADE (occ/shape_tessellation.hpp; face ids are
// FreeCAD's 1-based FaceN). A build without OpenCASCADE (CURVEDSLICER_BUILD_OCC=OFF) refuses CAD
// files with InvalidInput.
#pragma once

#include <filesystem>
#include <string>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer::cli {

/// True for a CAD file name: .step .stp .iges .igs .brep .brp, in any letter case.
bool isCadFile(const std::filesystem::path& path);

/// Parses --tessellation-tolerance (mm, > 0); empty text gives 0 (automatic).
/// @throws InvalidInput for a value that is not a positive finite number.
double parseTessellationTolerance(const std::string& text);

/// A model as read.
struct ModelInput {
  TriMesh mesh;
  double tessellationTolerance = 0.0;  ///< mm, the chord error used for a CAD file; 0: a mesh file
};

/// Reads `path`. A CAD file is tessellated with chord deflection `tolerance` (mm); 0 means
/// deflectionForVoxelSize(voxelSize), or TessellationOptions{}'s when `voxelSize` <= 0 (thin
/// wall); the angular deflection is TessellationOptions{}'s.
/// @throws InvalidInput / IoError from reading; InvalidInput for a CAD file without OpenCASCADE.
ModelInput readModel(const std::filesystem::path& path, double tolerance, double voxelSize);

}  // namespace curvedslicer::cli
