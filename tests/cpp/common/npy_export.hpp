// NumPy exports of a voxelized field problem for the scikit-fmm peers of the field benchmarks
// (tests/bench/field_bench.cpp, model_field_bench.cpp; read by field_vs_skfmm.py and
// model_vs_skfmm.py).
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/voxel/voxel_grid.hpp"

namespace curvedslicer::testing {

/// Writes a C-order NumPy .npy file (format 1.0) of shape dims; `descr` the NumPy type string
/// (e.g. "<f8"), `bytes` the size of `data`.
void writeNpy(const std::filesystem::path& path, const char* descr, const Vec3i& dims,
              const void* data, std::size_t bytes);

/// Signed distance (mm) to the start surface in the seed band √3·L, NaN elsewhere, per grid cell:
///  - inside cells whose centre lies within the band of the source triangles get +distance:
///    exactly the seed voxels and seed values of the C++ methods (placeSeeds, default band);
///  - outside cells within the band whose closest source point is the foot of the perpendicular
///    on a source triangle (i.e. cells behind the start surface, not beside its rim) get
///    −distance, the negative side that skfmm needs to see a zero level set on the start surface.
/// Meant for start surfaces on the solid's boundary (the analytic cases): where the start surface
/// reaches beyond the solid (a build plate), cells beside the part get −distance too.
std::vector<double> signedBandDistances(const VoxelGrid& grid, const TriMesh& source);

/// Straight-line distance (mm) from the centres of the inside cells to the start surface where it
/// is at most `reach` mm, NaN elsewhere (for scikit-fmm peers on a start surface that reaches
/// beyond the solid, see model_vs_skfmm.py).
std::vector<double> insideSourceDistances(const VoxelGrid& grid, const TriMesh& source,
                                          double reach);

}  // namespace curvedslicer::testing
