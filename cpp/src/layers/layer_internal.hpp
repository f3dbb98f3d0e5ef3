// Internal building blocks of extractLayers (layer_extraction.cpp): field extension beyond the
// solid, one-pass marching tetrahedra for all levels, clipping to the solid, mesh statistics.
// Not part of the public API.
#pragma once

#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/voxel/voxel_grid.hpp"

namespace curvedslicer::layers_detail {

/// A number in a message, with up to ten significant digits.
inline std::string formatNumber(double x) {
  std::ostringstream s;
  s.precision(10);
  s << x;
  return s.str();
}

/// Runs body(i) for i in [0, count) with OpenMP, in consecutive chunks of at least one item per
/// thread (a batch of a few layers still runs them in parallel); after each chunk reports
/// progress (fraction of items done) on the calling thread, which may throw Cancelled. `body` must
/// not throw.
template <class Body>
void runChunked(std::size_t count, const Progress& progress, std::string_view stage, Body&& body) {
  progress.report(0.0, stage);
  const auto threads = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
  const std::size_t chunk = std::max<std::size_t>(threads, (count + 31) / 32);
  for (std::size_t begin = 0; begin < count; begin += chunk) {
    const auto end = static_cast<std::ptrdiff_t>(std::min(count, begin + chunk));
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t i = static_cast<std::ptrdiff_t>(begin); i < end; ++i) {
      body(static_cast<std::size_t>(i));
    }
    progress.report(static_cast<double>(end) / static_cast<double>(count), stage);
  }
}

// ---- field extension (field_extension.cpp) --------------------------------------------------

struct FieldExtensionStats {
  std::size_t extendedCells = 0;     ///< outside cells that received a value
  std::size_t partialFits = 0;       ///< of those, fitted with a rank-deficient gradient
  std::size_t nearestFallbacks = 0;  ///< of those, given the nearest reached value
};

/// Adds values in outside cells (grid.inside == 0) within Chebyshev distance `kExtensionBand`
/// cells of a reached cell (value < +inf), in place: a weighted least-squares linear fit
/// d ≈ a + g·(x − x0) over the reached cells in the (2·kFitRadius + 1)³ box around the cell x0
/// (weights 1/|x − x0|²). Directions in which the samples' weighted variance is below
/// kMinVariance (cells²) get no gradient component (truncated eigen-solve); if no direction is
/// determined, the nearest reached value is used. A linear field is reproduced exactly whenever
/// the samples span 3D. Every fit reads the values as they were before the call; other cells keep
/// their values (+inf if not reached). Extra memory: one bit per cell plus 12 bytes per extended
/// cell.
/// @return the extended cells, increasing linear index
inline constexpr int kExtensionBand = 2;
inline constexpr int kFitRadius = 3;
inline constexpr double kMinVariance = 0.04;
std::vector<std::size_t> extendFieldInPlace(std::vector<float>& values, const VoxelGrid& grid,
                                            FieldExtensionStats& stats, const Progress& progress);

/// The same on a copy of the field.
std::vector<float> extendField(const DistanceField& field, const VoxelGrid& grid,
                               FieldExtensionStats& stats, const Progress& progress);

// ---- marching tetrahedra (marching_tetrahedra.cpp) ------------------------------------------

/// What one scan of the dual grid learns before any surface is built: for every level i·h
/// (i = 1..layerCount) the number of cubes it crosses (a proxy for its triangle count: the Kuhn
/// split gives at most 12 triangles per cube and level), and per fixed x slab of cubes the levels
/// it meets, so that later passes for a range of levels skip slabs that meet none of them.
struct IsoSurfacePlan {
  struct SlabLevels {
    int x0 = 0, x1 = 0;  ///< cubes with min-corner x in [x0, x1)
    int firstLevel = 0,
        lastLevel = -1;  ///< levels crossing a cube of the slab (empty if last < first)
  };
  double h = 1.0;
  int layerCount = 0;
  int layerBits = 1;
  std::vector<SlabLevels> slabs;
  std::vector<std::uint64_t> crossingCubes;  ///< [i − 1]: cubes crossed by level i
};

/// Scans `values` (one per cell, +inf = no value) once for the plan above.
/// @throws InvalidInput if grid keys and level numbers do not fit 64 bits together.
IsoSurfacePlan planIsoSurfaces(const std::vector<float>& values, const GridGeometry& geometry,
                               double h, int layerCount, const Progress& progress);

/// Iso-surfaces values = i·h for i = levelBegin..levelEnd (1-based, within the plan) of the
/// piecewise-linear interpolant of `values` on the Kuhn (Freudenthal) tetrahedralisation of the
/// dual grid, in one pass over the cubes of the slabs that meet those levels. Result[i −
/// levelBegin] is level i, part frame, indexed (vertices shared through the grid edge they lie
/// on), triangles oriented with normals towards increasing values; triangles with repeated
/// vertices are dropped. A level's surface does not depend on the range it is extracted with.
std::vector<TriMesh> extractIsoSurfaces(const std::vector<float>& values,
                                        const GridGeometry& geometry, const IsoSurfacePlan& plan,
                                        int levelBegin, int levelEnd, const Progress& progress);

// ---- clipping and clean-up (surface_clipping.cpp) -------------------------------------------

struct ClipStats {
  std::size_t exactQueries = 0;  ///< vertices whose signed distance was computed exactly
  std::size_t rimVertices = 0;   ///< new vertices created on the model surface
};

/// Vertices closer than kSnapDistance·L to the model surface are treated as lying on it.
inline constexpr double kSnapDistance = 1e-6;

/// One byte per cell: 1 if the cell's cube may meet a model triangle (conservative: the cell lies
/// in the triangle's bounding box and its centre within √3/2·L of the triangle's plane). A point
/// in an unmarked cell is on the same side of the model surface as that cell's centre.
std::vector<std::uint8_t> markSurfaceCells(const TriMesh& model, const GridGeometry& geometry);

/// Keeps the part of `surface` inside the solid (signed distance ≤ 0): triangles crossing the
/// model surface are split at the linear zero of the vertex signed distances and the new rim
/// vertices are moved to their closest point on the model surface; vertices within
/// kSnapDistance·L of the surface are moved onto it instead of being split off. Vertices in cells
/// not marked by `markSurfaceCells` take their side from the voxel mask instead of an exact
/// distance query. The result is cleaned (see `removeDegenerateAndUnused`).
TriMesh clipSurfaceToSolid(const TriMesh& surface, const TriangleBvh& model, const VoxelGrid& grid,
                           const std::vector<std::uint8_t>& surfaceCells, ClipStats& stats);

/// Drops triangles with repeated vertices or exactly zero area, then vertices no triangle uses
/// (order of the rest preserved).
void removeDegenerateAndUnused(TriMesh& mesh);

/// Number of edge-connected components of the triangles.
std::size_t countEdgeComponents(const TriMesh& mesh);

}  // namespace curvedslicer::layers_detail
