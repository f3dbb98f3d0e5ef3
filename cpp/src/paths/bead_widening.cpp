#include "curvedslicer/paths/bead_widening.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "curvedslicer/core/error.hpp"
#include "paths_internal.hpp"

namespace curvedslicer {

namespace {

using paths_detail::formatNumber;

/// One bead segment: its ends, widths at both ends, and which bead and points it joins.
struct Segment {
  Vec3 a, b;
  double widthA = 0.0, widthB = 0.0;
  std::size_t bead = 0, i = 0, j = 0;
  bool widenable = false;
};

/// Nearest bead edge to a point: how far beyond it the point lies (negative inside the bead).
struct EdgeHit {
  double beyond = kInf;
  const Segment* segment = nullptr;
  Vec3 foot = Vec3::Zero();  ///< closest point on the segment's centre line
  double t = 0.0;            ///< its parameter along the segment
};

/// Segments hashed into cubes `cell` wide; each segment sits in every cell its bead, grown by
/// `reach`, touches.
class SegmentCells {
 public:
  SegmentCells(std::vector<Segment> segments, double cell, double reach)
      : segments_(std::move(segments)), cell_(cell) {
    for (std::size_t s = 0; s < segments_.size(); ++s) {
      const Segment& g = segments_[s];
      const Vec3 grow = Vec3::Constant(0.5 * std::max(g.widthA, g.widthB) + reach);
      const Vec3i lo = cellOf(g.a.cwiseMin(g.b) - grow), hi = cellOf(g.a.cwiseMax(g.b) + grow);
      for (int x = lo.x(); x <= hi.x(); ++x) {
        for (int y = lo.y(); y <= hi.y(); ++y) {
          for (int z = lo.z(); z <= hi.z(); ++z) cells_[key(x, y, z)].push_back(s);
        }
      }
    }
  }

  /// Bound on how fast nearestEdge(p).beyond changes with p (mm per mm): 1 for beads of constant
  /// width, more where a short segment's width changes fast (its edge then tilts).
  double slope() const {
    double slope = 1.0;
    for (const Segment& g : segments_) {
      const double len = (g.b - g.a).norm();
      const double dw = std::abs(g.widthB - g.widthA);
      if (dw > 0.0) slope = std::max(slope, len > 0.0 ? 1.0 + 0.5 * dw / len : kInf);
    }
    return slope;
  }

  EdgeHit nearestEdge(const Vec3& p) const {
    EdgeHit best;
    for (const std::size_t s : near(p)) {
      const EdgeHit hit = edgeOf(segments_[s], p);
      if (hit.beyond < best.beyond) best = hit;
    }
    return best;
  }

  /// Width of the strip `p` lies in: from the nearest edge to the nearest bead edge on the far
  /// side of `p` (p between the two centre lines); +inf if there is none (an open void).
  double stripWidthAt(const Vec3& p, const EdgeHit& nearest) const {
    const Vec3 towardNearest = nearest.foot - p;
    double width = kInf;
    for (const std::size_t s : near(p)) {
      const EdgeHit hit = edgeOf(segments_[s], p);
      if ((hit.foot - p).dot(towardNearest) < 0.0) {
        width = std::min(width, hit.beyond + nearest.beyond);
      }
    }
    return width;
  }

