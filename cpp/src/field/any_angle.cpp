// Any-angle geodesic propagation (the accurate default).
//
// Dijkstra order over the 26-neighbourhood, but every cell carries a *parent*: a source triangle
// (distance = exact point–triangle distance) or a pivot cell (distance = pivot distance + straight
// segment). A cell inherits the parent of the neighbour that reaches it best (optimistically, as in
// Lazy Theta*, Nash et al. 2010); when the cell is popped the straight segment to its parent is
// checked for line of sight, and only if that fails the cell takes the best of (a) its finished
// neighbours' parents that it can see, and (b) a finished neighbour itself as a new pivot. Pivots
// therefore appear only where shortest paths bend around concave edges, so distances are exact
// straight-line distances wherever the source is visible, and the stencil bias of fixed-neighbour
// Dijkstra (ACCURACY.md) never accumulates.
//
// Line of sight: sphere tracing through the clearance field (exact EDT of the outside) while the
// segment is far from walls, exact cell walking (3D DDA over the inside mask) near walls.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/voxel/clearance.hpp"
#include "field_internal.hpp"

namespace curvedslicer::detail {

namespace {

constexpr std::uint8_t kDone = 1;
constexpr std::uint8_t kVerified = 2;
constexpr double kSqrt3 = 1.7320508075688772;

struct HeapItem {
  float d;
  std::uint32_t n;
};
struct HeapGreater {
  bool operator()(const HeapItem& a, const HeapItem& b) const {
    return a.d > b.d || (a.d == b.d && a.n > b.n);
  }
};

class AnyAnglePropagator {
 public:
  AnyAnglePropagator(const VoxelGrid& grid, const std::vector<Triangle>& source,
                     double seedBandCells, std::vector<float>& dist,
                     std::vector<std::int32_t>& parent, std::vector<float> clearance)
      : g_(grid.geometry),
        inside_(grid.inside),
        source_(source),
        slack_(seedBandCells),
        dist_(dist),
        parent_(parent),
        clearance_(std::move(clearance)),
        state_(dist.size(), 0) {
    const auto& offs = neighbourOffsets26();
    for (int o = 0; o < 26; ++o) {
      offsets_[o] = offs[o].cast<double>();
      lengths_[o] = offs[o].cast<double>().norm();
      deltas_[o] = static_cast<std::ptrdiff_t>(offs[o].x()) * g_.strideX() +
                   static_cast<std::ptrdiff_t>(offs[o].y()) * g_.strideY() + offs[o].z();
    }
  }

  MethodStats run(const std::vector<std::uint32_t>& seeds, Progress progress) {
    MethodStats stats;
    std::size_t insideCount = 0;
    for (std::uint8_t v : inside_) insideCount += v;
    heap_.reserve(seeds.size() * 4);
    for (std::uint32_t s : seeds) {
      state_[s] = kVerified;
      push(dist_[s], s);
    }
    std::size_t finished = 0;
    const std::size_t reportEvery = std::max<std::size_t>(insideCount / 200, 4096);
    while (!heap_.empty()) {
      std::pop_heap(heap_.begin(), heap_.end(), HeapGreater{});
      const HeapItem item = heap_.back();
      heap_.pop_back();
      const std::uint32_t n = item.n;
      if ((state_[n] & kDone) || item.d != dist_[n]) continue;  // stale entry
      const Vec3i c = g_.cell(n);
      const Vec3 x = cellCentre(c);
      if (!(state_[n] & kVerified)) {
        state_[n] |= kVerified;
        ++stats.lineOfSightTests;
        Vec3 target;
        evaluate(parent_[n], x, &target);
        if (!visible(x, target, slackFor(parent_[n]))) {
          ++stats.lineOfSightFailures;
          repair(n, x);
          push(dist_[n], n);  // its value grew: back into the queue, now verified
          continue;
        }
      }
      state_[n] |= kDone;
      if (++finished % reportEvery == 0) {
        progress.report(static_cast<double>(finished) / static_cast<double>(insideCount),
                        "geodesic field: any-angle propagation");
      }
      const std::int32_t p = parent_[n];
      for (int o = 0; o < 26; ++o) {
        const std::size_t m = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(n) + deltas_[o]);
        if (!inside_[m] || (state_[m] & kDone)) continue;
        const double cand = evaluate(p, x + offsets_[o], nullptr);
        if (cand < dist_[m]) {
          dist_[m] = static_cast<float>(cand);
          parent_[m] = p;
          state_[m] &= static_cast<std::uint8_t>(~kVerified);
          push(dist_[m], static_cast<std::uint32_t>(m));
        }
      }
    }
    return stats;
  }

 private:
  void push(float d, std::uint32_t n) {
    heap_.push_back({d, n});
    std::push_heap(heap_.begin(), heap_.end(), HeapGreater{});
  }

