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
///    on a source triangle (i.e. not beside its rim) get −distance if they lie behind it (on the
///    other side than the inside band cells closest to that triangle): the negative side that
///    skfmm needs to see a zero level set on the start surface. Where the start surface reaches
///    beyond the solid (a build plate under a curved bottom), those on the solid's side get
///    +distance, so that skfmm, which takes no seed values, still sees the start surface as its
///    zero level set there (it marches through that outside layer, at most √3·L thick). The
///    analytic cases' start surfaces lie on the solid's boundary and have no such cells.
std::vector<double> signedBandDistances(const VoxelGrid& grid, const TriMesh& source);

}  // namespace curvedslicer::testing
