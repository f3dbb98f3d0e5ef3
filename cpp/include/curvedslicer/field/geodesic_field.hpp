// Geodesic distance field inside the solid from a start surface (GDTS, paper §2.2).
//
// Two methods:
//  - `Paper`: the paper's optimised search (§2.2.2 steps 1–9): reference set B, front A, search
//    sphere r = 2√3·L (eq. 8), and the correction split at Smax − √3·L (steps 5–8). Overestimates
//    by up to ~2.9 % of the distance (the stencil's worst angular gap) plus about L.
//  - `AnyAngle` (default): Dijkstra-ordered any-angle propagation. Every voxel keeps a parent —
//    a source triangle (its distance is then the exact point–triangle distance) or a pivot voxel
//    (distance = pivot distance + straight segment) — and inherits its neighbour's parent when the
//    straight segment stays inside the solid (line-of-sight through a clearance field from an exact
//    Euclidean distance transform, with exact voxel walking near walls). Pivots appear only where
//    the shortest path bends around a concave edge. See docs/ACCURACY in the repository.
//    Parents are first inherited untested, then every cell's line of sight is tested in parallel
//    (OpenMP); only cells in the shadow of concave edges are propagated again with pivots
//    (docs/METHODS.md). Peak memory 11 bytes per grid cell besides the inside mask.
//
// Seed voxels (centres within `seedBand` of the start surface) get exact point–triangle distances.
// Inside voxels not connected to the seeds keep +inf and are reported, never dropped silently.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/core/types.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/voxel/voxel_grid.hpp"

namespace curvedslicer {

enum class GeodesicMethod {
  AnyAngle,  ///< accurate default
  Paper,     ///< the paper's optimised search, faithfully
};

std::string_view toString(GeodesicMethod method);
/// Parses "anyangle"/"any-angle"/"exact"/"default" or "paper" (any case); "exact" names the
/// any-angle method with exact line of sight, the reference for any approximate field.
/// @throws InvalidInput listing the choices.
GeodesicMethod parseGeodesicMethod(std::string_view name);

struct GeodesicOptions {
  GeodesicMethod method = GeodesicMethod::AnyAngle;
  /// mm; inside voxels whose centre is within this distance of the start surface are seeds with
  /// exact distances. <= 0: √3·L.
  double seedBand = 0.0;
  /// Paper method only: search-sphere radius in units of L. <= 0: 2√3 (paper §2.2.3).
  double paperSearchRadius = 0.0;
};

/// Per-cell distance in mm; +inf for outside cells and for unreached inside cells.
struct DistanceField {
  GridGeometry geometry;
  std::vector<float> distance;

  float at(std::size_t n) const { return distance[n]; }
  float at(const Vec3i& c) const { return distance[geometry.index(c)]; }
  bool reached(std::size_t n) const { return distance[n] < kInfF; }
};

/// Inside voxels that no path from the start surface reaches (e.g. a separate shell).
struct UnreachedVoxels {
  std::size_t count = 0;
  std::size_t components = 0;   ///< 26-connected components among them
  Aabb bounds;                  ///< part frame, of their centres
  Vec3 example = Vec3::Zero();  ///< one unreached voxel centre, part frame
};

struct GeodesicResult {
  DistanceField field;
  GeodesicMethod method = GeodesicMethod::AnyAngle;
  std::size_t seedCount = 0;
  std::size_t reachedCount = 0;
  UnreachedVoxels unreached;
  double maxDistance = 0.0;  ///< mm, over reached voxels
  // Diagnostics.
  std::size_t lineOfSightTests = 0;       ///< AnyAngle
  std::size_t lineOfSightFailures = 0;    ///< AnyAngle: voxels that needed a pivot
  std::size_t paperOuterIterations = 0;   ///< Paper: loops of steps 2–9
  std::size_t paperCorrectionRounds = 0;  ///< Paper: loops of steps 5–8
  std::size_t edgePivots = 0;             ///< AnyAngle: pivots placed on reflex edges of the model
};

/// Computes the field with the solid's surface at hand (the accurate configuration, used by the
/// pipeline): the any-angle method then tests line of sight exactly against the model's triangles
/// and bends paths at sub-voxel pivots on its reflex (concave) edges.
/// @param grid    voxelized solid (inside mask); the result shares its geometry
/// @param model   the solid's closed, outward-oriented surface, part frame
/// @param source  start-surface triangles, part frame (see `resolveStartSurface`)
/// @throws InvalidInput if the start surface does not touch the solid (no inside voxel centre
///         within the seed band), naming the gap; Cancelled via `progress`.
GeodesicResult computeGeodesicField(const VoxelGrid& grid, const TriMesh& model,
                                    const TriMesh& source, const GeodesicOptions& options = {},
                                    Progress progress = {});

/// The same from the voxel grid alone: line of sight through the voxel mask (clearance field and
/// cell walking) and pivots at voxel centres. Less accurate next to walls (errors up to about one
/// voxel around concave edges); for grids that do not come from a mesh.
GeodesicResult computeGeodesicField(const VoxelGrid& grid, const TriMesh& source,
                                    const GeodesicOptions& options = {}, Progress progress = {});

/// Exact distance from `p` to triangle (a, b, c) and the closest point (Ericson, RTCD §5.1.5).
double pointTriangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                             Vec3* closest = nullptr);

}  // namespace curvedslicer
