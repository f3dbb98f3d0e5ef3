// The deposit so far as capsules in a uniform grid (see deposit_index.hpp).
#include "deposit_index.hpp"

#include <algorithm>
#include <cmath>

namespace curvedslicer::detail {

namespace {
constexpr std::size_t kChunkSegments = 8;
}  // namespace

double pointSegmentDistance(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((x - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (a + t * d - x).norm();
}

// Closest points of two segments: minimise |p0 + s·d1 - q0 - t·d2| over s, t in [0, 1]. The
// unconstrained minimiser in s is clamped, t follows from s and is clamped, and s is
// recomputed for a clamped t (the minimum of a convex quadratic over a square).
double segmentDistance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 w = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(w);
  constexpr double kTiny = 1e-18;
  double s = 0.0, t = 0.0;
  if (a <= kTiny && e <= kTiny) return w.norm();
  if (a <= kTiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(w);
    if (e <= kTiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denominator = a * e - b * b;  // >= 0, 0 for parallel segments
      s = denominator > kTiny * a * e ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return (w + s * d1 - t * d2).norm();
}

DepositIndex::DepositIndex(const Aabb& bounds, double beadRadius, double cellSize,
                           std::size_t maxCells)
    : radius_(beadRadius) {
  Aabb box = bounds;
  if (box.empty()) box.extend(Vec3::Zero());
  box.min -= Vec3::Constant(beadRadius + 1e-6);
  box.max += Vec3::Constant(beadRadius + 1e-6);
  cell_ = std::max(cellSize, 1e-3);
  const Vec3 size = box.size();
  auto countCells = [&](double c) { return (size / c).array().ceil().max(1.0).eval(); };
  while (countCells(cell_).prod() > static_cast<double>(maxCells)) cell_ *= 1.25;
  const auto n = countCells(cell_);
  dims_ = Vec3i(static_cast<int>(n.x()), static_cast<int>(n.y()), static_cast<int>(n.z()));
  origin_ = box.min;
  cells_.resize(static_cast<std::size_t>(dims_.x()) * dims_.y() * dims_.z());
}

bool DepositIndex::cellRange(const Aabb& box, Vec3i& lo, Vec3i& hi) const {
  for (int k = 0; k < 3; ++k) {
    const double a = std::floor((box.min[k] - origin_[k]) / cell_);
    const double b = std::floor((box.max[k] - origin_[k]) / cell_);
    if (b < 0.0 || a >= dims_[k]) return false;
    lo[k] = static_cast<int>(std::max(a, 0.0));
    hi[k] = static_cast<int>(std::min(b, static_cast<double>(dims_[k] - 1)));
  }
  return true;
}

void DepositIndex::add(const DepositSegment& segment, bool newPath) {
  if (newPath || chunks_.empty() || chunks_.back().count >= kChunkSegments) {
    Chunk chunk;
    chunk.first = segments_.size();
    chunks_.push_back(chunk);
    stamp_.push_back(0);
  }
  Chunk& chunk = chunks_.back();
  const auto id = static_cast<std::uint32_t>(chunks_.size() - 1);
  segments_.push_back(segment);
  ++chunk.count;
  chunk.box.extend(segment.a);
  chunk.box.extend(segment.b);
  extent_.extend(segment.a);
  extent_.extend(segment.b);
  Aabb grown;
  grown.extend(segment.a);
  grown.extend(segment.b);
  grown.min -= Vec3::Constant(radius_);
  grown.max += Vec3::Constant(radius_);
  Vec3i lo, hi;
  if (!cellRange(grown, lo, hi)) return;
  for (int z = lo.z(); z <= hi.z(); ++z) {
    for (int y = lo.y(); y <= hi.y(); ++y) {
      for (int x = lo.x(); x <= hi.x(); ++x) {
        std::vector<std::uint32_t>& list = cells_[cellIndex(x, y, z)];
        if (list.empty() || list.back() != id) list.push_back(id);
      }
    }
  }
}

template <typename Visit, typename Keep>
void DepositIndex::visitCandidates(const Vec3& p, const Vec3& q, double reach, Visit&& visit,
                                   Keep&& keep) const {
  Aabb box;
  box.extend(p);
  box.extend(q);
  const double grow = reach + radius_;
  box.min -= Vec3::Constant(grow);
  box.max += Vec3::Constant(grow);
  Vec3i lo, hi;
  if (!cellRange(box, lo, hi)) return;
  if (++query_ == 0) {  // wrapped: clear the stamps
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    query_ = 1;
  }
  // a bead within reach of [p, q] is listed in the cell holding its point nearest to [p, q],
  // whose centre lies within half a cell diagonal of that point: cells farther than that from
  // the query segment need not be visited (a long slanted query spans many such cells)
  const double cellCull = 0.5 * std::sqrt(3.0) * cell_ + radius_ + reach;
  for (int z = lo.z(); z <= hi.z(); ++z) {
    for (int y = lo.y(); y <= hi.y(); ++y) {
      for (int x = lo.x(); x <= hi.x(); ++x) {
        const std::vector<std::uint32_t>& list = cells_[cellIndex(x, y, z)];
        if (list.empty()) continue;
        const Vec3 centre = origin_ + (Vec3(x, y, z) + Vec3::Constant(0.5)) * cell_;
        Aabb cellBox;  // the cell grown by the bead radius: what its segments' axes may reach
        cellBox.extend(centre - Vec3::Constant(0.5 * cell_ + radius_));
        cellBox.extend(centre + Vec3::Constant(0.5 * cell_ + radius_));
        if (!keep(cellBox)) continue;
        if (pointSegmentDistance(centre, p, q) > cellCull) continue;
        for (std::uint32_t id : list) {
          if (stamp_[id] == query_) continue;
          stamp_[id] = query_;
          const Chunk& chunk = chunks_[id];
          if (chunk.first >= visible_) continue;
          // sphere cull: every point of the chunk lies within `bound` of the box centre
          const double bound = 0.5 * chunk.box.diagonal();
          if (!keep(chunk.box)) continue;
          if (pointSegmentDistance(chunk.box.center(), p, q) - bound - radius_ >= reach) continue;
          const std::size_t end = std::min(chunk.first + chunk.count, visible_);
          for (std::size_t s = chunk.first; s < end; ++s) {
            if (!visit(s)) return;
          }
        }
      }
    }
  }
}

DepositHit DepositIndex::nearest(const Vec3& p, const Vec3& q, double reach) const {
  DepositHit best;
  visitCandidates(p, q, reach, [&](std::size_t s) {
    const double d = segmentDistance(p, q, segments_[s].a, segments_[s].b) - radius_;
    if (d < reach && d < best.distance) {
      best.distance = d;
      best.segment = s;
    }
    return true;
  });
  return best;
}

void DepositIndex::forEachWithin(const Vec3& p, const Vec3& q, double reach,
                                 const std::function<bool(std::size_t, double)>& visit,
                                 const Vec3& above, double level) const {
  const bool cut = !above.isZero();
  visitCandidates(
      p, q, reach,
      [&](std::size_t s) {
        const DepositSegment& g = segments_[s];
        if (cut && std::max(above.dot(g.a), above.dot(g.b)) < level) return true;
        const double d = segmentDistance(p, q, g.a, g.b) - radius_;
        return d >= reach || visit(s, d);
      },
      [&](const Aabb& box) {
        // the box's highest point along `above`
        return !cut || above.dot(box.center()) + 0.5 * above.cwiseAbs().dot(box.size()) >= level;
      });
}

bool DepositIndex::anyWithin(const Vec3& p, const Vec3& q, double reach, DepositHit* hit) const {
  bool found = false;
  visitCandidates(p, q, reach, [&](std::size_t s) {
    const double d = segmentDistance(p, q, segments_[s].a, segments_[s].b) - radius_;
    if (d >= reach) return true;
    found = true;
    if (hit) *hit = DepositHit{d, s};
    return false;
  });
  return found;
}

}  // namespace curvedslicer::detail
