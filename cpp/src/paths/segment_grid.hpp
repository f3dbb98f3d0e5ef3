// Internal: a uniform hash grid of 3D line segments for nearest-point queries bounded by a radius
// (deposition.cpp: the beads deposited so far). Segments are stored in every cell their bounding
// box overlaps; a query visits cube shells of cells around the query cell until the shell is
// farther than the best distance found or the radius. Exact (every segment that could be nearer is
// tested). Cost: insertion O(cells overlapped); query O(cells visited + segments in them).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "curvedslicer/core/types.hpp"

namespace curvedslicer::detail {

class SegmentGrid {
 public:
  explicit SegmentGrid(double cell) : cell_(cell > 0.0 ? cell : 1.0) {}

  bool empty() const { return a_.empty(); }

  void add(const Vec3& a, const Vec3& b) {
    const int id = static_cast<int>(a_.size());
    a_.push_back(a);
    b_.push_back(b);
    const Vec3i lo = cellOf(a.cwiseMin(b)), hi = cellOf(a.cwiseMax(b));
    for (int i = lo.x(); i <= hi.x(); ++i) {
      for (int j = lo.y(); j <= hi.y(); ++j) {
        for (int k = lo.z(); k <= hi.z(); ++k) cells_[key(i, j, k)].push_back(id);
      }
    }
    bounds_.extend(a);
    bounds_.extend(b);
  }

  /// Nearest point of any segment to `p` within `radius` (mm); returns false if none is within it.
  bool nearest(const Vec3& p, double radius, Vec3& point, double& distance) const {
    if (a_.empty()) return false;
    const Vec3i c = cellOf(p);
    // Largest shell worth visiting: the whole grid's bounds (in cells) or the radius.
    const Vec3i lo = cellOf(bounds_.min), hi = cellOf(bounds_.max);
    int maxShell = 0;
    for (int d = 0; d < 3; ++d) {
      maxShell = std::max({maxShell, std::abs(c[d] - lo[d]), std::abs(c[d] - hi[d])});
    }
    if (std::isfinite(radius)) {
      maxShell = std::min(maxShell, static_cast<int>(std::ceil(radius / cell_)) + 1);
    }
    double best = radius;
    bool found = false;
    for (int r = 0; r <= maxShell; ++r) {
      // Every point in shell r is at least (r − 1)·cell away from p.
      if (r >= 1 && (r - 1) * cell_ > best) break;
      for (int i = c.x() - r; i <= c.x() + r; ++i) {
        for (int j = c.y() - r; j <= c.y() + r; ++j) {
          const bool edgeIJ = std::abs(i - c.x()) == r || std::abs(j - c.y()) == r;
          // Rows inside the shell's i/j outline touch the shell only at its two z faces.
          const int kStep = edgeIJ || r == 0 ? 1 : 2 * r;
          for (int k = c.z() - r; k <= c.z() + r; k += kStep) {
            const auto it = cells_.find(key(i, j, k));
            if (it == cells_.end()) continue;
            for (const int id : it->second) {
              const Vec3 q = closestOnSegment(p, a_[id], b_[id]);
              const double d = (q - p).norm();
              if (d < best || (!found && d <= best)) {
                best = d;
                point = q;
                found = true;
              }
            }
          }
        }
      }
    }
    if (found) distance = best;
    return found;
  }

  double longestSegment() const {
    double m = 0.0;
    for (std::size_t i = 0; i < a_.size(); ++i) m = std::max(m, (b_[i] - a_[i]).norm());
    return m;
  }

 private:
  static Vec3 closestOnSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    if (len2 <= 0.0) return a;
    const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
    return a + t * ab;
  }

  Vec3i cellOf(const Vec3& p) const {
    return Vec3i(static_cast<int>(std::floor(p.x() / cell_)),
                 static_cast<int>(std::floor(p.y() / cell_)),
                 static_cast<int>(std::floor(p.z() / cell_)));
  }

  static std::uint64_t key(int i, int j, int k) {
    const auto u = [](int v) {
      return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)) & 0x1fffffu;
    };
    return (u(i) << 42) | (u(j) << 21) | u(k);
  }

  double cell_;
  std::vector<Vec3> a_, b_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
  Aabb bounds_;
};

}  // namespace curvedslicer::detail
