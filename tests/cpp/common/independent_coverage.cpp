#include "common/independent_coverage.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

namespace curvedslicer::testing {
namespace {

struct Segment {
  Vec3 a, b;
  double halfA = 0.0, halfB = 0.0;  // half widths at a and b, mm
};

/// The segments of a layer's paths (closing segments of closed paths included) in a hash grid
/// of cells `reach` wide (the largest half width), each segment in every cell its box grown by
/// `reach` meets.
class SegmentHash {
 public:
  SegmentHash(const std::vector<PlanPath>& paths, double s, bool useWidths) {
    const auto half = [&](const PathPoint& p) {
      return useWidths && p.width > 0.0 ? 0.5 * p.width : 0.5 * s;
    };
    std::vector<Segment> segments;
    for (const PlanPath& path : paths) {
      const std::size_t n = path.points.size();
      if (n == 1 && useWidths) {
        const PathPoint& p = path.points[0];
        segments.push_back({p.position, p.position, half(p), half(p)});
      }
      if (n < 2) continue;
      const std::size_t count = path.closed ? n : n - 1;
      for (std::size_t i = 0; i < count; ++i) {
        const PathPoint& p = path.points[i];
        const PathPoint& q = path.points[(i + 1) % n];
        segments.push_back({p.position, q.position, half(p), half(q)});
      }
    }
    reach_ = 0.5 * s;
    for (const Segment& g : segments) reach_ = std::max({reach_, g.halfA, g.halfB});
    for (const Segment& g : segments) add(g);
  }
  /// True if a bead covers p.
  bool covers(const Vec3& p) const {
    const auto it = cells_.find(key(cellOf(p)));
    if (it == cells_.end()) return false;
    for (const std::size_t k : it->second) {
      const Segment& g = segments_[k];
      const Vec3 ab = g.b - g.a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((p - g.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      const double half = g.halfA + t * (g.halfB - g.halfA);
      if ((p - (g.a + t * ab)).norm() <= half) return true;
    }
    return false;
  }

 private:
  Eigen::Vector3i cellOf(const Vec3& p) const {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / reach_)),
                           static_cast<int>(std::floor(p.y() / reach_)),
                           static_cast<int>(std::floor(p.z() / reach_)));
  }
  static std::int64_t key(const Eigen::Vector3i& c) {
    return (static_cast<std::int64_t>(c.x() + 100000) * 200003 + (c.y() + 100000)) * 200003 +
           (c.z() + 100000);
  }
  void add(const Segment& g) {
    segments_.push_back(g);
    const Vec3 grow = Vec3::Constant(reach_);
    const Eigen::Vector3i lo = cellOf(g.a.cwiseMin(g.b) - grow);
    const Eigen::Vector3i hi = cellOf(g.a.cwiseMax(g.b) + grow);
    for (int x = lo.x(); x <= hi.x(); ++x) {
      for (int y = lo.y(); y <= hi.y(); ++y) {
        for (int z = lo.z(); z <= hi.z(); ++z) {
          cells_[key({x, y, z})].push_back(segments_.size() - 1);
        }
      }
    }
  }
  double reach_ = 0.0;
  std::vector<Segment> segments_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

}  // namespace

void addLayerCoverage(const TriMesh& mesh, const std::vector<PlanPath>& paths, double s,
                      Coverage& c, bool useWidths) {
  const SegmentHash hash(paths, s, useWidths);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3& a = mesh.vertices[mesh.triangles[t][0]];
    const Vec3& b = mesh.vertices[mesh.triangles[t][1]];
    const Vec3& d = mesh.vertices[mesh.triangles[t][2]];
    const double longest = std::max({(b - a).norm(), (d - b).norm(), (a - d).norm()});
    const int m = std::max(1, static_cast<int>(std::ceil(longest / 0.5)));
    const double sub = 0.5 * (b - a).cross(d - a).norm() / (m * m);
    for (int i = 0; i < m; ++i) {
      for (int j = 0; i + j < m; ++j) {
        // The upright sub-triangle (i, j) and, where it exists, the inverted one beside it.
        const Vec3 p = a + ((i + 1.0 / 3) * (b - a) + (j + 1.0 / 3) * (d - a)) / m;
        c.area += sub;
        if (!hash.covers(p)) c.voidArea += sub;
        if (i + j + 1 < m) {
          const Vec3 q = a + ((i + 2.0 / 3) * (b - a) + (j + 2.0 / 3) * (d - a)) / m;
          c.area += sub;
          if (!hash.covers(q)) c.voidArea += sub;
        }
      }
    }
  }
}

}  // namespace curvedslicer::testing
