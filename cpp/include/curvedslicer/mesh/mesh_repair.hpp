// Cleaning a triangle soup into an indexed mesh: vertex welding with a tolerance relative to the
// model size, removal of degenerate and duplicated triangles. Cost O(n log n).
//
// Welding visits the vertices in index order; each joins the lowest-index representative within
// the tolerance (found through a spatial hash), or becomes a representative itself. So every
// merged vertex lies within the tolerance of the position it takes (no transitive chains), and
// the result does not depend on hash order. Representatives keep their own positions. The output
// keeps only vertices used by a surviving triangle, in input order; triangles stay in input
// order.
#pragma once

#include <cstddef>
#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

struct CleanOptions {
  /// Vertices closer than this fraction of the bounding-box diagonal are merged. 0 merges only
  /// bit-identical positions.
  double relativeWeldTolerance = 1e-6;
  /// Triangles with a repeated vertex after welding, or area below 1e-12·diag² (the threshold
  /// analyzeMesh uses).
  bool removeDegenerate = true;
  bool removeDuplicates = true;  ///< triangles over the same three vertices (keeps the first)
};

struct CleanResult {
  TriMesh mesh;                    ///< faceIds carried over from the input (when present)
  std::size_t mergedVertices = 0;  ///< input vertices merged into another
  std::size_t degenerateTriangles = 0;
  std::size_t duplicateTriangles = 0;          ///< same orientation as the kept copy
  std::size_t oppositeDuplicateTriangles = 0;  ///< opposite orientation to the kept copy
  double weldTolerance = 0.0;                  ///< mm, the absolute tolerance used
};

/// Representative of each vertex: the lowest index with the bit-identical position. O(n log n).
std::vector<int> findExactDuplicateVertices(const std::vector<Vec3>& vertices);

/// @throws InvalidInput for non-finite coordinates or out-of-range indices.
CleanResult cleanMesh(const TriMesh& mesh, const CleanOptions& options = {});

}  // namespace curvedslicer