  /// Distance of point x (cell units) through parent `code`; the segment's far end in `target`.
  double evaluate(std::int32_t code, const Vec3& x, Vec3* target) const {
    if (code < 0) {
      const Triangle& t = source_[parentTriangle(code)];
      return pointTriangleDistance(x, t[0], t[1], t[2], target);
    }
    const Vec3 pc = cellCentre(g_.cell(static_cast<std::size_t>(code)));
    if (target) *target = pc;
    return dist_[static_cast<std::size_t>(code)] + (x - pc).norm();
  }

  /// The last stretch of a segment to a source triangle runs through cells cut by the start
  /// surface; seeds within the band are taken as visible, so that stretch is not checked.
  double slackFor(std::int32_t code) const { return code < 0 ? slack_ : 0.0; }

  /// Line-of-sight failure at cell n: best of the finished neighbours' parents that n can see and
  /// of the finished neighbours themselves as pivots.
  void repair(std::uint32_t n, const Vec3& x) {
    const std::int32_t failed = parent_[n];
    double best = kInf;
    std::int32_t bestParent = kNoParent;
    std::int32_t tried[26];
    int triedCount = 0;
    for (int o = 0; o < 26; ++o) {
      const std::size_t m = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(n) + deltas_[o]);
      if (!(state_[m] & kDone)) continue;
      const double viaPivot = dist_[m] + lengths_[o];
      if (viaPivot < best) {
        best = viaPivot;
        bestParent = static_cast<std::int32_t>(m);
      }
      const std::int32_t q = parent_[m];
      if (q == failed || std::find(tried, tried + triedCount, q) != tried + triedCount) continue;
      tried[triedCount++] = q;
      Vec3 target;
      const double viaParent = evaluate(q, x, &target);
      if (viaParent < best && visible(x, target, slackFor(q))) {
        best = viaParent;
        bestParent = q;
      }
    }
    if (bestParent == kNoParent) {
      // Cannot happen: a queued cell always has a finished neighbour or is a seed.
      throw NumericalFailure("any-angle propagation lost the parent of a voxel; please report");
    }
    dist_[n] = static_cast<float>(best);
    parent_[n] = bestParent;
  }

  bool insideCell(const Vec3& p, std::size_t* index) const {
    const int i = static_cast<int>(std::floor(p.x()));
    const int j = static_cast<int>(std::floor(p.y()));
    const int k = static_cast<int>(std::floor(p.z()));
    if (!g_.contains(i, j, k)) return false;
    *index = g_.index(i, j, k);
    return inside_[*index] != 0;
  }

  /// True if the segment from `from` (an inside cell centre) to `to`, minus its last `slack`
  /// cells, stays inside inside cells.
  bool visible(const Vec3& from, const Vec3& to, double slack) const {
    Vec3 d = to - from;
    const double len = d.norm();
    if (len <= slack + 1e-12) return true;
    d /= len;
    const double tEnd = len - slack;
    const Vec3 inv(d.x() != 0 ? 1.0 / d.x() : kInf, d.y() != 0 ? 1.0 / d.y() : kInf,
                   d.z() != 0 ? 1.0 / d.z() : kInf);
    double t = 0.0;
    while (t < tEnd) {
      const Vec3 p = from + t * d;
      std::size_t idx;
      if (!insideCell(p, &idx)) return false;
      const double safe = clearance_[idx] - kSqrt3;
      if (safe > 1.0) {
        t += safe;
        continue;
      }
      // Walk to the exit of the current cell.
      double step = kInf;
      for (int a = 0; a < 3; ++a) {
        if (d[a] == 0) continue;
        const double cellEdge = d[a] > 0 ? std::floor(p[a]) + 1.0 : std::floor(p[a]);
        step = std::min(step, (cellEdge - p[a]) * inv[a]);
      }
      t += std::max(step, 0.0) + 1e-7;
    }
    return true;
  }

  const GridGeometry& g_;
  const std::vector<std::uint8_t>& inside_;
  const std::vector<Triangle>& source_;
  double slack_;
  std::vector<float>& dist_;
  std::vector<std::int32_t>& parent_;
  std::vector<float> clearance_;
  std::vector<std::uint8_t> state_;
  std::vector<HeapItem> heap_;
  Vec3 offsets_[26];
  double lengths_[26];
  std::ptrdiff_t deltas_[26];
};

}  // namespace

MethodStats propagateAnyAngle(const VoxelGrid& grid, const std::vector<Triangle>& source,
                              const std::vector<std::uint32_t>& seeds, double seedBandCells,
                              std::vector<float>& dist, std::vector<std::int32_t>& parent,
                              Progress progress) {
  // Neighbour offsets are applied without bounds checks: computeGeodesicField has checked that
  // no inside cell touches the grid border.
  progress.report(0.0, "geodesic field: clearance");
  std::vector<float> clearance = computeClearance(grid, progress.sub(0.0, 0.1));
  AnyAnglePropagator propagator(grid, source, seedBandCells, dist, parent, std::move(clearance));
  return propagator.run(seeds, progress.sub(0.1, 1.0));
}

}  // namespace curvedslicer::detail