 private:
  const std::vector<std::size_t>& near(const Vec3& p) const {
    static const std::vector<std::size_t> kNone;
    const Vec3i c = cellOf(p);
    const auto it = cells_.find(key(c.x(), c.y(), c.z()));
    return it == cells_.end() ? kNone : it->second;
  }
  static EdgeHit edgeOf(const Segment& g, const Vec3& p) {
    const Vec3 ab = g.b - g.a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((p - g.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const Vec3 foot = g.a + t * ab;
    return {(p - foot).norm() - 0.5 * (g.widthA + t * (g.widthB - g.widthA)), &g, foot, t};
  }
  Vec3i cellOf(const Vec3& p) const {
    return {static_cast<int>(std::floor(p.x() / cell_)),
            static_cast<int>(std::floor(p.y() / cell_)),
            static_cast<int>(std::floor(p.z() / cell_))};
  }
  static std::int64_t key(int x, int y, int z) {
    return (static_cast<std::int64_t>(x & 0x1FFFFF) << 42) |
           (static_cast<std::int64_t>(y & 0x1FFFFF) << 21) |
           static_cast<std::int64_t>(z & 0x1FFFFF);
  }
  std::vector<Segment> segments_;
  double cell_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

double widthOf(const WidenableBead& bead, std::size_t i, double s) {
  return i < bead.widths.size() && bead.widths[i] > 0.0 ? bead.widths[i] : s;
}

std::vector<Segment> collectSegments(const std::vector<WidenableBead>& beads, double s) {
  std::vector<Segment> segments;
  for (std::size_t k = 0; k < beads.size(); ++k) {
    const std::vector<Vec3>& pts = beads[k].line->points;
    const std::size_t n = pts.size();
    if (n == 1)
      segments.push_back(
          {pts[0], pts[0], widthOf(beads[k], 0, s), widthOf(beads[k], 0, s), k, 0, 0, false});
    const std::size_t count = n < 2 ? 0 : (beads[k].line->closed && n >= 3 ? n : n - 1);
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t j = (i + 1) % n;
      segments.push_back(
          {pts[i], pts[j], widthOf(beads[k], i, s), widthOf(beads[k], j, s), k, i, j, true});
    }
  }
  return segments;
}

/// Per point of `bead`: the unit direction tangent × normal (its right side).
std::vector<Vec3> computeRightSides(const WidenableBead& bead) {
  const std::vector<Vec3>& pts = bead.line->points;
  const std::size_t n = pts.size();
  const bool closed = bead.line->closed && n >= 3;
  std::vector<Vec3> right(n, Vec3::Zero());
  for (std::size_t i = 0; i < n && n >= 2; ++i) {
    const Vec3& prev = i > 0 ? pts[i - 1] : (closed ? pts[n - 1] : pts[i]);
    const Vec3& next = i + 1 < n ? pts[i + 1] : (closed ? pts[0] : pts[i]);
    const Vec3 r = (next - prev).cross((*bead.normals)[i]);
    if (r.norm() > 0.0) right[i] = r.normalized();
  }
  return right;
}

void validateWideningInput(const std::vector<WidenableBead>& beads, const BeadWideningOptions& o) {
  if (!std::isfinite(o.beadSpacing) || o.beadSpacing <= 0.0) {
    throw InvalidInput("bead spacing must be a positive number of mm: " +
                       formatNumber(o.beadSpacing) + "; pass a value such as 3.7");
  }
  for (const double v :
       {o.maxExtension, o.maxWidth, o.sampleSpacing, o.minRunLength, o.minStripWidth}) {
    if (!std::isfinite(v) || v == 0.0) {
      throw InvalidInput("bead widening lengths must be finite and non-zero (negative: default): " +
                         formatNumber(v) + "; pass a positive number of mm or -1");
    }
  }
  for (const WidenableBead& b : beads) {
    if (b.line == nullptr || b.normals == nullptr || b.normals->size() != b.line->points.size()) {
      throw InvalidInput("bead widening needs one normal per bead point: " +
                         std::to_string(b.normals ? b.normals->size() : 0) + " normals for " +
                         std::to_string(b.line ? b.line->points.size() : 0) +
                         " points; pass the bead's normals");
    }
  }
}

/// Clears the extensions of every run of consecutive widened points (wrapping on a closed bead)
/// shorter than `minLength` along the bead: corners and short voids are not worth the overlap.
void dropShortRuns(const Polyline& line, std::vector<double>& left, std::vector<double>& right,
                   double minLength) {
  const std::size_t n = left.size();
  const auto widened = [&](std::size_t i) { return left[i] + right[i] > 0.0; };
  std::size_t start = 0;
  const bool wraps = line.closed && n >= 3;
  if (wraps) {
    while (start < n && widened(start)) ++start;
    if (start == n) return;  // widened all round
  }
  // Walk once round from a point that is not widened (or from 0 on an open bead).
  std::vector<std::size_t> run;
  const auto flush = [&] {
    double length = 0.0;
    for (std::size_t r = 1; r < run.size(); ++r) {
      length += (line.points[run[r]] - line.points[run[r - 1]]).norm();
    }
    if (length < minLength) {
      for (const std::size_t i : run) left[i] = right[i] = 0.0;
    }
    run.clear();
  };
  for (std::size_t step = 0; step < n; ++step) {
    const std::size_t i = (start + step) % n;
    if (widened(i)) {
      run.push_back(i);
    } else if (!run.empty()) {
      flush();
    }
  }
  if (!run.empty()) flush();
}

}  // namespace

BeadWidening computeBeadWidening(const TriMesh& mesh, const std::vector<WidenableBead>& beads,
                                 const std::vector<double>& edgeDistance,
                                 const BeadWideningOptions& options) {
  validateWideningInput(beads, options);
  if (!edgeDistance.empty() && edgeDistance.size() != mesh.vertexCount()) {
    throw InvalidInput("bead widening needs one edge distance per layer vertex: " +
                       std::to_string(edgeDistance.size()) + " values for " +
                       std::to_string(mesh.vertexCount()) +
                       " vertices; pass the distance field of the same mesh, or none");
  }
  const double s = options.beadSpacing;
  const double maxExtension = options.maxExtension < 0.0 ? 0.25 * s : options.maxExtension;
  const double maxWidth = options.maxWidth < 0.0 ? 1.25 * s : options.maxWidth;
  const double spacing = options.sampleSpacing < 0.0 ? s / 16.0 : options.sampleSpacing;
  const double minRun = options.minRunLength < 0.0 ? s : options.minRunLength;
  const double minStrip = options.minStripWidth < 0.0 ? 0.1 * s : options.minStripWidth;
  BeadWidening out;
  out.left.resize(beads.size());
  out.right.resize(beads.size());
  const SegmentCells cells(collectSegments(beads, s), s, 2.0 * maxExtension);
  std::vector<std::vector<Vec3>> rightSides(beads.size());
  // `edge`: the sample's distance to the part edge (+inf where unknown).
  const auto ask = [&](const Vec3& x, double edge) {
    const EdgeHit hit = cells.nearestEdge(x);
    if (!(hit.beyond > 1e-9 * s) || hit.beyond > maxExtension || !hit.segment->widenable) return;
    // Only strips between two beads: a band along the part edge (the edge nearer than any bead
    // on the far side) or an open void would need the bead across the edge at corners. A sliver
    // narrower than minStrip is fit noise, not worth a wider bead.
    const double strip = cells.stripWidthAt(x, hit);
    if (!(strip <= hit.beyond + edge) || strip < minStrip) return;
    const Segment& g = *hit.segment;
    if (rightSides[g.bead].empty()) {
      rightSides[g.bead] = computeRightSides(beads[g.bead]);
      out.left[g.bead].assign(rightSides[g.bead].size(), 0.0);
      out.right[g.bead].assign(rightSides[g.bead].size(), 0.0);
    }
    const Vec3 off = x - hit.foot;
    const Vec3& r = rightSides[g.bead][hit.t < 0.5 ? g.i : g.j];
    const double across = off.dot(r);
    if (std::abs(across) < 0.5 * off.norm()) return;  // beyond the bead's end, not its side
    std::vector<double>& side = across > 0.0 ? out.right[g.bead] : out.left[g.bead];
    const double e = hit.beyond + 0.5 * spacing;
    side[g.i] = std::max(side[g.i], e);
    side[g.j] = std::max(side[g.j], e);
  };
  std::vector<double> vertexBeyond(mesh.vertexCount());
  for (std::size_t v = 0; v < vertexBeyond.size(); ++v) {
    vertexBeyond[v] = cells.nearestEdge(mesh.vertices[v]).beyond;
  }
  const auto edgeAt = [&](const Vec3i& tri, double u, double w) {
    if (edgeDistance.empty()) return kInf;
    const double d0 = edgeDistance[tri[0]], d1 = edgeDistance[tri[1]], d2 = edgeDistance[tri[2]];
    const double d = d0 + u * (d1 - d0) + w * (d2 - d0);
    return std::isfinite(d) ? std::max(d, 0.0) : kInf;
  };
  // A sample is asked only if its distance beyond the nearest bead edge may lie in
  // (1e-9·s, maxExtension]. `beyond` changes at most `slope` per mm, so the triangle's corners
  // bound it: at most beyond(v) + slope·|x − v| (x inside a bead: nothing to widen), at least
  // min(beyond(v), reach) − slope·|x − v| (x too far off). The cells find every segment whose
  // edge is within `reach` of a point, so a corner's value above `reach` only says "more than
  // reach". Skipping such samples leaves the result as if all were asked, at a fraction of
  // the cost: most samples lie inside beads.
  const double reach = 2.0 * maxExtension;
  const double slope = cells.slope();
  const double inside = 1e-9 * s;
  for (const Vec3i& tri : mesh.triangles) {
    const std::array<Vec3, 3> p = {mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                   mesh.vertices[tri[2]]};
    const std::array<double, 3> beyond = {vertexBeyond[tri[0]], vertexBeyond[tri[1]],
                                          vertexBeyond[tri[2]]};
    const double edge =
        std::max({(p[1] - p[0]).norm(), (p[2] - p[1]).norm(), (p[0] - p[2]).norm()});
    const double lo = std::min({beyond[0], beyond[1], beyond[2]});
    const double hi = std::max({beyond[0], beyond[1], beyond[2]});
    if (hi < -slope * edge || lo > maxExtension + slope * edge) continue;  // all in, or all off
    const int n = std::max(1, static_cast<int>(std::ceil(edge / spacing)));
    for (int a = 0; a <= n; ++a) {
      for (int b = 0; a + b <= n; ++b) {
        const double u = static_cast<double>(a) / n, w = static_cast<double>(b) / n;
        const Vec3 x = p[0] + u * (p[1] - p[0]) + w * (p[2] - p[0]);
        double upper = kInf, lower = -kInf;
        for (int c = 0; c < 3; ++c) {
          const double d = slope * (x - p[c]).norm();
          upper = std::min(upper, beyond[c] + d);
          lower = std::max(lower, std::min(beyond[c], reach) - d);
        }
        if (upper <= inside || lower > maxExtension) continue;
        ask(x, edgeAt(tri, u, w));
      }
    }
  }
  for (std::size_t k = 0; k < beads.size(); ++k) {
    if (!out.left[k].empty()) dropShortRuns(*beads[k].line, out.left[k], out.right[k], minRun);
    for (std::size_t i = 0; i < out.left[k].size(); ++i) {
      double& l = out.left[k][i];
      double& r = out.right[k][i];
      const double w = widthOf(beads[k], i, s);
      const double room = std::max(0.0, maxWidth - w);
      if (l + r > room) {
        const double scale = room / (l + r);
        l *= scale;
        r *= scale;
      }
      out.widenedPoints += l + r > 0.0;
      out.largestWidth = std::max(out.largestWidth, w + l + r);
    }
  }
  return out;
}

}  // namespace curvedslicer
