#include "curvedslicer/voxel/voxel_grid.hpp"

namespace curvedslicer {

const std::array<Vec3i, 26>& neighbourOffsets26() {
  static const std::array<Vec3i, 26> offsets = [] {
    std::array<Vec3i, 26> o;
    int n = 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (dx != 0 || dy != 0 || dz != 0) o[n++] = Vec3i(dx, dy, dz);
    return o;
  }();
  return offsets;
}

}  // namespace curvedslicer
