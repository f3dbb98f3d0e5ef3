// Ordering the paths of one layer: the deposition order, the direction of open
// paths and the seam (start point) of closed rings, so that travel between paths is short and
// seams do not stack from layer to layer.
//
// Method: greedy nearest neighbour from the torch position (the end of the previous layer, or
// `start`), then 2-opt passes on the sequence. Entering an open path costs the distance to its
// nearer end (the path is reversed when entering at its last point, so neighbouring open paths
// alternate direction where that saves travel); a closed ring stays closed and keeps its
// direction, entered and left at its seam. A ring's seam is chosen among its points at least
// `seamSeparation` (mm, straight-line) away from every seam of the previous layer, nearest to the
// torch; if no point qualifies (the ring is too short or lies among the previous seams) the point
// farthest from them is taken and the path is counted in `seamsTooClose`. The seams of open paths
// are their first points (not movable). Each path is one arc start, so the number of arc starts
// equals the number of paths; nothing is merged here — the planner then joins consecutive rings
// (paths/connected_insets.hpp), whose joined path starts at its first ring's seam chosen here.
// Preconditions: every path has at least 2 points (closed rings at least 3), finite coordinates.
// Cost: O(n²·m) for n paths of m points (greedy entry search) plus O(n²) per 2-opt pass.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

struct OrderingOptions {
  /// mm; smallest straight-line distance between a ring's seam and the previous layer's seams
  /// (the planner passes 2·s). 0 disables staggering.
  double seamSeparation = 0.0;
  /// 2-opt improvement passes over the greedy order (0: greedy only).
  int improvementPasses = 4;
};

/// How one input path is deposited.
struct OrderedPath {
  std::size_t source = 0;     ///< index into the input paths
  bool reversed = false;      ///< open paths: deposited from the last point to the first
  std::size_t seam = 0;       ///< closed rings: index of the first deposited point (0 for open)
  bool seamTooClose = false;  ///< the seam could not keep `seamSeparation` (see file comment)
};

struct LayerOrder {
  std::vector<OrderedPath> paths;  ///< deposition order
  double travel = 0.0;             ///< mm, straight-line travel from `start` through all paths
  std::size_t seamsTooClose = 0;   ///< rings whose seam could not keep `seamSeparation`
  std::vector<Vec3> seams;         ///< first deposited point of every path, in deposition order
  Vec3 end = Vec3::Zero();         ///< where the torch is after the last path
};

/// Orders one layer's paths (see the file comment).
/// @param paths          the layer's paths, part frame, mm
/// @param start          torch position before the layer (e.g. the previous layer's end); none:
///                       the first point of paths[0]
/// @param previousSeams  seams of the previous layer (LayerOrder::seams of it), may be empty
/// @throws InvalidInput for a path with too few points.
LayerOrder orderLayerPaths(const std::vector<Polyline>& paths, const std::optional<Vec3>& start,
                           const std::vector<Vec3>& previousSeams,
                           const OrderingOptions& options = {});

/// The points of `path` in deposition order according to `order` (open: reversed if so; closed:
/// rotated to start at the seam). Works for any per-point data aligned with the path's points.
template <typename T>
std::vector<T> applyOrder(const std::vector<T>& values, bool closed, const OrderedPath& order) {
  std::vector<T> out;
  out.reserve(values.size());
  if (closed) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      out.push_back(values[(order.seam + i) % values.size()]);
    }
  } else if (order.reversed) {
    out.assign(values.rbegin(), values.rend());
  } else {
    out = values;
  }
  return out;
}

}  // namespace curvedslicer
