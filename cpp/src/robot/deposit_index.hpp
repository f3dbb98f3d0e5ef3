// Internal to robot/: the material deposited so far, as capsules around the welded path segments,
// in a uniform grid over the part-frame box of the plan. Built incrementally in execution order
// (each weld move appends its segment after the move is checked), queried with a segment and a
// radius: the smallest surface distance of the beads within reach. Shared by the travel planner
// (TCP clearance) and the collision check (torch envelope).
//
// Structure: consecutive segments of one path form chunks of at most kChunkSegments segments
// with a bounding sphere; every grid cell a chunk's segments touch (box of the segment grown by
// the bead radius) lists the chunk. A query visits the cells of its own grown box, culls chunks
// by their sphere and measures the segments of the rest exactly (closest points of two
// segments). Cost: insert O(cells touched); query O(cells in the query box + candidates).
// Not thread-safe (queries stamp visited chunks).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "curvedslicer/core/types.hpp"

namespace curvedslicer::detail {

/// Distance between the closest points of segments [p0, p1] and [q0, q1] (mm); degenerate
/// segments are points.
double segmentDistance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

/// Distance of point x from segment [a, b].
double pointSegmentDistance(const Vec3& x, const Vec3& a, const Vec3& b);

/// One welded segment and the path it belongs to.
struct DepositSegment {
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  int layer = 0;
  int path = 0;
};

/// The nearest bead found by a query.
struct DepositHit {
  double distance = kInf;   ///< mm, query segment to bead surface (axis distance - bead radius)
  std::size_t segment = 0;  ///< index into DepositIndex::segments()
  bool found() const { return distance < kInf; }
};

class DepositIndex {
 public:
  /// `bounds`: part-frame box that holds every segment that will be added (grown by the bead
  /// radius inside); `beadRadius` mm (> 0); `cellSize` mm (> 0, raised when the grid would
  /// exceed `maxCells`).
  DepositIndex(const Aabb& bounds, double beadRadius, double cellSize,
               std::size_t maxCells = std::size_t{1} << 21);

  /// Appends a welded segment; `newPath` starts a new chunk (first segment of a path).
  void add(const DepositSegment& segment, bool newPath);

  /// The bead nearest to segment [p, q] among those whose surface lies closer than `reach`
  /// (mm); DepositHit{} (infinite distance) when none does.
  DepositHit nearest(const Vec3& p, const Vec3& q, double reach) const;

  /// True when some bead's surface lies closer than `reach` to segment [p, q] (stops at the
  /// first one; `hit` gets it).
  bool anyWithin(const Vec3& p, const Vec3& q, double reach, DepositHit* hit = nullptr) const;

  /// Calls `visit(segment, distance)` for every bead whose surface lies closer than `reach` to
  /// segment [p, q] (`distance`: that surface distance), in no particular order, until `visit`
  /// returns false. With a unit `above` (not zero), beads whose axis lies wholly below the plane
  /// above · x = level (by whole chunks, then segment by segment) are skipped.
  void forEachWithin(const Vec3& p, const Vec3& q, double reach,
                     const std::function<bool(std::size_t, double)>& visit,
                     const Vec3& above = Vec3::Zero(), double level = 0.0) const;

  const std::vector<DepositSegment>& segments() const { return segments_; }
  double beadRadius() const { return radius_; }
  /// Box of the axes of every segment added (visible or not); empty before the first.
  const Aabb& extent() const { return extent_; }

  /// Queries see only the first `count` segments added (the deposit before a given move when
  /// a whole path has been added ahead); SIZE_MAX (the default) sees all.
  void setVisible(std::size_t count) { visible_ = count; }

 private:
  struct Chunk {
    std::size_t first = 0;  // first segment
    std::size_t count = 0;
    Aabb box;  // of the segment end points
  };
  template <typename Visit>
  void visitCandidates(const Vec3& p, const Vec3& q, double reach, Visit&& visit) const {
    visitCandidates(p, q, reach, visit, [](const Aabb&) { return true; });
  }
  /// As above; chunks whose box `keep` refuses are skipped.
  template <typename Visit, typename Keep>
  void visitCandidates(const Vec3& p, const Vec3& q, double reach, Visit&& visit,
                       Keep&& keep) const;
  bool cellRange(const Aabb& box, Vec3i& lo, Vec3i& hi) const;
  std::size_t cellIndex(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * dims_.y() + static_cast<std::size_t>(y)) * dims_.x() +
           static_cast<std::size_t>(x);
  }

  Vec3 origin_;
  Vec3i dims_;
  double cell_ = 1.0;
  double radius_ = 1.0;
  std::vector<std::vector<std::uint32_t>> cells_;  // chunk ids per cell
  std::vector<DepositSegment> segments_;
  std::vector<Chunk> chunks_;
  Aabb extent_;
  mutable std::vector<std::uint32_t> stamp_;  // per chunk: last query that visited it
  mutable std::uint32_t query_ = 0;
  std::size_t visible_ = static_cast<std::size_t>(-1);
};

}  // namespace curvedslicer::detail
