// Any-angle geodesic propagation (the accurate default).
//
// Every cell carries a *parent*: a source triangle (distance = exact point–triangle distance) or a
// pivot point (distance = pivot distance + straight segment). Three phases:
//  1. parent inheritance: Dijkstra order over the 26-neighbourhood from the seeds; a cell takes
//     the source triangle of the neighbour that reaches it best, untested (sequential, cheap);
//  2. line of sight: every inherited segment is tested, strictly; cells that see their parent are
//     final (their distance is a straight path inside the solid), the others are reset (parallel);
//  3. shadow: the reset cells in Dijkstra order from the finished ones, as Lazy Theta* (Nash et
//     al. 2010): a cell inherits the parent of the neighbour that reaches it best, the segment is
//     tested when the cell is popped, and only if that fails the cell takes the best of
//       (a) the parents of its finished neighbours that it can see,
//       (b) a new pivot on a reflex (concave) edge of the model within reach, placed at the point
//           of the edge that minimises parent distance + segment (shortest paths inside a
//           polyhedron bend only at reflex edges and vertices, so this pivot is where the true
//           path bends), and
//       (c) a finished neighbour's centre as a pivot (the fallback when no model surface is given).
// Pivots therefore appear only where shortest paths bend around concave edges; elsewhere distances
// are exact straight-line distances, and the stencil bias of fixed-neighbour Dijkstra
// (ACCURACY.md) never accumulates. Cost: phase 1 O(N log C) with a radix heap; phase 2 one segment
// test per cell on all cores; phase 3 a test per shadow cell plus repairs.
//
// Line of sight: sphere tracing through the clearance field (exact EDT of the outside) far from
// walls; near walls, with the model surface, an exact test of the segment against the surface
// triangles in the bricks it passes; without it, exact cell walking.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/voxel/clearance.hpp"
#include "field_internal.hpp"
#include "solid_boundary.hpp"

namespace curvedslicer::detail {

namespace {

constexpr std::uint8_t kDone = 1;
constexpr std::uint8_t kVerified = 2;
/// The cell is inside the solid (a copy of the mask, so relaxations read one byte per neighbour).
constexpr std::uint8_t kInside = 4;
/// Phase 1: inheriting line of sight failed because a reflex edge meets the swept region (the
/// cell is at the edge of a shadow; phase 2 tests it).
constexpr std::uint8_t kShadowEdge = 8;
/// Phase 1: every neighbour it could inherit line of sight from is at or behind a shadow edge;
/// phase 2 hands it to phase 3 without a test.
constexpr std::uint8_t kShadowDown = 16;
constexpr double kSqrt3 = 1.7320508075688772;
constexpr double kHalfSqrt3 = 0.5 * kSqrt3;
/// Reflex edges considered at a line-of-sight failure lie within this many cells of the cell or
/// of the point where its blocked segment meets the surface.
constexpr double kEdgeReach = 2.5;
/// A chord between two points of the surface may dip this many cells outside the solid.
constexpr double kChordDepth = 0.02;
/// Line of sight is inherited from a neighbour (see inheritsLineOfSight) only on closed models
/// with at most this many reflex edges, which are then all tested per cell.
constexpr std::size_t kInheritMaxReflexEdges = 64;
/// Phase 2 runs its segment tests on all threads only when at least this many are pending.
constexpr std::size_t kParallelTestsMin = 20000;
/// Geometric tolerance of the inheritance test, cells (any doubt makes it fall back).
constexpr double kInheritTolerance = 1e-6;

/// Candidate::edge of a repair's placeholder for the pivots through one parent (see repair).
constexpr std::int32_t kExpandParent = -2;

struct Candidate {
  double value;         // total distance via this option, cells (a lower bound for a placeholder)
  std::int32_t parent;  // parent of the option (or of the new pivot)
  std::int32_t edge;    // reflex edge of a new pivot, -1 for "take the parent directly",
                        // kExpandParent for the pivots through `parent` not yet valued
  Vec3 point;           // the new pivot's position
};

struct HeapItem {
  float d;
  std::uint32_t n;
};

/// Monotone priority queue of (distance, cell) — a radix heap (Ahuja, Mehlhorn, Orlin & Tarjan
/// 1990) on the bit patterns of non-negative floats, which order like the floats. Bucket b > 0
/// holds keys whose highest bit differing from the last popped key is b − 1; a pop empties the
/// lowest non-empty bucket into lower ones, so each item moves at most 32 times and push is O(1).
/// Dijkstra-like propagation may offer a key below the last popped one (a neighbour that is
/// nearer the source than the cell being finished but was reached late); it is queued at the last
/// popped key, i.e. popped next. Deterministic: ties pop in a fixed order.
class RadixQueue {
 public:
  bool empty() const { return size_ == 0; }
  void push(float d, std::uint32_t n) {
    std::uint32_t key = keyOf(d);
    if (key < last_) key = last_;
    buckets_[bucketOf(key)].push_back({key, d, n});
    ++size_;
  }
  HeapItem pop() {
    settle();
    const Entry e = buckets_[0].back();
    buckets_[0].pop_back();
    --size_;
    return {e.d, e.n};
  }
  void clear() {
    for (auto& b : buckets_) std::vector<Entry>().swap(b);
    size_ = 0;
    last_ = 0;
  }

 private:
  /// Makes bucket 0 non-empty (precondition: not empty).
  void settle() {
    if (buckets_[0].empty()) {
      int b = 1;
      while (buckets_[b].empty()) ++b;
      std::uint32_t lowest = UINT32_MAX;
      for (const Entry& e : buckets_[b]) lowest = std::min(lowest, e.key);
      last_ = lowest;
      for (const Entry& e : buckets_[b]) buckets_[bucketOf(e.key)].push_back(e);
      buckets_[b].clear();
    }
  }

