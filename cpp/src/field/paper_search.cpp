// The paper's optimised search for the geodesic volume field (Virtual and Physical Prototyping
// 2024, §2.2.2, steps 1–9, fig. 5), implemented as written, with these readings of the text:
//
//  * "Surrounding points" (steps 2 and 7) are the 26 neighbours of a cell.
//  * Step 3 (eq. 8): J_P = min over the cells N of the reference set B inside the search sphere of
//    radius r = 2√3·L around P of (l_i + t_i). All cells of a front are evaluated against the same
//    B (not against each other), so the result does not depend on visiting order.
//  * Steps 4 and 8, "B is updated with A" / "with the union of D and E", are read as unions: B
//    accumulates every computed cell, and the newest cells form the working front whose unknown
//    neighbours are computed next. (Reading "updated with" as replacement — B = the newest front
//    only — leaves eq. 8 so few directions inside the sphere that the method breaks its own
//    accuracy claim: measured on the 128-cell analytic cases, overestimates of 3.7 % + L on the
//    spherical shell and 5.7 % + L on the U-bend, against the 2.9 % + L bound of the sphere's
//    angular gap, which the union reading meets.)
//  * Steps 5–8 (ambiguous in the text): the part of the front C that is expanded again must be
//    the *lagging* cells, t < Smax − √3·L, while D (t ≥ Smax − √3·L) waits; E = unknown neighbours
//    of C, computed by step 3; the front becomes D ∪ E; repeat until C is empty. The literal
//    wording ("in point set C, the GDTS values are greater") would push the leading cells further
//    ahead, which contradicts the stated purpose (keep every value of B within √3·L of Smax,
//    §2.2.3) and fig. 9(b)
//    ("propagation along the shorter side"); the reading above achieves that purpose.
//  * Step 9: the loop ends when no unknown cell borders B; inside cells never reached are reported.
//  * Seeds (step 1) get the exact distance to the start surface rather than 0, so a start surface
//  between
//    voxel centres does not shift every distance by up to half a voxel.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "field_internal.hpp"

namespace curvedslicer::detail {

namespace {

// kKnown: computed (member of the reference set B); kFront: computed and on the working front.
enum : std::uint8_t { kUnknown = 0, kKnown = 1, kFront = 2, kPending = 3 };
constexpr double kSqrt3 = 1.7320508075688772;

struct Offset {
  Vec3i o;
  std::ptrdiff_t delta;
  float length;
};

class PaperSearch {
 public:
  PaperSearch(const VoxelGrid& grid, double radius, std::vector<float>& dist)
      : g_(grid.geometry), inside_(grid.inside), dist_(dist), state_(dist.size(), kUnknown) {
    const int R = static_cast<int>(std::floor(radius));
    reach_ = R;
    for (int dx = -R; dx <= R; ++dx)
      for (int dy = -R; dy <= R; ++dy)
        for (int dz = -R; dz <= R; ++dz) {
          const double len = std::sqrt(double(dx * dx + dy * dy + dz * dz));
          if (len == 0 || len > radius + 1e-9) continue;
          sphere_.push_back({Vec3i(dx, dy, dz), delta(dx, dy, dz), static_cast<float>(len)});
        }
    for (const Vec3i& o : neighbourOffsets26()) {
      adjacent_.push_back(delta(o.x(), o.y(), o.z()));
    }
  }

