// Internal helpers shared by the path-geometry sources (not part of the public API).
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer::paths_detail {

/// A number in a message: four significant digits (%.4g).
inline std::string formatNumber(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.4g", value);
  return buffer;
}

/// Key of the undirected edge (a, b).
inline std::uint64_t edgeKey(std::int32_t a, std::int32_t b) {
  const auto lo = static_cast<std::uint64_t>(static_cast<std::uint32_t>(a < b ? a : b));
  const auto hi = static_cast<std::uint64_t>(static_cast<std::uint32_t>(a < b ? b : a));
  return (lo << 32) | hi;
}

/// Places the crossing point on edge (a, b) where the linear interpolation of the field reaches
/// the level: t in [0, 1] from a to b. May refine it (user-surface sections).
using CrossingPlacer = std::function<Vec3(std::int32_t a, std::int32_t b, double t)>;

/// Marching triangles (see iso_lines.hpp): the level set {f = level} of a per-vertex field,
/// chained into polylines; vertices with f ≥ level count as above. Triangles with a non-finite
/// corner value are skipped. Orientation: the side with f > level on the left, seen from the
/// normals' side. `place` defaults to linear interpolation.
std::vector<Polyline> traceLevelSet(const TriMesh& mesh, const std::vector<double>& f, double level,
                                    const CrossingPlacer& place = {});

/// traceLevelSet for several levels in one pass over the triangles (each triangle visits only
/// the levels between its corner values); result k is exactly traceLevelSet(…, levels[k], …).
std::vector<std::vector<Polyline>> traceLevelSets(const TriMesh& mesh, const std::vector<double>& f,
                                                  const std::vector<double>& levels,
                                                  const CrossingPlacer& place = {});

}  // namespace curvedslicer::paths_detail