  struct Entry {
    std::uint32_t key;
    float d;
    std::uint32_t n;
  };
  static std::uint32_t keyOf(float d) {
    std::uint32_t k;
    std::memcpy(&k, &d, sizeof k);
    return k;  // d >= 0 (and +inf never queued): the bit patterns order like the values
  }
  int bucketOf(std::uint32_t key) const {
    return key == last_ ? 0 : 32 - std::countl_zero(key ^ last_);
  }
  std::array<std::vector<Entry>, 33> buckets_;
  std::uint32_t last_ = 0;
  std::size_t size_ = 0;
};

/// A byte per grid cell in tiles of 4 × 4 × 4 cells, one cache line each: sphere tracing's short
/// steps near walls then mostly stay within a line. The same values as the row-major array, so
/// the same steps.
class TiledBytes {
 public:
  /// `linear`: one byte per cell of a grid of `dims`, row-major (VoxelGrid::index); released
  /// once copied, so the peak is one extra byte per cell only while copying.
  TiledBytes(const Vec3i& dims, std::vector<std::uint8_t>&& linear)
      : tiles_((dims.array() + 3) / 4),
        bytes_(static_cast<std::size_t>(tiles_.x()) * tiles_.y() * tiles_.z() * 64, 0) {
    for (int i = 0; i < dims.x(); ++i)
      for (int j = 0; j < dims.y(); ++j)
        for (int k = 0; k < dims.z(); ++k)
          bytes_[offset(i, j, k)] =
              linear[(static_cast<std::size_t>(i) * dims.y() + j) * dims.z() + k];
    std::vector<std::uint8_t>().swap(linear);
  }
  std::uint8_t at(int i, int j, int k) const { return bytes_[offset(i, j, k)]; }

 private:
  std::size_t offset(int i, int j, int k) const {
    const std::size_t tile =
        (static_cast<std::size_t>(i >> 2) * tiles_.y() + (j >> 2)) * tiles_.z() + (k >> 2);
    return tile * 64 + static_cast<std::size_t>(((i & 3) << 4) | ((j & 3) << 2) | (k & 3));
  }
  Vec3i tiles_;
  std::vector<std::uint8_t> bytes_;
};

struct Pivot {
  Vec3 position;  // cell units
  double distance;
  std::int32_t edge = -1;  // reflex edge the pivot lies on, -1 for a cell-centre pivot
};

class AnyAnglePropagator {
 public:
  AnyAnglePropagator(const VoxelGrid& grid, const std::vector<Triangle>& source,
                     double seedBandCells, std::vector<float>& dist,
                     std::vector<std::int32_t>& parent, const SolidBoundary* boundary,
                     std::vector<std::uint8_t> clearance)
      : g_(grid.geometry),
        inside_(grid.inside),
        source_(source),
        slack_(seedBandCells),
        dist_(dist),
        parent_(parent),
        boundary_(boundary),
        clearance_(grid.geometry.dims, std::move(clearance)),
        state_(dist.size(), 0) {
    for (std::size_t n = 0; n < state_.size(); ++n) state_[n] = inside_[n] ? kInside : 0;
    if (boundary_) mailbox_ = boundary_->makeMailbox();
    inheritSight_ = boundary_ && boundary_->closedManifold() &&
                    boundary_->reflexEdgeCount() <= kInheritMaxReflexEdges;
    const auto& offs = neighbourOffsets26();
    for (int o = 0; o < 26; ++o) {
      offsets_[o] = offs[o].cast<double>();
      lengths_[o] = offs[o].cast<double>().norm();
      deltas_[o] = static_cast<std::ptrdiff_t>(offs[o].x()) * g_.strideX() +
                   static_cast<std::ptrdiff_t>(offs[o].y()) * g_.strideY() + offs[o].z();
      byLength_[o] = o;
    }
    std::stable_sort(byLength_, byLength_ + 26,
                     [this](int a, int b) { return lengths_[a] < lengths_[b]; });
    if (inheritSight_) {
      // Four x slabs of the grid, 2^12 to 2^16 entries of 40 bytes.
      const std::size_t want = std::clamp<std::size_t>(4 * g_.strideX(), 4096, 65536);
      feet_.resize(std::bit_ceil(want));
      feetMask_ = feet_.size() - 1;
    }
  }

  MethodStats run(const std::vector<std::uint32_t>& seeds, Progress progress) {
    std::size_t insideCount = 0;
    for (std::uint8_t v : inside_) insideCount += v;
    inheritParents(seeds, insideCount, progress.sub(0.0, 0.45));
    std::size_t reset = 0;
    const std::size_t finished = checkInheritedParents(reset, progress.sub(0.45, 0.65));
    if (reset > 0) propagateIntoShadow(finished, insideCount, progress.sub(0.65, 1.0));
    return stats_;
  }

  std::size_t edgePivots() const { return edgePivots_; }

 private:
  /// Offers the parent of finished cell n (centre x) to its unfinished inside neighbours.
  void relaxNeighbours(std::uint32_t n, const Vec3& x) {
    // Raw pointers: the byte stores below would make the compiler reload the vectors' data.
    std::uint8_t* const state = state_.data();
    std::int32_t* const parent = parent_.data();
    float* const dist = dist_.data();
    const std::int32_t p = parent[n];
    const Pivot* pivot = p >= 0 ? &pivots_[static_cast<std::size_t>(p)] : nullptr;
    const Triangle* triangle = p < 0 ? &source_[parentTriangle(p)] : nullptr;
    for (int o = 0; o < 26; ++o) {
      const std::size_t m = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(n) + deltas_[o]);
      // A neighbour with the same parent already holds exactly this candidate.
      if ((state[m] & (kInside | kDone)) != kInside || parent[m] == p) continue;
      const Vec3 y = x + offsets_[o];
      Vec3 foot;
      double value;  // evaluate(p, y)
      if (pivot) {
        if (!pivotMayImprove(*pivot, y, dist[m])) continue;
        value = pivot->distance + (y - pivot->position).norm();
      } else {
        const Triangle& t = *triangle;
        value = pointTriangleDistance(y, t[0], t[1], t[2], &foot);
      }
      // Compare as stored (float): an equal candidate must not count as an improvement.
      const float cand = static_cast<float>(value);
      if (cand < dist[m]) {
        if (triangle && inheritSight_)
          feet_[m & feetMask_] = {static_cast<std::uint32_t>(m), p, value, foot};
        dist[m] = cand;
        parent[m] = p;
        state[m] &= static_cast<std::uint8_t>(~kVerified);
        push(cand, static_cast<std::uint32_t>(m));
      }
    }
  }

  /// False only if the pivot's value at y, as relaxNeighbours computes and rounds it, is surely
  /// not below `current`: pivot.distance + |y − P| >= current, decided from |y − P|² with a
  /// relative margin of 1e-9 that covers every rounding (no square root); true when in doubt.
  /// If r = current − distance > 0 and |y − P|² > r²·(1 + 1e-9), then |y − P| > r·(1 + 4e-10)
  /// even after rounding the square root, the sum exceeds `current`, and its rounding to double
  /// and to float cannot go below the float `current`.
  static bool pivotMayImprove(const Pivot& pivot, const Vec3& y, float current) {
    if (!(current < kInfF)) return true;
    const double r = static_cast<double>(current) - pivot.distance;
    if (r <= 0.0) return false;   // the sum is at least pivot.distance >= current
    if (r < 1e-100) return true;  // r² could underflow
    return !((y - pivot.position).squaredNorm() > r * r * (1.0 + 1e-9));
  }

