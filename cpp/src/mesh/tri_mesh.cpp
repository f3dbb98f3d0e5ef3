#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

double surfaceArea(const TriMesh& mesh) {
  double area = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) area += mesh.triangleArea(t);
  return area;
}

double signedVolume(const TriMesh& mesh) {
  // Divergence theorem relative to the bounding-box centre (reduces cancellation).
  const Vec3 c = mesh.bounds().center();
  double six = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3 a = mesh.corner(t, 0) - c, b = mesh.corner(t, 1) - c, d = mesh.corner(t, 2) - c;
    six += a.dot(b.cross(d));
  }
  return six / 6.0;
}

void appendMesh(TriMesh& mesh, const TriMesh& other) {
  const int offset = static_cast<int>(mesh.vertices.size());
  const bool keepIds = mesh.faceIds.size() == mesh.triangles.size() &&
                       other.faceIds.size() == other.triangles.size();
  mesh.vertices.insert(mesh.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const Vec3i& t : other.triangles) mesh.triangles.push_back(t.array() + offset);
  if (keepIds) {
    mesh.faceIds.insert(mesh.faceIds.end(), other.faceIds.begin(), other.faceIds.end());
  } else {
    mesh.faceIds.clear();
  }
}

}  // namespace curvedslicer
