// Internal pieces shared by the two geodesic-field methods. Everything here works in "cell units":
// positions are continuous cell coordinates (cell (i,j,k) has its centre at (i+½, j+½, k+½)) and
// distances are in units of L; the public entry point converts back to mm.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/field/geodesic_field.hpp"

namespace curvedslicer::detail {

using Triangle = std::array<Vec3, 3>;

/// Source triangles in cell coordinates; zero-area triangles dropped.
std::vector<Triangle> toCellCoordinates(const GridGeometry& geometry, const TriMesh& source);

inline Vec3 cellCentre(const Vec3i& c) {
  return c.cast<double>().array() + 0.5;
}

/// Parent encoding of the any-angle method: >= 0 a pivot cell, < 0 the source triangle -1-code.
inline constexpr std::int32_t kNoParent = INT32_MIN;
inline std::int32_t triangleParent(std::size_t t) {
  return -1 - static_cast<std::int32_t>(t);
}
inline std::size_t parentTriangle(std::int32_t code) {
  return static_cast<std::size_t>(-1 - code);
}

/// Seeds: inside cells whose centre lies within `bandCells` of a source triangle get the exact
/// distance (cell units) and, if `parent` is given, the closest triangle as parent.
/// @return the seed cells in increasing index order.
/// @throws InvalidInput if no inside cell is within the band (the start surface misses the solid).
std::vector<std::uint32_t> placeSeeds(const VoxelGrid& grid, const std::vector<Triangle>& source,
                                      double bandCells, std::vector<float>& dist,
                                      std::vector<std::int32_t>* parent, const TriMesh& sourceMm);

struct MethodStats {
  std::size_t lineOfSightTests = 0;
  std::size_t lineOfSightFailures = 0;
  std::size_t outerIterations = 0;
  std::size_t correctionRounds = 0;
  std::size_t edgePivots = 0;
};

/// Clearance of every cell (computeClearance) floored to whole cells, saturated at 255: the
/// any-angle method's line-of-sight fast path. 1 byte per cell (4 more while it is computed).
std::vector<std::uint8_t> computeClearanceCells(const VoxelGrid& grid, Progress progress);

/// Any-angle propagation (see geodesic_field.hpp). `dist` holds the seeds on entry and the field
/// (cell units, +inf where unreached) on exit; `parent` the seeds' triangles on entry.
/// `clearance` from computeClearanceCells (consumed). `model` (may be null) enables exact line of
/// sight and pivots on its reflex edges.
MethodStats propagateAnyAngle(const VoxelGrid& grid, const TriMesh* model,
                              const std::vector<Triangle>& source,
                              const std::vector<std::uint32_t>& seeds, double seedBandCells,
                              std::vector<std::uint8_t> clearance, std::vector<float>& dist,
                              std::vector<std::int32_t>& parent, Progress progress);

/// The paper's optimised search (§2.2.2 steps 1–9). `dist` holds the seeds on entry.
MethodStats propagatePaper(const VoxelGrid& grid, const std::vector<std::uint32_t>& seeds,
                           double searchRadiusCells, std::vector<float>& dist, Progress progress);

}  // namespace curvedslicer::detail
