// Tessellating CAD shapes with OpenCASCADE: BREP text (FreeCAD's `shape.exportBrepToString()`) or
// a STEP / IGES / BREP file becomes a TriMesh whose triangles carry the FreeCAD face number they
// came from.
//
// Method: BRepMesh_IncrementalMesh with a linear (chord) and an angular deflection; each face's
// Poly_Triangulation is moved by the face's location and its triangles are flipped for reversed
// faces, so a closed solid gives an outward-oriented mesh. Face numbers are 1-based in
// TopExp::MapShapes(shape, TopAbs_FACE) order — FreeCAD's `FaceN`. The shared edge nodes of
// neighbouring faces are welded (cleanMesh, tolerance 1e-6 of the diagonal; triangles that
// become degenerate are dropped), so a closed solid gives a closed indexed mesh.
// Preconditions: none; a shape without faces or a face that cannot be meshed is an InvalidInput.
// Cost: that of BRepMesh (roughly linear in the triangles produced, which grow as
// 1/deflection for curved faces), plus O(n log n) welding.
#pragma once

#include <filesystem>
#include <string_view>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

struct TessellationOptions {
  /// mm (> 0); largest distance between a triangle and the exact surface (chord error). See
  /// `deflectionForVoxelSize` for the value the layer job uses.
  double linearDeflection = 0.1;
  /// radians (> 0); largest angle between the normals of neighbouring triangles on a curved face.
  double angularDeflection = 0.5;
};

/// The chord error the layer job asks for at voxel size L: L/4 (mm), so the tessellated surface
/// stays within a quarter voxel of the exact one — well below the voxel-centre sampling error —
/// without the triangle count exploding at fine voxel sizes. @throws InvalidInput for L <= 0.
double deflectionForVoxelSize(double voxelSize);

/// Which file a shape comes from.
enum class CadFormat {
  Auto,  ///< by extension (.step/.stp, .iges/.igs, .brep/.brp), else by content
  Step,
  Iges,
  Brep,
};

/// "auto" | "step" | "iges" | "brep" (the Python module's names).
std::string_view toString(CadFormat format);
/// @throws InvalidInput naming the text and the choices.
CadFormat parseCadFormat(std::string_view name);

/// Tessellates a shape given as OpenCASCADE BREP text (part frame, mm).
/// @return mesh with `faceIds[t]` = the FaceN of triangle t (1-based)
/// @throws InvalidInput for text that is not a BREP shape, a shape without faces, bad options,
///         or a face that could not be triangulated (naming its FaceN).
TriMesh tessellateBrepText(std::string_view brep, const TessellationOptions& options = {});

/// Reads a STEP, IGES or BREP file (mm) and tessellates the whole shape it contains.
/// @throws InvalidInput for a missing, unreadable or empty file (naming it), plus the errors of
///         `tessellateBrepText`.
TriMesh tessellateCadFile(const std::filesystem::path& path, CadFormat format = CadFormat::Auto,
                          const TessellationOptions& options = {});

/// Number of faces of a BREP shape (the largest valid FaceN). @throws InvalidInput as above.
int countBrepFaces(std::string_view brep);

}  // namespace curvedslicer