  // ---- geodesic field: parent inheritance ------------------------------------------------
  /// Phase 1: Dijkstra order from the seeds; every cell takes the source triangle of the
  /// neighbour that reaches it best, without any line-of-sight test.
  void inheritParents(const std::vector<std::uint32_t>& seeds, std::size_t insideCount,
                      Progress progress) {
    for (std::uint32_t s : seeds) {
      state_[s] |= kVerified;  // a seed's distance is exact: never tested
      push(dist_[s], s);
    }
    std::size_t finished = 0;
    const std::size_t reportEvery = std::max<std::size_t>(insideCount / 100, 4096);
    while (!heap_.empty()) {
      const HeapItem item = heap_.pop();
      const std::uint32_t n = item.n;
      if ((state_[n] & kDone) || item.d != dist_[n]) continue;  // stale entry
      state_[n] |= kDone;
      if (++finished % reportEvery == 0) {
        progress.report(static_cast<double>(finished) / static_cast<double>(insideCount),
                        "geodesic field: parent inheritance");
      }
      const Vec3 x = cellCentre(g_.cell(n));
      if (inheritSight_ && !(state_[n] & kVerified)) state_[n] |= inheritLineOfSight(n, x);
      relaxNeighbours(n, x);
    }
    heap_.clear();
  }

  // ---- geodesic field: line of sight ------------------------------------------------------
  /// Phase 2: every inherited (source-triangle) parent is tested for line of sight, strictly (no
  /// start tolerance: a doubtful cell goes to phase 3, which decides it as before). Cells that see
  /// their parent are finished; the others are reset. Independent per cell: parallel over x
  /// slabs, progress reported between batches on the calling thread. Returns the finished count.
  std::size_t checkInheritedParents(std::size_t& reset, Progress progress) {
    const int nx = g_.dims.x(), ny = g_.dims.y(), nz = g_.dims.z();
    const int batch = std::max(1, (nx + 7) / 8);
    // Threads only pay off when there are segments to test (phase 1 may have verified nearly
    // every cell by inheritance).
    std::size_t pending = 0;
    for (const std::uint8_t st : state_)
      pending += (st & (kDone | kVerified | kShadowDown)) == kDone;
    const bool threads = pending >= kParallelTestsMin;
    std::size_t finished = 0;
    for (int i0 = 0; i0 < nx; i0 += batch) {
      const int i1 = std::min(nx, i0 + batch);
      std::size_t passed = 0, tested = 0, failed = 0;
#pragma omp parallel reduction(+ : passed, tested, failed) if (threads)
      {
        SolidBoundary::Mailbox mailbox;
        if (boundary_) mailbox = boundary_->makeMailbox();
#pragma omp for schedule(dynamic, 1) collapse(2)
        for (int i = i0; i < i1; ++i)
          for (int j = 0; j < ny; ++j) {
            const std::size_t row = g_.index(i, j, 0);
            for (int k = 0; k < nz; ++k) {
              const std::size_t n = row + static_cast<std::size_t>(k);
              if (!(state_[n] & kDone)) continue;
              if (state_[n] & kVerified) {
                ++passed;
                continue;
              }
              bool seen = false;
              if (!(state_[n] & kShadowDown)) {
                ++tested;
                const Vec3 x = cellCentre(Vec3i(i, j, k));
                Vec3 target;
                evaluate(parent_[n], x, &target);
                seen = visible(x, target, slackFor(parent_[n]), mailbox, /*strict=*/true);
              }
              if (seen) {
                state_[n] |= kVerified;
                ++passed;
              } else {
                state_[n] = kInside;
                dist_[n] = kInfF;
                parent_[n] = kNoParent;
                ++failed;
              }
            }
          }
      }
      reset += failed;
      finished += passed;
      stats_.lineOfSightTests += tested;
      progress.report(static_cast<double>(i1) / nx, "geodesic field: line of sight");
    }
    return finished;
  }

  // ---- geodesic field: any-angle propagation ------------------------------------------------
  /// Phase 3: the cells without line of sight to their inherited parent, in Dijkstra order from
  /// the finished cells around them, with a line-of-sight test per cell and repairs (pivots), as
  /// in Lazy Theta*. Sequential: which pivots exist depends on the order of the repairs.
  void propagateIntoShadow(std::size_t finished, std::size_t insideCount, Progress progress) {
    pushShadowFrontier();
    const std::size_t reportEvery = std::max<std::size_t>(insideCount / 200, 4096);
    while (!heap_.empty()) {
      const HeapItem item = heap_.pop();
      const std::uint32_t n = item.n;
      if ((state_[n] & kDone) || item.d != dist_[n]) continue;  // stale entry
      const Vec3 x = cellCentre(g_.cell(n));
      if (!(state_[n] & kVerified)) {
        state_[n] |= kVerified;
        // A cell that inherits its line of sight from a neighbour needs no segment test.
        const bool inherited = inheritSight_ && (inheritLineOfSight(n, x) & kVerified);
        if (!inherited) ++stats_.lineOfSightTests;
        Vec3 hit;
        bool hitFound = false;
        if (!inherited && !visibleVia(parent_[n], x, &hit, &hitFound)) {
          ++stats_.lineOfSightFailures;
          repair(n, x, hitFound ? &hit : nullptr);
          push(dist_[n], n);  // its value grew: back into the queue, now verified
          continue;
        }
      }
      state_[n] |= kDone;
      if (++finished % reportEvery == 0) {
        progress.report(static_cast<double>(finished) / static_cast<double>(insideCount),
                        "geodesic field: any-angle propagation");
      }
      relaxNeighbours(n, x);
    }
  }

