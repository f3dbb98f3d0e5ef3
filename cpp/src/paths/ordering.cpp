#include "curvedslicer/paths/ordering.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace {

/// Smallest distance from `p` to any of `seams` (+inf if there are none).
double distanceToSeams(const Vec3& p, const std::vector<Vec3>& seams) {
  double best = kInf;
  for (const Vec3& s : seams) best = std::min(best, (p - s).norm());
  return best;
}

/// A candidate way of entering a path from the torch position.
struct Entry {
  double cost = kInf;
  bool reversed = false;
  std::size_t seam = 0;
  bool seamTooClose = false;
};

/// Per ring: which points keep the seam separation (computed once per layer).
struct RingSeams {
  std::vector<std::size_t> admissible;  ///< point indices far enough from the previous seams
  std::size_t fallback = 0;             ///< the point farthest from them
};

RingSeams findRingSeams(const Polyline& ring, const std::vector<Vec3>& previousSeams,
                        double separation) {
  RingSeams r;
  double farthest = -1.0;
  for (std::size_t i = 0; i < ring.points.size(); ++i) {
    const double d = distanceToSeams(ring.points[i], previousSeams);
    if (d >= separation) r.admissible.push_back(i);
    if (d > farthest) {
      farthest = d;
      r.fallback = i;
    }
  }
  return r;
}

Entry bestEntry(const Polyline& path, const RingSeams& seams, const Vec3& torch) {
  Entry e;
  if (!path.closed) {
    const double toFirst = (path.points.front() - torch).norm();
    const double toLast = (path.points.back() - torch).norm();
    e.reversed = toLast < toFirst;
    e.cost = std::min(toFirst, toLast);
    return e;
  }
  if (seams.admissible.empty()) {
    e.seam = seams.fallback;
    e.seamTooClose = true;
    e.cost = (path.points[e.seam] - torch).norm();
    return e;
  }
  for (const std::size_t i : seams.admissible) {
    const double d = (path.points[i] - torch).norm();
    if (d < e.cost) {
      e.cost = d;
      e.seam = i;
    }
  }
  return e;
}

const Vec3& entryPoint(const Polyline& path, const OrderedPath& o) {
  if (path.closed) return path.points[o.seam];
  return o.reversed ? path.points.back() : path.points.front();
}

const Vec3& exitPoint(const Polyline& path, const OrderedPath& o) {
  if (path.closed) return path.points[o.seam];
  return o.reversed ? path.points.front() : path.points.back();
}

}  // namespace

LayerOrder orderLayerPaths(const std::vector<Polyline>& paths, const std::optional<Vec3>& start,
                           const std::vector<Vec3>& previousSeams, const OrderingOptions& options) {
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const std::size_t need = paths[i].closed ? 3 : 2;
    if (paths[i].points.size() < need) {
      throw InvalidInput("path " + std::to_string(i) + " has " +
                         std::to_string(paths[i].points.size()) + " point(s): a" +
                         (paths[i].closed ? " closed path needs 3" : "n open path needs 2") +
                         "; drop it before ordering");
    }
  }
  LayerOrder result;
  if (paths.empty()) {
    result.end = start.value_or(Vec3::Zero());
    return result;
  }
  std::vector<RingSeams> ringSeams(paths.size());
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (paths[i].closed) {
      ringSeams[i] = findRingSeams(paths[i], previousSeams, options.seamSeparation);
    }
  }

  // ---- greedy nearest neighbour ---------------------------------------------------------------
  const Vec3 origin = start.value_or(paths[0].points.front());
  Vec3 torch = origin;
  std::vector<bool> used(paths.size(), false);
  for (std::size_t step = 0; step < paths.size(); ++step) {
    std::size_t bestPath = paths.size();
    Entry best;
    for (std::size_t i = 0; i < paths.size(); ++i) {
      if (used[i]) continue;
      const Entry e = bestEntry(paths[i], ringSeams[i], torch);
      if (bestPath == paths.size() || e.cost < best.cost) {  // ties: the lower index
        best = e;
        bestPath = i;
      }
    }
    used[bestPath] = true;
    OrderedPath o;
    o.source = bestPath;
    o.reversed = best.reversed;
    o.seam = best.seam;
    o.seamTooClose = best.seamTooClose;
    result.paths.push_back(o);
    torch = exitPoint(paths[bestPath], o);
  }

  // ---- 2-opt: reverse a run of paths when that shortens the travel ------------------------------
  auto& seq = result.paths;
  const std::size_t n = seq.size();
  for (int pass = 0; pass < options.improvementPasses; ++pass) {
    bool improved = false;
    for (std::size_t a = 0; a + 1 < n; ++a) {
      for (std::size_t b = a + 1; b < n; ++b) {
        const Vec3& before = a == 0 ? origin : exitPoint(paths[seq[a - 1].source], seq[a - 1]);
        const Vec3& inA = entryPoint(paths[seq[a].source], seq[a]);
        const Vec3& outB = exitPoint(paths[seq[b].source], seq[b]);
        double oldCost = (inA - before).norm();
        double newCost = (outB - before).norm();
        if (b + 1 < n) {
          const Vec3& inNext = entryPoint(paths[seq[b + 1].source], seq[b + 1]);
          oldCost += (inNext - outB).norm();
          newCost += (inNext - inA).norm();
        }
        if (newCost < oldCost - 1e-9) {
          std::reverse(seq.begin() + static_cast<std::ptrdiff_t>(a),
                       seq.begin() + static_cast<std::ptrdiff_t>(b) + 1);
          for (std::size_t k = a; k <= b; ++k) {
            if (!paths[seq[k].source].closed) seq[k].reversed = !seq[k].reversed;
          }
          improved = true;
        }
      }
    }
    if (!improved) break;
  }

  // ---- totals ----------------------------------------------------------------------------------
  torch = origin;
  for (const OrderedPath& o : seq) {
    const Polyline& p = paths[o.source];
    result.travel += (entryPoint(p, o) - torch).norm();
    result.seams.push_back(entryPoint(p, o));
    if (o.seamTooClose) ++result.seamsTooClose;
    torch = exitPoint(p, o);
  }
  result.end = torch;
  return result;
}

}  // namespace curvedslicer
