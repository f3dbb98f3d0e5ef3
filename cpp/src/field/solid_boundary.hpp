// The solid's surface in cell coordinates, bucketed into bricks of cells, for the any-angle field:
//  - exact line of sight: does a segment strictly cross any surface triangle?
//  - reflex (concave) edges near a point: where shortest paths inside a polyhedron bend.
// Cost: O(T · bricks per triangle) to build; a segment query walks the bricks it passes (3D DDA).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/voxel/voxel_grid.hpp"
#include "field_internal.hpp"

namespace curvedslicer::detail {

class SolidBoundary {
 public:
  /// @param model  closed, outward-oriented surface (part frame); edges that are not shared by
  ///               exactly two consistently oriented triangles are never reflex edges.
  SolidBoundary(const GridGeometry& geometry, const TriMesh& model);

  /// Not thread-safe (per-query marks). True if the open segment (a, b) crosses no triangle
  /// strictly (touching a triangle's plane at an endpoint, or running inside a plane, is not a
  /// crossing). Cell coordinates. When blocked and `hit` is given, it receives a crossing point
  /// (one of the first bricks' along the segment).
  bool segmentClear(const Vec3& a, const Vec3& b, Vec3* hit = nullptr) const;

  /// Indices of reflex edges passing within `radius` cells of `x`, ascending.
  void reflexEdgesNear(const Vec3& x, double radius, std::vector<std::uint32_t>& out) const;

  const std::array<Vec3, 2>& reflexEdge(std::uint32_t e) const { return reflex_[e]; }

  /// True if segment `d` (not normalised), leaving a point of reflex edge `e`, points into the
  /// outside wedge (in front of both faces of the edge) steeply enough to dip more than `depth`
  /// cells outside the solid: a chord across a concave hollow whose far end is on the surface
  /// again. A chord of length l leaving at angle b dips about l·sin(b)/2; shallow chords along a
  /// finely faceted concave wall are accepted (length error ~ depth²/l).
  bool leavesSolidAt(std::uint32_t e, const Vec3& d, double depth) const {
    const double limit = std::max(2.0 * depth, 1e-9 * d.norm());
    return reflexNormals_[e][0].dot(d) > limit && reflexNormals_[e][1].dot(d) > limit;
  }
  std::size_t reflexEdgeCount() const { return reflex_.size(); }

 private:
  std::size_t brickIndex(const Vec3i& b) const {
    return (static_cast<std::size_t>(b.x()) * bdims_.y() + b.y()) * bdims_.z() + b.z();
  }
  Vec3i brickOf(const Vec3& p) const;
  bool crossesTriangle(const Vec3& a, const Vec3& b, std::uint32_t t) const;

  static constexpr int kBrick = 2;  // cells per brick edge
  // Per-query marks so a triangle spanning several bricks is tested once per segment. Queries are
  // therefore not thread-safe (the field propagation is sequential).
  mutable std::vector<std::uint32_t> stamp_;
  mutable std::uint32_t epoch_ = 0;
  Vec3i bdims_;
  std::vector<Triangle> tris_;
  std::vector<Vec3> normals_;                      // unnormalised
  std::vector<std::uint32_t> triStart_, triList_;  // CSR: brick -> triangles
  std::vector<std::array<Vec3, 2>> reflex_;
  std::vector<std::array<Vec3, 2>> reflexNormals_;   // unit outward normals of the two faces
  std::vector<std::uint32_t> edgeStart_, edgeList_;  // CSR: brick -> reflex edges
};

}  // namespace curvedslicer::detail
