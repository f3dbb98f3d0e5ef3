// Indexed triangle mesh: the interchange type between file readers, the OCCT tessellator, the
// voxelizer, layer surfaces and the bindings.
#pragma once

#include <cstdint>
#include <vector>

#include "curvedslicer/core/types.hpp"

namespace curvedslicer {

struct TriMesh {
  /// Vertex positions, mm, part frame.
  std::vector<Vec3> vertices;
  /// Vertex indices per triangle; counter-clockwise seen from outside for a solid.
  std::vector<Vec3i> triangles;
  /// Optional, one per triangle (empty = none): the id of the source face the triangle came
  /// from. STL/OBJ readers store the triangle's 0-based position in the file; the OCCT
  /// tessellator stores FreeCAD's 1-based face number (FaceN). Start surfaces of kind `Faces`
  /// select triangles by this id.
  std::vector<int> faceIds;

  std::size_t vertexCount() const { return vertices.size(); }
  std::size_t triangleCount() const { return triangles.size(); }
  bool empty() const { return triangles.empty(); }

  const Vec3& corner(std::size_t t, int k) const { return vertices[triangles[t][k]]; }
  /// Unnormalised normal (twice the area times the unit normal).
  Vec3 areaNormal(std::size_t t) const {
    return (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0));
  }
  double triangleArea(std::size_t t) const { return 0.5 * areaNormal(t).norm(); }

  Aabb bounds() const {
    Aabb b;
    for (const Vec3& v : vertices) b.extend(v);
    return b;
  }
};

/// Total surface area, mm².
double surfaceArea(const TriMesh& mesh);

/// Signed enclosed volume, mm³ (positive for outward-oriented closed meshes).
double signedVolume(const TriMesh& mesh);

/// Appends `other` to `mesh` (indices shifted; face ids kept if both have them).
void appendMesh(TriMesh& mesh, const TriMesh& other);

}  // namespace curvedslicer
