// Start surfaces: where the geodesic field is zero (paper §2.2.2 step 1, "the initial curved
// layer given by users").
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

struct StartSurface {
  enum class Kind {
    Plane,  ///< a plane, by default the build plate under the model (z = model's min z)
    Faces,  ///< a subset of the model's own triangles, selected by `TriMesh::faceIds`
    Mesh,   ///< a separate surface mesh, e.g. the curved base the part grows from
  };
  Kind kind = Kind::Plane;

  /// Plane: when true the plane is z = (model's min z), normal +z; otherwise `planePoint` and
  /// `planeNormal` (part frame, mm; the normal need not be unit length).
  bool planeAtModelBottom = true;
  Vec3 planePoint = Vec3::Zero();
  Vec3 planeNormal = Vec3::UnitZ();

  /// Faces: ids matched against the model's `faceIds` (triangle positions in the file for STL/OBJ,
  /// FreeCAD FaceN numbers for CAD shapes).
  std::vector<int> faceIds;

  /// Mesh: the surface, part frame, mm.
  TriMesh mesh;

  static StartSurface buildPlate() { return {}; }
  static StartSurface horizontalPlane(double z) {
    StartSurface s;
    s.planeAtModelBottom = false;
    s.planePoint = Vec3(0, 0, z);
    return s;
  }
  static StartSurface plane(const Vec3& point, const Vec3& normal) {
    StartSurface s;
    s.planeAtModelBottom = false;
    s.planePoint = point;
    s.planeNormal = normal;
    return s;
  }
  static StartSurface faces(std::vector<int> ids) {
    StartSurface s;
    s.kind = Kind::Faces;
    s.faceIds = std::move(ids);
    return s;
  }
  static StartSurface surface(TriMesh m) {
    StartSurface s;
    s.kind = Kind::Mesh;
    s.mesh = std::move(m);
    return s;
  }

  /// Human-readable description for reports, e.g. "plane z=0 mm", "faces 3,4,7 (2 triangles)".
  std::string describe() const;
};

/// "plane" | "faces" | "mesh" (the kinds of the command line's start specs and the Python
/// module's names).
std::string_view toString(StartSurface::Kind kind);
/// @throws InvalidInput naming the text and the choices.
StartSurface::Kind parseStartSurfaceKind(std::string_view name);

/// Turns a start-surface description into source triangles in the part frame.
/// A plane becomes a rectangle (two triangles) covering the model's bounding box with a margin.
/// @throws InvalidInput for a zero normal, face ids the model does not have (naming them), a model
///         without face ids, or an empty/non-finite surface mesh.
TriMesh resolveStartSurface(const TriMesh& model, const StartSurface& start);

}  // namespace curvedslicer
