// Test helpers shared by the robot tests (travel, collision, cells): straight synthetic paths, the
// brute-force point-to-segment distance the independent checks use, and the distance of a point
// from a positioner's table and working volume.
#pragma once

#include <algorithm>
#include <cmath>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/plan/plan.hpp"
#include "curvedslicer/robot/cell.hpp"

namespace curvedslicer::robot_test {

/// One straight path from `a` to `b` (points 1 mm apart), V = -z, normal +z.
inline PlanPath straightPath(const Vec3& a, const Vec3& b) {
  PlanPath path;
  const int n = std::max(2, static_cast<int>(std::ceil((b - a).norm())) + 1);
  for (int i = 0; i < n; ++i) {
    PathPoint p;
    p.position = a + (b - a) * (static_cast<double>(i) / (n - 1));
    p.normal = Vec3::UnitZ();
    p.deposition = -Vec3::UnitZ();
    path.points.push_back(p);
  }
  path.length = (b - a).norm();
  return path;
}

/// Distance from `x` to the segment [a, b] (a degenerate segment is its point).
inline double distanceToSegment(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = std::clamp(len2 > 0 ? (x - a).dot(d) / len2 : 0.0, 0.0, 1.0);
  return (a + t * d - x).norm();
}

/// Distance of a point (table frame) from the solid cylinder made of the table disc and the
/// working volume above it.
inline double distanceFromTableAndVolume(const PositionerGeometry& g, const Vec3& p) {
  const double radius = std::max(g.tableRadius, g.maxPartRadius);
  const double dr = std::max(std::hypot(p.x(), p.y()) - radius, 0.0);
  const double dz = std::max({-g.tableThickness - p.z(), p.z() - g.maxPartHeight, 0.0});
  return std::hypot(dr, dz);
}

}  // namespace curvedslicer::robot_test
