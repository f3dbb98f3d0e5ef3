// Closing the holes of an open mesh so that it bounds a solid: every boundary loop (a cycle of
// edges used by one triangle only) gets a cap of concentric rings around the loop's centroid,
// oriented consistently with the triangles along the loop.
//
// A loop that lies on the start surface (every loop vertex within `onSurfaceTolerance` of it) is
// capped *on* that surface: the cap's interior vertices are projected onto the start surface
// along the loop's normal (closest point where no ray hits), with rings `ringSpacing` apart, so a
// part whose open bottom sits on a curved base plate becomes the solid between its walls and the
// plate. Other loops get a plain centroid fan (exact for planar, star-shaped holes).
//
// Preconditions: a welded mesh (see cleanMesh); boundary vertices with more than one outgoing
// boundary edge (pinched boundaries) are left open and counted. Cost: O(T + C log S) for T model
// triangles, C cap vertices and S start-surface triangles.
#pragma once

#include <cstddef>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

struct HoleCappingOptions {
  /// mm; radial spacing of the cap rings on the start surface (the layer job uses the voxel size).
  double ringSpacing = 1.0;
  /// mm; a loop counts as lying on the start surface when all its vertices are this close to it.
  double onSurfaceTolerance = 0.1;
  /// Upper bound on the rings of one cap (keeps tiny spacings on huge holes bounded).
  int maxRings = 512;
};

struct HoleCappingResult {
  TriMesh mesh;                         ///< input triangles, then the caps (face id −1)
  std::size_t loops = 0;                ///< boundary loops found
  std::size_t cappedLoops = 0;          ///< of which capped
  std::size_t loopsOnStartSurface = 0;  ///< of the capped loops, those capped on the start surface
  std::size_t capTriangles = 0;
  std::size_t openBoundaryEdges = 0;  ///< boundary edges left open (pinched boundaries)
};

/// @param mesh          welded triangle mesh, part frame, mm
/// @param startSurface  start-surface triangles, part frame (may be empty)
/// @throws InvalidInput for non-positive or non-finite spacing or tolerance.
HoleCappingResult capHoles(const TriMesh& mesh, const TriMesh& startSurface,
                           const HoleCappingOptions& options = {});

}  // namespace curvedslicer
