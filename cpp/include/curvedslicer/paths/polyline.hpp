// Polylines: the raw form of every curve the path stage handles (initial curves, iso-lines,
// resampled paths) and small measurements on them.
//
// A polyline is an ordered list of points (part frame, mm); `closed` means the last point
// connects back to the first (the first point is not repeated at the end).
// Cost: every function is O(points) unless stated.
#pragma once

#include <cstddef>
#include <vector>

#include "curvedslicer/core/types.hpp"

namespace curvedslicer {

struct Polyline {
  std::vector<Vec3> points;  ///< part frame, mm; a closed polyline does not repeat its first point
  bool closed = false;       ///< the last point connects back to the first

  /// Number of segments: points − 1 (open) or points (closed, ≥ 3 points); 0 for < 2 points.
  std::size_t segmentCount() const;
  /// Total length, mm, including the closing segment of a closed polyline.
  double length() const;
  /// Segment i (0 ≤ i < segmentCount()): its start and end point.
  const Vec3& segmentStart(std::size_t i) const { return points[i]; }
  const Vec3& segmentEnd(std::size_t i) const { return points[(i + 1) % points.size()]; }
};

/// Closest point of a polyline to a query point.
struct PolylinePoint {
  Vec3 point = Vec3::Zero();  ///< part frame, mm
  std::size_t segment = 0;    ///< segment index holding `point`
  double parameter = 0.0;     ///< position within that segment, 0..1
  double distance = kInf;     ///< |query − point|, mm (+inf for a polyline without points)
};

/// Closest point on `polyline` (all its segments; a single point counts) to `p`. O(points).
PolylinePoint closestPointOnPolyline(const Polyline& polyline, const Vec3& p);

/// Arc length at every point, mm: result[0] = 0, result[i] = length up to point i; a closed
/// polyline gets one more entry, the total length (back at point 0).
std::vector<double> computeCumulativeLengths(const Polyline& polyline);

/// The point at arc length `s` (mm, clamped to [0, length]; wraps for closed polylines).
Vec3 evaluatePolylineAt(const Polyline& polyline, double s);

/// Smallest distance between two polylines, mm (segment–segment distances; O(n·m)).
double computePolylineDistance(const Polyline& a, const Polyline& b);

/// Largest distance from any point of `a` (its vertices and `samplesPerSegment` evenly spaced
/// points per segment) to polyline `b`, mm: a one-sided Hausdorff distance. O(n·m·samples).
double computeOneSidedHausdorff(const Polyline& a, const Polyline& b, int samplesPerSegment = 4);

/// True if two non-adjacent segments of the polyline come closer than `tolerance` (mm), i.e. the
/// polyline touches or crosses itself. O(n²).
bool hasSelfIntersection(const Polyline& polyline, double tolerance = 1e-9);

}  // namespace curvedslicer