  /// Unfinished inside cells next to finished ones get their finished neighbours' parents (the
  /// finished cells in increasing index order). A finished cell can have an unfinished inside
  /// neighbour only if one of the nine z rows around its own holds an unfinished inside cell, so
  /// the rows far from the shadow are skipped after one pass over the states.
  void pushShadowFrontier() {
    const int nx = g_.dims.x(), ny = g_.dims.y(), nz = g_.dims.z();
    std::vector<std::uint8_t> openRow(static_cast<std::size_t>(nx) * ny, 0);
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j) {
        const std::uint8_t* row = state_.data() + g_.index(i, j, 0);
        std::uint8_t open = 0;
        for (int k = 0; k < nz; ++k) open |= (row[k] & (kInside | kDone)) == kInside;
        openRow[static_cast<std::size_t>(i) * ny + j] = open;
      }
    // Inside (and so finished) cells never touch the grid border.
    for (int i = 1; i + 1 < nx; ++i)
      for (int j = 1; j + 1 < ny; ++j) {
        std::uint8_t openNearby = 0;
        for (int di = -1; di <= 1; ++di) {
          const std::uint8_t* r = openRow.data() + static_cast<std::size_t>(i + di) * ny + j;
          openNearby |= r[-1] | r[0] | r[1];
        }
        if (!openNearby) continue;
        const std::size_t row = g_.index(i, j, 0);
        for (int k = 0; k < nz; ++k) {
          const std::size_t n = row + static_cast<std::size_t>(k);
          if (!(state_[n] & kDone)) continue;
          bool frontier = false;
          for (int o = 0; o < 26 && !frontier; ++o) {
            const std::size_t m =
                static_cast<std::size_t>(static_cast<std::ptrdiff_t>(n) + deltas_[o]);
            frontier = (state_[m] & (kInside | kDone)) == kInside;
          }
          if (frontier) relaxNeighbours(static_cast<std::uint32_t>(n), cellCentre(Vec3i(i, j, k)));
        }
      }
  }

  void push(float d, std::uint32_t n) {
    heap_.push(d, n);
  }

  /// Distance of point x (cell units) through parent `code`; the segment's far end in `target`.
  double evaluate(std::int32_t code, const Vec3& x, Vec3* target) const {
    if (code < 0) {
      const Triangle& t = source_[parentTriangle(code)];
      return pointTriangleDistance(x, t[0], t[1], t[2], target);
    }
    const Pivot& p = pivots_[static_cast<std::size_t>(code)];
    if (target) *target = p.position;
    return p.distance + (x - p.position).norm();
  }

  /// The last stretch of a segment to a source triangle runs through cells cut by the start
  /// surface (which may also lie slightly off the solid); seeds within the band are taken as
  /// visible, so that stretch is not checked.
  double slackFor(std::int32_t code) const {
    return code < 0 ? slack_ : 0.0;
  }

  std::int32_t addPivot(const Pivot& pivot) {
    if (pivots_.size() >= static_cast<std::size_t>(INT32_MAX)) {
      throw ResourceLimit("too many pivot points in the geodesic field; use a larger voxel size");
    }
    pivots_.push_back(pivot);
    return static_cast<std::int32_t>(pivots_.size() - 1);
  }

  /// Minimises evaluate(q, y) + |x − y| over y on the segment [a, b]; returns the value and y.
  double bestPointOnEdge(std::int32_t q, const Vec3& a, const Vec3& b, const Vec3& x,
                         Vec3* y) const {
    const Vec3 ab = b - a;
    const double len = ab.norm();
    const Vec3 u = ab / len;
    if (q >= 0) {
      // Point parent: unfold about the edge line — s* = (h2·s1 + h1·s2) / (h1 + h2).
      const Vec3& P = pivots_[static_cast<std::size_t>(q)].position;
      const double s1 = (P - a).dot(u), s2 = (x - a).dot(u);
      const double h1 = (P - a - s1 * u).norm(), h2 = (x - a - s2 * u).norm();
      const double s = h1 + h2 > 0 ? (h2 * s1 + h1 * s2) / (h1 + h2) : 0.5 * (s1 + s2);
      *y = a + std::clamp(s, 0.0, len) * u;
      return evaluate(q, *y, nullptr) + (x - *y).norm();
    }
    // Triangle parent: the objective is convex along the edge; golden-section search.
    constexpr double kPhi = 0.6180339887498949;
    auto f = [&](double s) {
      const Vec3 p = a + s * u;
      return evaluate(q, p, nullptr) + (x - p).norm();
    };
    double lo = 0.0, hi = len;
    double m1 = hi - kPhi * (hi - lo), m2 = lo + kPhi * (hi - lo);
    double f1 = f(m1), f2 = f(m2);
    while (hi - lo > 1e-4) {
      if (f1 < f2) {
        hi = m2;
        m2 = m1;
        f2 = f1;
        m1 = hi - kPhi * (hi - lo);
        f1 = f(m1);
      } else {
        lo = m1;
        m1 = m2;
        f1 = f2;
        m2 = lo + kPhi * (hi - lo);
        f2 = f(m2);
      }
    }
    const double s = 0.5 * (lo + hi);
    *y = a + s * u;
    return f(s);
  }

  /// Line-of-sight failure at cell n: see the file comment, (a)–(c). Candidate lengths are cheap,
  /// visibility tests are not, so candidates are taken in increasing length from a heap until one
  /// is admissible: (a) the neighbours' parents; (b) pivots on the reflex edges near the cell and
  /// near where its blocked segment meets the surface, generated per parent only when the heap
  /// reaches that parent's straight length (distances through a parent are 1-Lipschitz, so no
  /// pivot via the parent is shorter); (c) the finished neighbours' centres, tested when a
  /// candidate at least as long (within 1e-9) is next — the first one in sight ends the search.
  /// Edges whose outside wedge holds the cell are skipped: no pivot on them sees it.
  /// `blockedAt`: where the segment to the cell's parent was found to cross the surface, if known.
  void repair(std::uint32_t n, const Vec3& x, const Vec3* blockedAt) {
    const std::int32_t failed = parent_[n];
    ViaCentres via;
    collectNeighbourCandidates(n, x, failed, via);
    edges_.clear();
    if (boundary_) collectReflexEdges(x, failed, blockedAt);
    if (edges_.empty()) {
      std::erase_if(candidates_, [](const Candidate& c) { return c.edge == kExpandParent; });
    }
    if (searchCandidates(n, x, via)) return;
    while (via.best == kInf && via.next < via.count) tryVia(n, x, via);
    if (via.best == kInf) {
      if (via.count == 0) {
        // Cannot happen: a queued cell always has a finished neighbour or is a seed.
        throw NumericalFailure("any-angle propagation lost the parent of a voxel; please report");
      }
      // No neighbour centre in sight (a surface fold thinner than a cell between them): the
      // nearest one, as the voxel graph connects them.
      via.best = via.items[0].first;
      via.bestCell =
          static_cast<std::uint32_t>(static_cast<std::ptrdiff_t>(n) + deltas_[via.items[0].second]);
    }
    dist_[n] = static_cast<float>(via.best);
    parent_[n] = addPivot({cellCentre(g_.cell(via.bestCell)), dist_[via.bestCell], -1});
  }

