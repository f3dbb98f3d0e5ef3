// Curved layers from the geodesic field (paper §2.3).
//
// Layer i (i = 1, 2, …) is the iso-surface d = i·h of the field. Two representations:
//  - the paper's voxel sets S_i = {P : i·h − L/2 ≤ t_P ≤ i·h + L/2} (eq. 13);
//  - a triangle surface: marching tetrahedra (consistent Kuhn decomposition of each cube, so the
//    surface is watertight without ambiguous cases) on the field extended a few cells beyond the
//    solid, then clipped to the solid by the signed distance to the model surface, with rim
//    vertices projected onto the model surface.
// Per layer: area, triangle count, connected components and the measured thickness to the
// previous layer (distances from this layer's vertices to the previous surface; for layer 1 the
// start surface).
#pragma once

#include <cstddef>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"
#include "curvedslicer/voxel/voxel_grid.hpp"

namespace curvedslicer {

struct LayerOptions {
  double layerThickness = 1.0;  ///< h, mm (> 0)
  bool clipToSolid = true;      ///< clip surfaces to the model and project rims onto it
  int maxLayers = 100000;       ///< safety limit; more layers is an InvalidInput error
};

struct ThicknessStats {
  std::size_t samples = 0;  ///< vertices measured (0 if there is no previous surface)
  double min = 0.0, mean = 0.0, max = 0.0;  ///< mm
};

struct LayerSurface {
  int index = 0;       ///< i, 1-based
  double level = 0.0;  ///< i·h, mm
  TriMesh mesh;        ///< part frame
  double area = 0.0;   ///< mm²
  std::size_t components = 0;
  ThicknessStats thicknessToPrevious;
};

/// The paper's voxel set S_i (eq. 13).
struct VoxelLayerSet {
  int index = 0;
  double level = 0.0;
  std::vector<std::size_t> cells;  ///< linear cell indices into the grid
};

struct LayersResult {
  std::vector<LayerSurface> surfaces;
  std::vector<VoxelLayerSet> voxelSets;
};

/// @param field   geodesic field (its geometry matches `grid`)
/// @param grid    the voxelized solid
/// @param model   the solid's surface, part frame (for clipping and rim projection)
/// @param source  the start surface triangles (thickness reference of layer 1)
/// @throws InvalidInput for h <= 0 or more than `maxLayers` layers.
LayersResult extractLayers(const DistanceField& field, const VoxelGrid& grid, const TriMesh& model,
                           const TriMesh& source, const LayerOptions& options = {},
                           Progress progress = {});

}  // namespace curvedslicer
