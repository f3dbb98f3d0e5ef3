// Rigid frames, and the PCA frame of paper §2.1 ("the length, width and height directions of the
// bounding box are rotated to the X, Y and Z axes").
#pragma once

#include <string_view>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

/// A rigid frame: `rotation` columns are the frame's axes expressed in the part frame, `origin`
/// is the frame's origin in the part frame.
struct Frame {
  Mat3 rotation = Mat3::Identity();
  Vec3 origin = Vec3::Zero();

  /// Part-frame point -> frame coordinates.
  Vec3 toFrame(const Vec3& p) const { return rotation.transpose() * (p - origin); }
  /// Frame coordinates -> part-frame point.
  Vec3 toPart(const Vec3& q) const { return rotation * q + origin; }
  /// Frame direction -> part-frame direction.
  Vec3 directionToPart(const Vec3& d) const { return rotation * d; }
};

/// How the voxel grid is oriented.
enum class GridAlignment {
  Pca,    ///< principal axes of the surface (paper §2.1), largest extent first
  Model,  ///< the model's own axes
};

/// "pca" | "model" (the command line's, the workbench's and the report's names).
std::string_view toString(GridAlignment alignment);
/// Parses "pca" or "model" (case and surrounding spaces ignored).
/// @throws InvalidInput listing the choices.
GridAlignment parseGridAlignment(std::string_view name);

/// Principal-axis frame of a triangle surface.
///
/// Uses the exact second moments of the surface (area-weighted, integrated over each triangle), so
/// the result does not depend on how finely the surface is tessellated. Origin: area centroid.
/// Axes ordered by decreasing variance (x = longest direction), right-handed, each signed so its
/// largest-magnitude component is positive; axes whose variances agree within 1e-9 (relative)
/// snap to the model axes where possible so symmetric parts keep an axis-aligned grid.
/// @throws InvalidInput for an empty or zero-area mesh.
Frame computePcaFrame(const TriMesh& mesh);

}  // namespace curvedslicer
