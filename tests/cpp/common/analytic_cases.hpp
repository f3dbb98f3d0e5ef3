// Closed-form geodesic-distance cases (ACCURACY.md) on voxel grids whose inside mask comes straight
// from the analytic solid (cell centre inside the solid), so the field methods are measured without
// voxelization effects. Used by the field tests and the field benchmark.
#pragma once

#include <functional>
#include <string>

#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/voxel/voxel_grid.hpp"

namespace curvedslicer::testing {

/// Model-aligned grid over `box` with 2 cells of padding; inside = `inside` at each cell centre.
VoxelGrid makeGridFromPredicate(const Aabb& box, double voxelSize,
                                const std::function<bool(const Vec3&)>& inside);

struct AnalyticCase {
  std::string name;
  VoxelGrid grid;  ///< model-aligned grid, padding 2
  TriMesh model;   ///< the solid's surface (tessellated finely), part frame
  TriMesh source;  ///< start surface, part frame
  std::function<double(const Vec3&)> exact;  ///< closed-form distance, mm, part frame
};

/// Slab 0 <= n·(x − x0) <= T, tilted against the grid axes, grown from its face n·(x − x0) = 0.
AnalyticCase makeTiltedSlabCase(int cellsAlongLongestSide = 128);
/// Shell R1 <= |x − c| <= R2 grown from the inner sphere: d = |x − c| − R1.
AnalyticCase makeSphericalShellCase(int cellsAlongLongestSide = 128);
/// L-shaped prism (legs [0,A]×[0,W] and [0,W]×[0,B], z in [0,H]) grown from the end face x = A
/// of leg 1; points of leg 2 reach it around the re-entrant edge x = y = W.
AnalyticCase makeLShapeCase(int cellsAlongLongestSide = 128);
/// U-bend: half annulus Ri <= r <= Ro, y >= 0, z in [0,H], grown from its end face y = 0, x > 0.
AnalyticCase makeUBendCase(int cellsAlongLongestSide = 128);
/// U-channel (makeUChannel: arms [0,A]×[0,W] and [0,A]×[B−W,B], base [0,W]×[0,B]) grown from the
/// end face x = A of the lower arm: points of the upper arm reach it around both reflex edges.
AnalyticCase makeUChannelCase(int cellsAlongLongestSide = 128);

struct FieldError {
  double mean = 0.0;     ///< mean |computed − exact| in units of L over reached inside voxels
  double max = 0.0;      ///< max |computed − exact| in units of L
  double maxOver = 0.0;  ///< max (computed − exact) / L (overestimate)
  double maxRelativeOver = 0.0;  ///< max (computed − exact − L) / exact (paper bound check)
  std::size_t voxels = 0;
  std::size_t unreached = 0;
  Vec3 worst = Vec3::Zero();  ///< part-frame centre of the voxel with the max error
};

/// Error of `field` against the case's closed form.
FieldError measureFieldError(const AnalyticCase& c, const DistanceField& field);

}  // namespace curvedslicer::testing
