// Bounding-volume hierarchy over a triangle mesh: closest point, signed distance, ray and box
// queries.
//
// Method: CGAL's AABB tree (Simple_cartesian<double>, one primitive per non-degenerate triangle)
// with its k-d tree of reference points built eagerly, so every query is a `const` call that never
// mutates shared state — safe to call concurrently from OpenMP loops. CGAL is confined to
// triangle_bvh.cpp (pimpl).
//
// Signed distance (Bærentzen & Aanæs, "Signed distance computation using the angle weighted
// pseudonormal", IEEE TVCG 11(3), 2005): the closest point is found on the nearest triangle and
// classified as lying in that triangle's interior, on an edge or at a vertex (Voronoi regions of
// the triangle, Ericson RTCD §5.1.5); the sign is that of (p − closest)·n where n is the face
// normal, the edge pseudo-normal (sum of the unit normals of the triangles sharing the edge) or
// the vertex pseudo-normal (unit normals weighted by the incident angles). For a closed,
// consistently outward-oriented 2-manifold this sign is exact up to rounding, including for points
// arbitrarily close to the surface, at edges and at vertices (unlike a single face normal, which
// fails near sharp edges). Topology is taken from vertex positions, not indices: vertices with
// identical coordinates are welded first, so unwelded triangle soups (STL) work. Degenerate
// (zero-area) triangles take no part in any query.
//
// Preconditions: finite coordinates. `signedDistance` additionally needs a closed, outward-
// oriented mesh; on open or inconsistently oriented meshes the sign is only locally meaningful.
// Cost: construction O(T log T) time, ~200 bytes per triangle; closest point / signed distance
// O(log T) typical (grows with the distance to the surface); ray and box queries O(log T) typical.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

/// Closest point on the mesh to a query point.
struct ClosestPoint {
  Vec3 point = Vec3::Zero();  ///< part frame, mm
  int triangle = -1;          ///< index into the mesh's triangles; -1 if the mesh has none
  double distance = kInf;     ///< |query − point|, mm
};

/// First intersection of a ray with the mesh.
struct RayHit {
  Vec3 point = Vec3::Zero();  ///< part frame, mm
  int triangle = -1;          ///< index into the mesh's triangles
  double t = 0.0;             ///< ray parameter: point = origin + t·direction (t ≥ 0)
};

struct TriangleBvhOptions {
  /// Build a k-d tree over one corner per triangle to start closest-point searches near the
  /// answer (~40 % of the construction time). Without it, queries without a hint start from an
  /// arbitrary triangle (correct but slow); queries given a nearby hint are about as fast.
  bool searchTree = true;
};

class TriangleBvh {
 public:
  /// An empty hierarchy (every query reports "no triangle").
  TriangleBvh();
  /// Builds the hierarchy over `mesh` (part frame, mm). The mesh is copied; it need not outlive
  /// the hierarchy. Degenerate triangles are skipped. @throws InvalidInput for non-finite
  /// coordinates or out-of-range vertex indices.
  explicit TriangleBvh(const TriMesh& mesh, const TriangleBvhOptions& options = {});
  ~TriangleBvh();
  TriangleBvh(TriangleBvh&&) noexcept;
  TriangleBvh& operator=(TriangleBvh&&) noexcept;
  TriangleBvh(const TriangleBvh&) = delete;
  TriangleBvh& operator=(const TriangleBvh&) = delete;

  /// True if no (non-degenerate) triangle takes part in queries.
  bool empty() const;
  /// Number of triangles that take part in queries.
  std::size_t triangleCount() const;
  /// Bounding box of those triangles, part frame.
  Aabb bounds() const;

  /// Closest point on the surface to `p` (part frame, mm). Empty hierarchy: triangle = −1,
  /// distance = +inf.
  ClosestPoint closestPoint(const Vec3& p) const;
  /// The same, starting the search from `hint` — an earlier result for a nearby point (its point
  /// and triangle; a hint with triangle −1 is ignored, the search tree is used instead). The
  /// search visits every node within |p − hint.point| of p, so a hint is only worth giving when it
  /// is close (e.g. the previous vertex of a mesh in order); the result is the same up to ties.
  ClosestPoint closestPoint(const Vec3& p, const ClosestPoint& hint) const;

  /// Unsigned distance to the surface, mm (+inf for an empty hierarchy).
  double distance(const Vec3& p) const;

  /// Signed distance to a closed, outward-oriented surface, mm: negative inside, positive
  /// outside (pseudo-normal sign, see the file comment). `closest` (optional) receives the
  /// closest point. Empty hierarchy: +inf.
  double signedDistance(const Vec3& p, ClosestPoint* closest = nullptr) const;
  /// The same with a search hint (see `closestPoint`).
  double signedDistance(const Vec3& p, const ClosestPoint& hint,
                        ClosestPoint* closest = nullptr) const;

  /// First hit of the ray origin + t·direction, t in [0, maxT] (direction need not be unit;
  /// t is in units of its length). std::nullopt if none or the direction is zero.
  std::optional<RayHit> firstRayHit(const Vec3& origin, const Vec3& direction,
                                    double maxT = kInf) const;

  /// True if any triangle intersects the closed axis-aligned box (part frame).
  bool intersectsBox(const Aabb& box) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace curvedslicer
