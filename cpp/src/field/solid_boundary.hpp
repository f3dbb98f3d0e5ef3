// The solid's surface in cell coordinates, bucketed into bricks of cells, for the any-angle field:
//  - exact line of sight: does a segment strictly cross any surface triangle?
//  - reflex (concave) edges near a point: where shortest paths inside a polyhedron bend.
// Triangles are listed in the bricks they overlap (exact separating-axis test), reflex edges in
// the bricks within 3 cells of them.
// Cost: O(T · bricks per triangle) to build; a segment query walks the bricks it passes (3D DDA)
// and tests each listed triangle once; at most 1 byte per grid cell for the two brick indices
// (bricks of 2 cells; 4 or 8 for meshes of large triangles).
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

  /// Per-thread scratch of segment queries: marks so that a triangle spanning several bricks is
  /// tested once per segment. One per thread; `makeMailbox` sizes it (4 bytes per triangle).
  struct Mailbox {
    std::vector<std::uint32_t> stamp;
    std::uint32_t epoch = 0;
  };
  Mailbox makeMailbox() const { return Mailbox{std::vector<std::uint32_t>(tris_.size(), 0), 0}; }

  /// A crossing this close to the start of a segment (cells) is ignored by default: the start is
  /// then a cell centre in the sliver between a curved solid and its tessellation.
  static constexpr double kStartTolerance = 0.05;

  /// True if the open segment (a, b) crosses no triangle strictly (touching a triangle's plane at
  /// an endpoint, or running inside a plane, is not a crossing). Cell coordinates. When blocked
  /// and `hit` is given, it receives a crossing point (one of the first bricks' along the
  /// segment). Crossings within `startTolerance` cells of `a` are ignored (0: none is).
  /// Thread-safe with one `mailbox` per thread.
  bool segmentClear(const Vec3& a, const Vec3& b, Mailbox& mailbox, Vec3* hit = nullptr,
                    double startTolerance = kStartTolerance) const;

  /// Indices of reflex edges passing within `radius` cells of `x`, ascending.
  void reflexEdgesNear(const Vec3& x, double radius, std::vector<std::uint32_t>& out) const;

  const std::array<Vec3, 2>& reflexEdge(std::uint32_t e) const { return reflex_[e]; }
  /// Unit outward normals of the two faces of reflex edge e.
  const std::array<Vec3, 2>& reflexNormals(std::uint32_t e) const { return reflexNormals_[e]; }

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

  /// True if every edge of the model is shared by exactly two consistently oriented,
  /// non-degenerate triangles: then only reflex edges can block a segment locally (see
  /// polygonMeetsReflexEdge).
  bool closedManifold() const { return closed_; }

  /// True if a reflex edge other than `skip` (-1: none) meets the closed convex planar polygon
  /// `poly[0..count)` (3 or 4 vertices in order, cell units) or passes within `tolerance` cells
  /// of it; also true when the polygon is degenerate (conservative). Brute force over all
  /// reflex edges: O(reflexEdgeCount()), for models with few of them.
  bool polygonMeetsReflexEdge(const Vec3* poly, int count, std::int64_t skip,
                              double tolerance) const;

 private:
  std::size_t brickIndex(const Vec3i& b) const {
    return (static_cast<std::size_t>(b.x()) * bdims_.y() + b.y()) * bdims_.z() + b.z();
  }
  Vec3i brickOf(const Vec3& p) const;
  bool crossesTriangle(const Vec3& a, const Vec3& b, std::uint32_t t, double startTolerance) const;

  int brick_ = 2;  // cells per brick edge: 2, 4 or 8 (from the mean triangle area)
  // 1 / brick_: a power of two, so multiplying by it rounds exactly as dividing by brick_.
  double inverseBrick_ = 0.5;
  Vec3i bdims_;
  std::vector<Triangle> tris_;
  std::vector<Vec3> normals_;  // unnormalised
  /// Per triangle, for crossesTriangle: 1e-9·|n|, −1e-9·|n|², and the sides' inward normals
  /// n × (v[k+1] − v[k]) (n·((v[k+1] − v[k]) × (p − v[k])) = (n × (v[k+1] − v[k]))·(p − v[k])).
  struct CrossingData {
    double planeEps;
    double sideTol;
    std::array<Vec3, 3> sideNormals;
  };
  std::vector<CrossingData> crossing_;
  std::vector<std::uint32_t> triStart_, triList_;  // CSR: brick -> triangles
  std::vector<std::array<Vec3, 2>> reflex_;
  std::vector<std::array<Vec3, 2>> reflexNormals_;   // unit outward normals of the two faces
  std::vector<std::uint32_t> edgeStart_, edgeList_;  // CSR: brick -> reflex edges
  bool closed_ = false;
};

}  // namespace curvedslicer::detail
