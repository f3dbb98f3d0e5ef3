// Dense voxel grid (paper §2.1, eq. 1).
//
// Cell (i, j, k) is the cube [corner + (i,j,k)·L, corner + (i+1,j+1,k+1)·L] in the grid frame; its
// centre represents the voxel. Storage is a dense array indexed by
//   N = i·(ny·nz) + j·nz + k,
// the paper's eq. 1 (N = Px/L·M² + Py/L·M + Pz/L) with the single radix M replaced by the per-axis
// extents, which keeps the bijection (the paper's proof carries over axis by axis) while making the
// array exactly as large as the box. Neighbour access is O(1): the 26 neighbours of N are N plus
// fixed offsets. `paperKey` gives the literal eq. 1 key (M = max extent + 1) for the benchmark
// that reproduces the paper's Table 1.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/voxel/frame.hpp"

namespace curvedslicer {

struct GridGeometry {
  Frame frame;               ///< grid frame (PCA or model axes)
  Vec3 corner = Vec3::Zero();  ///< min corner of cell (0,0,0), grid-frame coordinates, mm
  double voxelSize = 1.0;    ///< L, mm
  Vec3i dims = Vec3i::Zero();  ///< nx, ny, nz

  std::size_t cellCount() const {
    return static_cast<std::size_t>(dims.x()) * dims.y() * dims.z();
  }
  std::size_t strideX() const { return static_cast<std::size_t>(dims.y()) * dims.z(); }
  std::size_t strideY() const { return static_cast<std::size_t>(dims.z()); }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) * strideX() + static_cast<std::size_t>(j) * strideY() + k;
  }
  std::size_t index(const Vec3i& c) const { return index(c.x(), c.y(), c.z()); }
  Vec3i cell(std::size_t n) const {
    const auto sx = strideX(), sy = strideY();
    return Vec3i(static_cast<int>(n / sx), static_cast<int>((n % sx) / sy),
                 static_cast<int>(n % sy));
  }
  bool contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < dims.x() && j < dims.y() && k < dims.z();
  }
  bool contains(const Vec3i& c) const { return contains(c.x(), c.y(), c.z()); }

  /// Cell centre in grid-frame coordinates, mm.
  Vec3 centerInGrid(const Vec3i& c) const {
    return corner + (c.cast<double>().array() + 0.5).matrix() * voxelSize;
  }
  /// Cell centre in the part frame, mm.
  Vec3 centerInPart(const Vec3i& c) const { return frame.toPart(centerInGrid(c)); }
  Vec3 centerInPart(std::size_t n) const { return centerInPart(cell(n)); }
  /// Continuous cell coordinates of a part-frame point (cell centres at integer + 0.5).
  Vec3 toCellCoordinates(const Vec3& partPoint) const {
    return (frame.toFrame(partPoint) - corner) / voxelSize;
  }
  /// Cell containing a part-frame point (may be outside the grid).
  Vec3i cellOf(const Vec3& partPoint) const {
    const Vec3 c = toCellCoordinates(partPoint);
    return Vec3i(static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y())),
                 static_cast<int>(std::floor(c.z())));
  }

  /// The paper's eq. 1 key with M = max(nx, ny, nz) + 1.
  std::uint64_t paperKey(int i, int j, int k) const {
    const std::uint64_t M = static_cast<std::uint64_t>(dims.maxCoeff()) + 1;
    return static_cast<std::uint64_t>(i) * M * M + static_cast<std::uint64_t>(j) * M +
           static_cast<std::uint64_t>(k);
  }
};

/// The 26 neighbour offsets (dx, dy, dz) in {-1,0,1}³ \ {0}, in a fixed order.
const std::array<Vec3i, 26>& neighbourOffsets26();

/// Inside/outside classification of every cell.
struct VoxelGrid {
  GridGeometry geometry;
  /// One byte per cell: 1 = inside the solid (centre inside), 0 = outside.
  std::vector<std::uint8_t> inside;
  std::size_t insideCount = 0;

  bool isInside(int i, int j, int k) const {
    return geometry.contains(i, j, k) && inside[geometry.index(i, j, k)] != 0;
  }
  bool isInside(const Vec3i& c) const { return isInside(c.x(), c.y(), c.z()); }
  /// Inside volume, mm³.
  double insideVolume() const {
    const double L = geometry.voxelSize;
    return static_cast<double>(insideCount) * L * L * L;
  }
};

}  // namespace curvedslicer
