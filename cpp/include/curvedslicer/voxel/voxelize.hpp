// Voxelization (paper §2.1, fig. 3): line segments along the grid's z axis through the voxel-centre
// columns are intersected with the surface; the inside spans fill the voxels whose centres they
// contain.
//
// The ray–triangle test is exact and watertight: vertices are snapped to a fine integer lattice in
// the grid plane and 2D orientations are evaluated in 128-bit integers, with a symbolic
// perturbation of the ray for ties, so a ray through a shared edge or vertex counts exactly once.
// Inside = non-zero winding number when the surface's edges cancel (closed and consistently
// oriented, possibly several overlapping or nested shells: their union; voxels inside two or more
// shells are counted as overlap), else odd crossing parity (robust to flipped triangles). Columns
// whose crossings do not close (an odd count: holes) are resolved voxel by voxel by rays along the
// grid's x and y axes (majority of the rays with an even count); the result says how many columns
// and voxels needed that. Cost: O(T + cells) with T the triangle-column incidences; parallel over
// columns (OpenMP).
#pragma once

#include <array>
#include <string>

#include <cstddef>
#include <string_view>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/voxel/voxel_grid.hpp"

namespace curvedslicer {

/// The smallest memory budget other than 0 (automatic) a job accepts: 1 MiB.
inline constexpr double kMinMemoryBudgetBytes = 1024.0 * 1024.0;

struct VoxelizeOptions {
  double voxelSize = 1.0;  ///< L, mm (> 0)
  GridAlignment alignment = GridAlignment::Pca;
  int padding = 2;  ///< empty cells added around the model's box on each side (≥ 1)
  /// Bytes the whole pipeline may use; 0 = 80 % of physical memory, else at least
  /// kMinMemoryBudgetBytes.
  double memoryBudgetBytes = 0.0;
  /// Bytes the pipeline needs per grid cell (mask, clearance, field, parents, queue).
  double bytesPerCell = 16.0;
};

/// How voxel centres were classified (see voxelize.cpp).
enum class FillRule {
  NonZeroWinding,  ///< closed, consistently oriented surface: union of its shells
  Parity,          ///< edges do not cancel (flipped or missing triangles): odd crossing count
};

std::string_view toString(FillRule rule);  ///< "nonzero" or "parity"

struct VoxelizeStats {
  FillRule fillRule = FillRule::NonZeroWinding;
  std::size_t overlapVoxels = 0;  ///< voxels inside two or more shells (winding |w| >= 2)
  /// Part frame, mm: the box of the overlap voxels' centres (empty without overlap).
  Aabb overlapBounds;
  std::size_t columns = 0;           ///< z columns cast
  std::size_t oddColumns = 0;        ///< z columns whose crossings do not close (odd count)
  std::size_t resolvedVoxels = 0;    ///< voxels of odd columns decided by x/y rays
  std::size_t unresolvedVoxels = 0;  ///< voxels where no ray had an even count (left outside)
  double seconds = 0.0;
};

struct VoxelizeResult {
  VoxelGrid grid;
  VoxelizeStats stats;
};

/// Grid geometry for a mesh: frame (PCA or model axes); the grid is anchored at the frame origin
/// (cell faces at multiples of L), covering the model's box in the frame plus `padding` cells on
/// each side, so dims can be one more than ceil(extent / L) + 2·padding.
/// @throws InvalidInput (L <= 0 or non-finite, empty mesh, non-finite coordinates),
///         ResourceLimit when cells·bytesPerCell exceeds the budget — the message gives the cell
///         count, the memory it needs and the smallest voxel size that fits.
GridGeometry planGrid(const TriMesh& mesh, const VoxelizeOptions& options = {});

/// What planGrid would allocate, also for grids beyond the cell limits (which no GridGeometry can
/// describe): the task panel's voxel and memory estimate. No allocation.
struct GridEstimate {
  std::array<double, 3> dims{};  ///< cells per axis (may exceed the per-axis limit)
  double cells = 0.0;            ///< dims[0]·dims[1]·dims[2]
  double bytes = 0.0;            ///< cells · bytesPerCell
  double budgetBytes = 0.0;      ///< the budget in force (0 in the options: 80 % of memory)
  bool fits = true;              ///< planGrid would succeed
  std::string message;           ///< planGrid's ResourceLimit text when it does not fit
};

/// @throws InvalidInput as planGrid; never ResourceLimit (that is `fits` = false).
GridEstimate estimateGrid(const TriMesh& mesh, const VoxelizeOptions& options = {});

/// Voxelizes a closed (or nearly closed) mesh. See the file comment.
VoxelizeResult voxelize(const TriMesh& mesh, const VoxelizeOptions& options = {},
                        Progress progress = {});

/// Physical memory of this machine in bytes (for the default budget).
double physicalMemoryBytes();

}  // namespace curvedslicer