  /// The finished neighbours of a cell under repair, by the distance via their centres (c).
  struct ViaCentres {
    std::pair<double, int> items[26];  // (distance via the finished neighbour's centre, offset)
    int count = 0;
    int next = 0;        // the next one to test
    double best = kInf;  // the first one in sight
    std::uint32_t bestCell = 0;
  };

  /// Repair candidates (a): the failed parent and the finished neighbours' parents, each also
  /// to be expanded into pivots; and the neighbours' centres (c), sorted.
  void collectNeighbourCandidates(std::uint32_t n, const Vec3& x, std::int32_t failed,
                                  ViaCentres& via) {
    std::int32_t parents[27];
    int parentCount = 0;
    parents[parentCount++] = failed;
    candidates_.clear();
    candidates_.push_back({evaluate(failed, x, nullptr), failed, kExpandParent, Vec3::Zero()});
    for (int o = 0; o < 26; ++o) {
      const std::size_t m = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(n) + deltas_[o]);
      if (!(state_[m] & kDone)) continue;
      via.items[via.count++] = {dist_[m] + lengths_[o], o};
      const std::int32_t q = parent_[m];
      if (std::find(parents, parents + parentCount, q) != parents + parentCount) continue;
      parents[parentCount++] = q;
      const double direct = evaluate(q, x, nullptr);
      candidates_.push_back({direct, q, -1, Vec3::Zero()});  // (a) the neighbour's parent
      candidates_.push_back({direct, q, kExpandParent, Vec3::Zero()});
    }
    std::sort(via.items, via.items + via.count);
  }

  /// Reflex edges (b) near the cell and near where its blocked segment meets the surface,
  /// without those whose outside wedge holds the cell.
  void collectReflexEdges(const Vec3& x, std::int32_t failed, const Vec3* blockedAt) {
    boundary_->reflexEdgesNear(x, kEdgeReach, edges_);
    Vec3 target, hit;
    bool blocked = blockedAt != nullptr;
    if (blocked) {
      hit = *blockedAt;
    } else {
      evaluate(failed, x, &target);
      blocked = !boundary_->segmentClear(x, shortened(x, target, slackFor(failed)), mailbox_, &hit);
    }
    if (blocked) {
      boundary_->reflexEdgesNear(hit, kEdgeReach, moreEdges_);
      edges_.insert(edges_.end(), moreEdges_.begin(), moreEdges_.end());
      std::sort(edges_.begin(), edges_.end());
      edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
    }
    // The faces' normals are perpendicular to the edge, so whether x lies in the outside wedge
    // (pivotAdmissible's test leavesSolidAt(e, x − pivot, 0)) does not depend on the pivot's
    // place on the edge; the margin makes the skip never reject what that test accepts.
    std::erase_if(edges_, [&](std::uint32_t e) {
      const auto& edge = boundary_->reflexEdge(e);
      const Vec3 d = x - edge[0];
      const auto& normals = boundary_->reflexNormals(e);
      const double tol = 1e-8 * (d.norm() + (edge[1] - edge[0]).norm());
      return normals[0].dot(d) > tol && normals[1].dot(d) > tol;
    });
  }

  /// Tests the next neighbour centre; true (and `via.best` set) when the cell sees it.
  bool tryVia(std::uint32_t n, const Vec3& x, ViaCentres& via) {
    const int k = via.next++;
    const int o = via.items[k].second;
    // Two neighbouring cell centres need not see each other: their segment can cut the corner
    // of a reflex edge that passes between them.
    if (!visible(x, x + offsets_[o], 0.0, mailbox_, /*strict=*/true)) return false;
    via.best = via.items[k].first;
    via.bestCell = static_cast<std::uint32_t>(static_cast<std::ptrdiff_t>(n) + deltas_[o]);
    return true;
  }

  /// Takes candidates shortest first until one is admissible (then the cell's distance and
  /// parent are set: true) or a neighbour centre at most as far is in sight (false).
  bool searchCandidates(std::uint32_t n, const Vec3& x, ViaCentres& via) {
    // Shortest first; equal lengths in a fixed order (a parent's expansion before the candidates,
    // then by edge and parent), as pivots at an edge's end tie across the edges meeting there.
    auto later = [](const Candidate& l, const Candidate& r) {
      if (l.value != r.value) return l.value > r.value;
      if (l.edge != r.edge) return l.edge > r.edge;
      return l.parent > r.parent;
    };
    std::make_heap(candidates_.begin(), candidates_.end(), later);
    while (!candidates_.empty()) {
      std::pop_heap(candidates_.begin(), candidates_.end(), later);
      const Candidate c = candidates_.back();
      candidates_.pop_back();
      bool settled = false;
      while (!settled && via.next < via.count && via.items[via.next].first <= c.value + 1e-9)
        settled = tryVia(n, x, via);
      if (settled) return false;
      if (c.edge == kExpandParent) {
        for (std::uint32_t e : edges_) {
          const auto& edge = boundary_->reflexEdge(e);
          if (chordAlwaysLeaves(c.parent, e)) continue;
          Vec3 y;
          const double value = bestPointOnEdge(c.parent, edge[0], edge[1], x, &y);
          candidates_.push_back({value, c.parent, static_cast<std::int32_t>(e), y});
          std::push_heap(candidates_.begin(), candidates_.end(), later);
        }
        continue;
      }
      if (c.edge < 0 ? visibleVia(c.parent, x) : pivotAdmissible(c, x)) {
        if (c.edge >= 0) {
          Vec3 target;
          const double dy = evaluate(c.parent, c.point, &target);
          dist_[n] = static_cast<float>(c.value);
          parent_[n] = addPivot({c.point, dy, c.edge});
          ++edgePivots_;
        } else {
          dist_[n] = static_cast<float>(c.value);
          parent_[n] = c.parent;
        }
        return true;
      }
    }
    return false;
  }

  /// Line of sight inherited from a neighbour, exactly. Let y be a finished neighbour with the
  /// same parent whose segment was verified, and Q the planar region swept between the two
  /// segments: the triangle (x, y, P) for a pivot P, or for a source triangle whose feet are
  /// both interior (the two segments are then parallel, along the triangle's normal) the
  /// trapezoid (x, y, y', x') whose far side y'x' is where the segments' tested part ends.
  /// If the outside met Q without touching its verified sides, the point of the outside in Q
  /// nearest to the side y–y' would be a locally convex corner of the outside, i.e. a point of
  /// a reflex edge (on a closed manifold surface every other edge or face leaves the outside on
  /// one side of a line that also has points nearer to y–y'). So x sees its parent if x–y and
  /// y'–x' are clear and no reflex edge meets Q — for a pivot on a reflex edge, that edge's
  /// outside wedge must miss the angle of Q at P instead. O(reflex edges) per call.
  /// Returns the state bit to add: kVerified (seen), kShadowEdge (a reflex edge met a swept
  /// region), kShadowDown (no verified neighbour with the same parent, but one at or behind a
  /// shadow edge), or 0 (undecided: test the segment).
  std::uint8_t inheritLineOfSight(std::uint32_t n, const Vec3& x) {
    const std::int32_t q = parent_[n];
    int tries = 0;
    bool edgeMet = false, behindShadow = false;
    for (int k = 0; k < 26 && tries < 3; ++k) {
      const int o = byLength_[k];
      const std::size_t m = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(n) + deltas_[o]);
      if (!(state_[m] & kDone) || parent_[m] != q) continue;
      if (!(state_[m] & kVerified)) {
        behindShadow = behindShadow || (state_[m] & (kShadowEdge | kShadowDown));
        continue;
      }
      ++tries;
      switch (sweptRegionClear(q, n, static_cast<std::uint32_t>(m), o, x)) {
        case Swept::Clear:
          return kVerified;
        case Swept::ReflexEdge:
          edgeMet = true;
          break;
        case Swept::Undecided:
          break;
      }
    }
    if (edgeMet) return kShadowEdge;
    return tries == 0 && behindShadow ? kShadowDown : 0;
  }

  enum class Swept { Clear, ReflexEdge, Undecided };

  /// The swept region between the segments of cell n (centre x, parent q) and of its finished
  /// neighbour m = n + deltas_[o] (same parent, verified); see inheritLineOfSight.
  Swept sweptRegionClear(std::int32_t q, std::uint32_t n, std::uint32_t m, int o, const Vec3& x) {
    const Vec3 y = x + offsets_[o];
    if (q < 0) {
      Vec3 fx, fy;
      const double dx = footOnTriangle(n, q, x, &fx);
      if (dx <= slack_) return Swept::Clear;  // as visible(): within the seed band
      footOnTriangle(m, q, y, &fy);
      const Vec3 xe = shortened(x, fx, slack_), ye = shortened(y, fy, slack_);
      const Vec3 quad[4] = {x, y, ye, xe};
      if (!planarConvex(quad)) return Swept::Undecided;
      if (boundary_->polygonMeetsReflexEdge(quad, 4, -1, kInheritTolerance))
        return Swept::ReflexEdge;
      return neighbourVisible(n, m, o, x) && boundary_->segmentClear(ye, xe, mailbox_, nullptr, 0.0)
                 ? Swept::Clear
                 : Swept::Undecided;
    }
    const Pivot& p = pivots_[static_cast<std::size_t>(q)];
    const Vec3 tri[3] = {x, y, p.position};
    if (boundary_->polygonMeetsReflexEdge(tri, 3, p.edge, kInheritTolerance))
      return Swept::ReflexEdge;
    if (p.edge >= 0 && !wedgeMissesAngle(static_cast<std::uint32_t>(p.edge), p.position,
                                         y - p.position, x - p.position))
      return Swept::ReflexEdge;
    return neighbourVisible(n, m, o, x) ? Swept::Clear : Swept::Undecided;
  }

  /// Line of sight (strict, as visible()) between the centres of inside cell n (x) and of its
  /// neighbour m = n + deltas_[o]. Every point of the segment lies within half its length ℓ of
  /// one of the two centres c, so it is at least clearance(c) − ℓ/2 from every outside cell
  /// centre: when that is at least √3/2 + ½ for both ends, the segment has the guarantee of
  /// visible()'s sphere tracing (see there) and needs no step; otherwise visible() decides.
  bool neighbourVisible(std::uint32_t n, std::uint32_t m, int o, const Vec3& x) const {
    const Vec3i cn = g_.cell(n), cm = g_.cell(m);
    const double c =
        std::min(clearance_.at(cn.x(), cn.y(), cn.z()), clearance_.at(cm.x(), cm.y(), cm.z()));
    if (c - 0.5 * lengths_[o] >= kHalfSqrt3 + 0.5) return true;
    return visible(x, x + offsets_[o], 0.0, mailbox_, /*strict=*/true);
  }

  /// Distance from the centre x of cell n to source triangle `q` (a parent code < 0) and the
  /// closest point, exactly pointTriangleDistance: from the cache of recent values that
  /// relaxNeighbours fills (phase 1 values every cell once there and asks again for the cell and
  /// for its neighbours in inheritLineOfSight), else computed and cached.
  double footOnTriangle(std::uint32_t n, std::int32_t q, const Vec3& x, Vec3* foot) {
    FootEntry& e = feet_[n & feetMask_];
    if (e.cell != n || e.parent != q) {
      const Triangle& t = source_[parentTriangle(q)];
      e.distance = pointTriangleDistance(x, t[0], t[1], t[2], &e.foot);
      e.cell = n;
      e.parent = q;
    }
    *foot = e.foot;
    return e.distance;
  }

  /// True if the quadrilateral q[0..3] (in order) is planar and convex within the tolerance
  /// (sides of length 0 allowed: a triangle).
  static bool planarConvex(const Vec3 (&q)[4]) {
    const Vec3 m = (q[2] - q[0]).cross(q[3] - q[1]);
    const double mm = m.norm();
    if (!(mm > 1e-12)) return false;
    const Vec3 n = m / mm;
    // The thresholds need lengths (square roots) only near them: scale >= 1, so an offset within
    // the tolerance passes, and a turn of sign >= 0 passes whatever the sides' lengths.
    double off[3];
    bool flat = true;
    for (int i = 1; i < 4; ++i) {
      off[i - 1] = std::abs(n.dot(q[i] - q[0]));
      flat = flat && off[i - 1] <= kInheritTolerance;
    }
    if (!flat) {
      double scale = 1.0;
      for (int i = 1; i < 4; ++i) scale = std::max(scale, (q[i] - q[0]).norm());
      for (int i = 0; i < 3; ++i) {
        if (off[i] > kInheritTolerance * scale) return false;
      }
    }
    for (int i = 0; i < 4; ++i) {
      const Vec3 a = q[(i + 1) % 4] - q[i], b = q[(i + 2) % 4] - q[(i + 1) % 4];
      const double turn = n.dot(a.cross(b));
      if (!(turn >= 0.0) && turn < -kInheritTolerance * a.norm() * b.norm()) return false;
    }
    return true;
  }

  /// True if the outside wedge of reflex edge e (in front of both faces) misses the angle
  /// between directions a and b at point P of the edge, which must lie inside the edge (not at
  /// its ends, where other faces meet) and the edge must not lie in the angle's plane.
  bool wedgeMissesAngle(std::uint32_t e, const Vec3& P, const Vec3& a, const Vec3& b) const {
    const auto& edge = boundary_->reflexEdge(e);
    const Vec3 along = edge[1] - edge[0];
    const double len = along.norm();
    const double s = (P - edge[0]).dot(along) / (len * len);
    if (!(s * len > 1e-3 && (1.0 - s) * len > 1e-3)) return false;
    // The edge must cross the angle's plane (only at P); lying in it, it could bring its ends
    // (where other faces meet) into the region.
    const Vec3 planeNormal = a.cross(b);
    const double pn = planeNormal.norm();
    if (!(pn > 1e-12) || std::abs(planeNormal.dot(along)) <= 1e-6 * pn * len) return false;
    const auto& normals = boundary_->reflexNormals(e);
    // Directions w(t) = (1 − t)·â + t·b̂, t in [0, 1]; the wedge, widened by the tolerance, is
    // where n_i·w(t) > −tol for both faces i; each condition holds on an interval of t.
    const Vec3 ua = a.normalized(), ub = b.normalized();
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 2; ++i) {
      const double fa = normals[i].dot(ua) + kInheritTolerance;
      const double fb = normals[i].dot(ub) + kInheritTolerance;
      if (fa <= 0.0 && fb <= 0.0) return true;  // behind this face all along: outside the wedge
      if (fa > 0.0 && fb > 0.0) continue;
      const double root = fa / (fa - fb);
      if (fa > 0.0) {
        hi = std::min(hi, root);
      } else {
        lo = std::max(lo, root);
      }
    }
    return lo >= hi;  // no direction in front of both faces
  }

  /// True if x lies in the outside wedge of the reflex edge that pivot `q` sits on: the segment
  /// from the pivot to x leaves the solid at once (in front of both faces of the edge), so it
  /// cannot be a line of sight. O(1); false for source triangles and cell-centre pivots.
  bool behindPivotEdge(std::int32_t q, const Vec3& x) const {
    if (q < 0 || !boundary_) return false;
    const Pivot& p = pivots_[static_cast<std::size_t>(q)];
    return p.edge >= 0 &&
           boundary_->leavesSolidAt(static_cast<std::uint32_t>(p.edge), x - p.position, 0.0);
  }

  /// Line of sight from x to its segment's end through parent q. When the surface blocks it and
  /// `hit` is given, *hitFound tells whether a crossing point was stored in *hit.
  bool visibleVia(std::int32_t q, const Vec3& x, Vec3* hit = nullptr,
                  bool* hitFound = nullptr) const {
    if (behindPivotEdge(q, x)) return false;
    Vec3 target;
    evaluate(q, x, &target);
    return visible(x, target, slackFor(q), mailbox_, /*strict=*/false, hit, hitFound);
  }

  /// A pivot at point c.point of reflex edge c.edge with parent c.parent: the segments to it must
  /// not cross the surface, and must not leave the solid at the pivot or at the parent pivot (a
  /// chord across a concave hollow).
  bool pivotAdmissible(const Candidate& c, const Vec3& x) const {
    Vec3 target;
    evaluate(c.parent, c.point, &target);
    const auto e = static_cast<std::uint32_t>(c.edge);
    if (boundary_->leavesSolidAt(e, target - c.point, kChordDepth)) return false;
    if (c.parent >= 0) {
      const Pivot& p = pivots_[static_cast<std::size_t>(c.parent)];
      if (p.edge >= 0 && boundary_->leavesSolidAt(static_cast<std::uint32_t>(p.edge),
                                                  c.point - target, kChordDepth))
        return false;
    }
    if (boundary_->leavesSolidAt(e, x - c.point, 0.0)) return false;
    if (!boundary_->segmentClear(x, c.point, mailbox_)) return false;
    const Vec3 end = c.parent < 0 ? shortened(c.point, target, slack_) : target;
    return boundary_->segmentClear(c.point, end, mailbox_);
  }

  /// True if pivotAdmissible rejects every pivot on reflex edge e through point parent q for its
  /// chord to q: the faces' normals of e are perpendicular to it, so whether the chord leaves the
  /// solid at the new pivot does not depend on the pivot's place on the edge; whether it leaves
  /// at q's own edge is linear along e, so decided at e's ends. Margins make the result never
  /// reject what pivotAdmissible accepts. False for source triangles.
  bool chordAlwaysLeaves(std::int32_t q, std::uint32_t e) const {
    if (q < 0) return false;
    const Pivot& p = pivots_[static_cast<std::size_t>(q)];
    const auto& edge = boundary_->reflexEdge(e);
    const double len = (edge[1] - edge[0]).norm();
    const Vec3 toParent = p.position - edge[0];
    const double limit = 2.0 * kChordDepth + 1e-8 * (toParent.norm() + len);
    const auto& normals = boundary_->reflexNormals(e);
    if (normals[0].dot(toParent) > limit && normals[1].dot(toParent) > limit) return true;
    if (p.edge < 0) return false;
    const auto& parentNormals = boundary_->reflexNormals(static_cast<std::uint32_t>(p.edge));
    for (const Vec3& nrm : parentNormals) {
      if (!(nrm.dot(edge[0] - p.position) > limit && nrm.dot(edge[1] - p.position) > limit))
        return false;
    }
    return true;
  }

  static Vec3 shortened(const Vec3& from, const Vec3& to, double slack) {
    const Vec3 d = to - from;
    const double len = d.norm();
    if (len <= slack) return from;
    return to - d * (slack / len);
  }

  /// Line of sight from `from` (an inside cell centre) to `to`, ignoring the last `slack` cells.
  /// Sphere tracing through the clearance field accepts the part of the segment that is far from
  /// every wall; the rest is tested exactly against the surface (or by cell walking without it).
  /// Thread-safe with one `mailbox` per thread. When the surface blocks the segment and `hit` is
  /// given, a crossing point goes to *hit and *hitFound is set (cell walking finds none).
  bool visible(const Vec3& from, const Vec3& to, double slack, SolidBoundary::Mailbox& mailbox,
               bool strict = false, Vec3* hit = nullptr, bool* hitFound = nullptr) const {
    const Vec3 end = shortened(from, to, slack);
    const Vec3 d = end - from;
    const double len = d.norm();
    if (len < 1e-12) return true;
    const Vec3 dir = d / len;
    double t = 0.0;
    while (true) {
      const Vec3 p = from + t * dir;
      const int i = static_cast<int>(std::floor(p.x()));
      const int j = static_cast<int>(std::floor(p.y()));
      const int k = static_cast<int>(std::floor(p.z()));
      if (!g_.contains(i, j, k)) break;
      // One load per step: the clearance is 0 exactly on outside cells and at least 1 inside.
      const std::uint8_t clearance = clearance_.at(i, j, k);
      if (clearance == 0) break;
      const Vec3 centre = cellCentre(Vec3i(i, j, k));
      // Every point q within `safe` of p is at least √3/2 + ½ cells from every outside cell
      // centre o, so q lies in an inside cell with half a cell to spare (see clearance.hpp):
      // |q − o| ≥ |o − c| − |c − p| − |p − q| ≥ clearance(c) − |c − p| − safe ≥ √3/2 + ½, with
      // c the centre of p's cell and |c − p| bounded by min(|c − p|₁, √3/2) (no square root; 0
      // at a cell centre, where the segments start, so a first step goes √3/2 further than
      // with the bound √3/2 alone).
      const Vec3 offset = (p - centre).cwiseAbs();
      const double reach = std::min(offset.x() + offset.y() + offset.z(), kHalfSqrt3);
      const double safe = clearance - reach - kHalfSqrt3 - 0.5;
      if (t + safe >= len) return true;
      if (safe < 1.0) break;
      t += safe;
    }
    const Vec3 rest = from + t * dir;
    if (boundary_) {
      const bool clear = boundary_->segmentClear(rest, end, mailbox, hit,
                                                 strict ? 0.0 : SolidBoundary::kStartTolerance);
      if (!clear && hitFound) *hitFound = true;
      return clear;
    }
    return visibleThroughCells(rest, end);
  }

  /// True if p lies in an inside cell; its index in `index` and, if given, its centre in
  /// `centre`.
  bool insideCell(const Vec3& p, std::size_t* index, Vec3* centre = nullptr) const {
    const int i = static_cast<int>(std::floor(p.x()));
    const int j = static_cast<int>(std::floor(p.y()));
    const int k = static_cast<int>(std::floor(p.z()));
    if (!g_.contains(i, j, k)) return false;
    *index = g_.index(i, j, k);
    if (centre) *centre = cellCentre(Vec3i(i, j, k));
    return inside_[*index] != 0;
  }

  /// Voxel-only line of sight: the segment from `from` to `to` stays inside inside cells.
  bool visibleThroughCells(const Vec3& from, const Vec3& to) const {
    Vec3 d = to - from;
    const double len = d.norm();
    if (len <= 1e-12) return true;
    d /= len;
    const double tEnd = len;
    const Vec3 inv(d.x() != 0 ? 1.0 / d.x() : kInf, d.y() != 0 ? 1.0 / d.y() : kInf,
                   d.z() != 0 ? 1.0 / d.z() : kInf);
    double t = 0.0;
    while (t < tEnd) {
      const Vec3 p = from + t * d;
      std::size_t idx;
      if (!insideCell(p, &idx)) return false;
      const Vec3i c = g_.cell(idx);
      const double safe = clearance_.at(c.x(), c.y(), c.z()) - kSqrt3;
      if (safe > 1.0) {
        t += safe;
        continue;
      }
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
  const SolidBoundary* boundary_;
  mutable SolidBoundary::Mailbox mailbox_;  // segment-query marks of the sequential phase
  TiledBytes clearance_;                    // floor of the clearance in cells, saturated at 255
  std::vector<std::uint8_t> state_;
  RadixQueue heap_;
  std::vector<Pivot> pivots_;
  std::vector<std::uint32_t> edges_, moreEdges_;
  std::vector<Candidate> candidates_;
  /// Cache of point–triangle distances and closest points for triangle parents, indexed by the
  /// low bits of the cell index (sized for a few x slabs of the grid: the Dijkstra front).
  struct FootEntry {
    std::uint32_t cell = UINT32_MAX;
    std::int32_t parent = kNoParent;
    double distance = 0.0;
    Vec3 foot = Vec3::Zero();
  };
  std::vector<FootEntry> feet_;
  std::size_t feetMask_ = 0;
  MethodStats stats_;
  std::size_t edgePivots_ = 0;
  bool inheritSight_ = false;  // inheritsLineOfSight applies (closed model, few reflex edges)
  Vec3 offsets_[26];
  double lengths_[26];
  std::ptrdiff_t deltas_[26];
  int byLength_[26];  // neighbour indices, face neighbours first, then edge, then corner
};

}  // namespace

