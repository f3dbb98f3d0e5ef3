#include "curvedslicer/paths/deposition.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "curvedslicer/core/error.hpp"
#include "segment_grid.hpp"

namespace curvedslicer {

void DepositionStats::add(const DepositionStats& other) {
  points += other.points;
  towardsSurface += other.towardsSurface;
  towardsBeads += other.towardsBeads;
  normalFallbacks += other.normalFallbacks;
  growthCorrections += other.growthCorrections;
  normalsOverruled += other.normalsOverruled;
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

/// The layer below's points and V in a uniform hash grid of cells one radius wide: the
/// distance-weighted mean V within the radius of a point (Growth).
class GrowthBelow {
 public:
  GrowthBelow(const std::vector<PlanPath>* below, double radius)
      : radius_(radius > 0.0 ? radius : 1.0) {
    if (below == nullptr || !(radius > 0.0)) return;
    for (const PlanPath& path : *below) {
      for (const PathPoint& q : path.points) {
        if (!q.position.allFinite() || !q.deposition.allFinite()) continue;
        cells_[key(cellOf(q.position))].push_back(static_cast<int>(points_.size()));
        points_.push_back(q.position);
        directions_.push_back(q.deposition);
      }
    }
  }

  /// The weighted mean V around `p` (unit), or false when no point of the layer below is within
  /// the radius or their directions cancel.
  bool mean(const Vec3& p, Vec3& direction) const {
    if (points_.empty()) return false;
    const Vec3i c = cellOf(p);
    Vec3 sum = Vec3::Zero();
    for (int i = c.x() - 1; i <= c.x() + 1; ++i) {
      for (int j = c.y() - 1; j <= c.y() + 1; ++j) {
        for (int k = c.z() - 1; k <= c.z() + 1; ++k) {
          const auto it = cells_.find(key(Vec3i(i, j, k)));
          if (it == cells_.end()) continue;
          for (const int id : it->second) {
            const double d = (points_[id] - p).norm();
            if (d >= radius_) continue;
            const double w = (1.0 - d / radius_) * (1.0 - d / radius_);
            sum += w * directions_[id];
          }
        }
      }
    }
    if (!(sum.norm() > 1e-9)) return false;
    direction = sum.normalized();
    return true;
  }

 private:
  Vec3i cellOf(const Vec3& p) const {
    return Vec3i(static_cast<int>(std::floor(p.x() / radius_)),
                 static_cast<int>(std::floor(p.y() / radius_)),
                 static_cast<int>(std::floor(p.z() / radius_)));
  }
  static std::int64_t key(const Vec3i& c) {
    constexpr std::int64_t kSpan = 1 << 20;
    return ((static_cast<std::int64_t>(c.x()) + kSpan) * 2 * kSpan +
            (static_cast<std::int64_t>(c.y()) + kSpan)) *
               2 * kSpan +
           (static_cast<std::int64_t>(c.z()) + kSpan);
  }

  double radius_;
  std::vector<Vec3> points_, directions_;
  std::unordered_map<std::int64_t, std::vector<int>> cells_;
};

double directionAngle(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
}

/// Growth: the paper's V `nearest` at `q`, or the growth direction where it strays from it.
Vec3 growthOrNearest(const PathPoint& q, const Vec3& nearest, const GrowthBelow& below,
                     double maxDeviation, DepositionStats& stats) {
  Vec3 growth = -q.normal.normalized();
  Vec3 mean;
  if (below.mean(q.position, mean) && directionAngle(growth, mean) > maxDeviation) {
    growth = mean;
    ++stats.normalsOverruled;
  }
  if (directionAngle(nearest, growth) <= maxDeviation) return nearest;
  ++stats.growthCorrections;
  return growth;
}

}  // namespace

const char* depositionMethodName(DepositionMethod method) {
  return method == DepositionMethod::Nearest ? "nearest" : "growth";
}

DepositionMethod parseDepositionMethod(const std::string& name) {
  if (name == "nearest") return DepositionMethod::Nearest;
  if (name == "growth") return DepositionMethod::Growth;
  throw InvalidInput("deposition direction method \"" + name +
                     "\" is not known; use growth (the default: the paper's V where it follows the "
                     "layer's growth) or nearest (the paper's V everywhere)");
}

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
  const bool growth = options.method == DepositionMethod::Growth;
  const GrowthBelow below(growth ? support.below : nullptr, support.belowRadius);
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
      const double margin =
          growth && support.surfaceIsSubstrate && onSurface ? support.substrateMargin : 0.0;
      if (beads.nearest(q.position, best, beadPoint, beadDistance) &&
          beadDistance + margin < best) {
        best = beadDistance;
        target = beadPoint;
        onSurface = false;
      }
      ++stats.points;
      if (!std::isfinite(best) || best < options.contactTolerance) {
        q.deposition = -q.normal.normalized();
        if (growth)
          q.deposition = growthOrNearest(q, q.deposition, below, options.maxDeviation, stats);
        ++stats.normalFallbacks;
        continue;
      }
      q.deposition = (target - q.position).normalized();
      if (growth && !(onSurface && support.surfaceIsSubstrate))
        q.deposition = growthOrNearest(q, q.deposition, below, options.maxDeviation, stats);
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
