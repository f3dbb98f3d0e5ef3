#include "curvedslicer/paths/deposition.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "segment_grid.hpp"

namespace curvedslicer {

void DepositionStats::add(const DepositionStats& other) {
  points += other.points;
  towardsSurface += other.towardsSurface;
  towardsBeads += other.towardsBeads;
  normalFallbacks += other.normalFallbacks;
  minDistance = std::min(minDistance, other.minDistance);
  maxDistance = std::max(maxDistance, other.maxDistance);
}

namespace {

double longestSegment(const Polyline& line) {
  double m = 0.0;
  for (std::size_t i = 0; i < line.segmentCount(); ++i) {
    m = std::max(m, (line.segmentEnd(i) - line.segmentStart(i)).norm());
  }
  return m;
}

void addSegments(detail::SegmentGrid& grid, const std::vector<Vec3>& points, bool closed) {
  if (points.size() == 1) grid.add(points[0], points[0]);
  for (std::size_t i = 0; i + 1 < points.size(); ++i) grid.add(points[i], points[i + 1]);
  if (closed && points.size() >= 3) grid.add(points.back(), points.front());
}

}  // namespace

DepositionStats assignDepositionDirections(std::vector<PlanPath>& paths,
                                           const DepositionSupport& support,
                                           const DepositionOptions& options) {
  // The grid cell: the longest segment of anything it will hold, so a query rarely visits more
  // than a few shells.
  double cell = options.gridCell;
  if (cell <= 0.0) {
    for (const Polyline& c : support.curves) cell = std::max(cell, longestSegment(c));
    if (support.earlierBeads) {
      for (const PlanPath& path : paths) {
        for (std::size_t i = 0; i + 1 < path.points.size(); ++i) {
          cell = std::max(cell, (path.points[i + 1].position - path.points[i].position).norm());
        }
      }
    }
    cell = std::max(cell, 1e-3);
  }
  detail::SegmentGrid beads(cell);
  for (const Polyline& c : support.curves) addSegments(beads, c.points, c.closed);

  const bool haveSurface = support.surface != nullptr && !support.surface->empty();
  DepositionStats stats;
  for (PlanPath& path : paths) {
    ClosestPoint hint;
    for (PathPoint& q : path.points) {
      if (!q.position.allFinite()) {
        throw InvalidInput("deposition direction: path point is not finite in layer " +
                           std::to_string(path.layer) + ", path " + std::to_string(path.index) +
                           "; check the layer surfaces");
      }
      double best = kInf;
      Vec3 target = q.position;
      bool onSurface = false;
      if (haveSurface) {
        hint = support.surface->closestPoint(q.position, hint);
        best = hint.distance;
        target = hint.point;
        onSurface = true;
      }
      Vec3 beadPoint;
      double beadDistance = kInf;
      if (beads.nearest(q.position, best, beadPoint, beadDistance) && beadDistance < best) {
        best = beadDistance;
        target = beadPoint;
        onSurface = false;
      }
      ++stats.points;
      if (!std::isfinite(best) || best < options.contactTolerance) {
        q.deposition = -q.normal.normalized();
        ++stats.normalFallbacks;
        continue;
      }
      q.deposition = (target - q.position).normalized();
      (onSurface ? stats.towardsSurface : stats.towardsBeads) += 1;
      stats.minDistance = std::min(stats.minDistance, best);
      stats.maxDistance = std::max(stats.maxDistance, best);
    }
    if (support.earlierBeads) {
      std::vector<Vec3> points;
      points.reserve(path.points.size());
      for (const PathPoint& q : path.points) points.push_back(q.position);
      addSegments(beads, points, path.closed);
    }
  }
  return stats;
}

}  // namespace curvedslicer