std::vector<std::uint8_t> computeClearanceCells(const VoxelGrid& grid, Progress progress) {
  std::vector<std::uint8_t> clearance(grid.inside.size());
  const std::vector<float> exact = computeClearance(grid, progress);
  // The transform is >= 0, so truncation is its floor (values from 255 up, and NaN, give 255).
  for (std::size_t i = 0; i < exact.size(); ++i)
    clearance[i] = exact[i] < 255.0f ? static_cast<std::uint8_t>(exact[i]) : std::uint8_t{255};
  return clearance;
}

MethodStats propagateAnyAngle(const VoxelGrid& grid, const TriMesh* model,
                              const std::vector<Triangle>& source,
                              const std::vector<std::uint32_t>& seeds, double seedBandCells,
                              std::vector<std::uint8_t> clearance, std::vector<float>& dist,
                              std::vector<std::int32_t>& parent, Progress progress) {
  // Neighbour offsets are applied without bounds checks: computeGeodesicField has checked that
  // no inside cell touches the grid border.
  std::unique_ptr<SolidBoundary> boundary;
  if (model) {
    progress.report(0.0, "geodesic field: surface index");
    boundary = std::make_unique<SolidBoundary>(grid.geometry, *model);
  }
  AnyAnglePropagator propagator(grid, source, seedBandCells, dist, parent, boundary.get(),
                                std::move(clearance));
  MethodStats stats = propagator.run(seeds, progress.sub(0.03, 1.0));
  stats.edgePivots = propagator.edgePivots();
  return stats;
}

}  // namespace curvedslicer::detail