  MethodStats run(const std::vector<std::uint32_t>& seeds, Progress progress) {
    MethodStats stats;
    std::size_t insideCount = 0;
    for (std::uint8_t v : inside_) insideCount += v;
    // Step 1: the seeds form the reference set B (and the first front, named B below).
    std::vector<std::uint32_t> B(seeds.begin(), seeds.end());
    for (std::uint32_t s : B) state_[s] = kFront;
    std::size_t known = B.size();
    std::vector<std::uint32_t> A, C, D, E;
    std::size_t nextReport = 0;
    while (true) {
      // Step 2: A = unknown cells around the front.
      collectUnknownNeighbours(B, A);
      if (A.empty()) break;  // step 9: nothing left that B can reach
      ++stats.outerIterations;
      // Step 3: GDTS of A from B within the search sphere (eq. 8).
      evaluate(A);
      // Step 4: Smax over A; A joins the reference set and becomes the front.
      float smax = 0.0f;
      for (std::uint32_t p : A) smax = std::max(smax, dist_[p]);
      for (std::uint32_t p : B) state_[p] = kKnown;
      for (std::uint32_t p : A) state_[p] = kFront;
      B.swap(A);
      known += B.size();
      // Steps 5–8: bring the lagging part of B forward until B spans at most √3·L.
      const float threshold = smax - static_cast<float>(kSqrt3);
      while (true) {
        C.clear();
        D.clear();
        for (std::uint32_t p : B) (dist_[p] < threshold ? C : D).push_back(p);
        if (C.empty()) break;  // step 6
        ++stats.correctionRounds;
        collectUnknownNeighbours(C, E);  // step 7
        evaluate(E);
        for (std::uint32_t p : C) state_[p] = kKnown;
        for (std::uint32_t p : E) state_[p] = kFront;
        known += E.size();
        B.swap(D);  // step 8: the front becomes D ∪ E (E joins the reference set)
        B.insert(B.end(), E.begin(), E.end());
      }
      if (known >= nextReport) {
        progress.report(static_cast<double>(known) / static_cast<double>(insideCount),
                        "geodesic field: paper search");
        nextReport = known + std::max<std::size_t>(insideCount / 200, 4096);
      }
    }
    return stats;
  }

 private:
  std::ptrdiff_t delta(int dx, int dy, int dz) const {
    return static_cast<std::ptrdiff_t>(dx) * static_cast<std::ptrdiff_t>(g_.strideX()) +
           static_cast<std::ptrdiff_t>(dy) * static_cast<std::ptrdiff_t>(g_.strideY()) + dz;
  }

  void collectUnknownNeighbours(const std::vector<std::uint32_t>& from,
                                std::vector<std::uint32_t>& out) {
    out.clear();
    for (std::uint32_t p : from) {
      for (std::ptrdiff_t dl : adjacent_) {
        const std::size_t m = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + dl);
        if (inside_[m] && state_[m] == kUnknown) {
          state_[m] = kPending;
          out.push_back(static_cast<std::uint32_t>(m));
        }
      }
    }
    std::sort(out.begin(), out.end());
  }

  /// Eq. 8 for every cell of `cells` against the reference set B (every computed cell).
  void evaluate(const std::vector<std::uint32_t>& cells) {
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(cells.size());
#pragma omp parallel for schedule(static) if (count > 4096)
    for (std::ptrdiff_t q = 0; q < count; ++q) {
      const std::uint32_t p = cells[q];
      const Vec3i c = g_.cell(p);
      const bool interior =
          (c.array() >= reach_).all() && (c.array() < g_.dims.array() - reach_).all();
      float best = kInfF;
      for (const Offset& o : sphere_) {
        if (!interior && !g_.contains(c + o.o)) continue;
        const std::size_t m = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + o.delta);
        if (state_[m] == kFront || state_[m] == kKnown) best = std::min(best, dist_[m] + o.length);
      }
      dist_[p] = best;
    }
  }

  const GridGeometry& g_;
  const std::vector<std::uint8_t>& inside_;
  std::vector<float>& dist_;
  std::vector<std::uint8_t> state_;
  std::vector<Offset> sphere_;
  std::vector<std::ptrdiff_t> adjacent_;
  int reach_ = 0;
};

}  // namespace

MethodStats propagatePaper(const VoxelGrid& grid, const std::vector<std::uint32_t>& seeds,
                           double searchRadiusCells, std::vector<float>& dist, Progress progress) {
  PaperSearch search(grid, searchRadiusCells, dist);
  return search.run(seeds, progress);
}

}  // namespace curvedslicer::detail
