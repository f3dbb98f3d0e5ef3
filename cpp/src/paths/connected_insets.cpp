#include "curvedslicer/paths/connected_insets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <optional>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "paths_internal.hpp"

namespace curvedslicer {

namespace {

using paths_detail::formatNumber;

/// The options with their defaults resolved, and what every step reads.
struct JoinContext {
  const std::vector<PlanPath>& paths;
  const std::vector<int>& levels;
  const SurfaceProjection& project;
  double maxLink = 0.0, clearance = 0.0, surfaceGap = 0.0, pointSpacing = 0.0;

  bool isRing(std::size_t i) const { return levels[i] >= 0 && paths[i].closed; }
};

void resolveOptions(const ConnectedInsetOptions& o, JoinContext& c) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(o.beadSpacing) || !positive(o.pointSpacing)) {
    throw InvalidInput("connected insets need a positive bead spacing and point spacing: " +
                       formatNumber(o.beadSpacing) + " and " + formatNumber(o.pointSpacing) +
                       " mm; pass values such as 3.7 and 2");
  }
  const double s = o.beadSpacing;
  c.maxLink = o.maxLinkLength < 0.0 ? 1.5 * s : o.maxLinkLength;
  c.clearance = o.clearance < 0.0 ? 0.5 * s : o.clearance;
  c.surfaceGap = o.maxSurfaceGap < 0.0 ? 0.25 * s : o.maxSurfaceGap;
  c.pointSpacing = o.pointSpacing;
}

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

/// Smallest distance from `p` to the centre line of `path` (closing segment included if closed).
double distanceToPath(const Vec3& p, const PlanPath& path) {
  const std::size_t n = path.points.size();
  if (n == 1) return (p - path.points[0].position).norm();
  const std::size_t segments = path.closed ? n : n - 1;
  double best = kInf;
  for (std::size_t i = 0; i < segments; ++i) {
    best = std::min(
        best, distanceToSegment(p, path.points[i].position, path.points[(i + 1) % n].position));
  }
  return best;
}

/// Index of the point of `ring` nearest to `p` (the first of equals).
std::size_t nearestPoint(const PlanPath& ring, const Vec3& p) {
  std::size_t best = 0;
  double bestDistance = kInf;
  for (std::size_t i = 0; i < ring.points.size(); ++i) {
    const double d = (ring.points[i].position - p).norm();
    if (d < bestDistance) {
      bestDistance = d;
      best = i;
    }
  }
  return best;
}

/// Rule 2 of the file comment for one link point (chord point `chord`, projected `p`).
bool isAdmissibleLinkPoint(const JoinContext& c, const Vec3& chord, const Vec3& p, const Vec3& e,
                           const Vec3& q, std::size_t from, std::size_t to) {
  if ((p - chord).norm() > c.surfaceGap) return false;
  if (distanceToPath(p, c.paths[from]) < 0.5 * (p - e).norm() - 1e-9) return false;
  if (distanceToPath(p, c.paths[to]) < 0.5 * (p - q).norm() - 1e-9) return false;
  for (std::size_t i = 0; i < c.paths.size(); ++i) {
    if (i != from && i != to && distanceToPath(p, c.paths[i]) < c.clearance) return false;
  }
  return true;
}

/// The link from point `e` of ring `from` to point `q` (index) of ring `to`: its interior points
/// on the surface, or none if it is not admissible.
std::optional<std::vector<SurfacePoint>> makeLink(const JoinContext& c, const Vec3& e,
                                                  std::size_t from, std::size_t to, std::size_t q) {
  const Vec3& target = c.paths[to].points[q].position;
  const double length = (target - e).norm();
  if (!(length <= c.maxLink)) return std::nullopt;
  const int pieces = std::max(1, static_cast<int>(std::ceil(length / c.pointSpacing)));
  std::vector<SurfacePoint> link;
  for (int j = 0; j <= pieces; ++j) {
    const Vec3 chord = e + (static_cast<double>(j) / pieces) * (target - e);
    const SurfacePoint sp = j == 0        ? SurfacePoint{e, Vec3::UnitZ()}
                            : j == pieces ? SurfacePoint{target, Vec3::UnitZ()}
                                          : c.project(chord);
    if (!isAdmissibleLinkPoint(c, chord, sp.point, e, target, from, to)) return std::nullopt;
    if (j > 0 && j < pieces) link.push_back(sp);
  }
  return link;
}

/// One arc-on path to be: its rings in deposition order, where each is entered, the links.
struct Chain {
  std::vector<std::size_t> rings;
  std::vector<std::size_t> entries;  ///< point index where each ring part starts (first: 0)
  std::vector<std::vector<SurfacePoint>> links;  ///< links[i] leads to rings[i + 1]
};

/// Rule 1 of the file comment: the next ring after the chain's last, if an admissible link leads
/// to one.
bool extendChain(const JoinContext& c, Chain& chain, std::vector<bool>& used,
                 std::size_t& rejected) {
  const std::size_t last = chain.rings.back();
  const Vec3 e = c.paths[last].points[chain.entries.back()].position;
  struct Candidate {
    double distance;
    std::size_t ring, point;
  };
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < c.paths.size(); ++i) {
    if (used[i] || !c.isRing(i) || c.levels[i] != c.levels[last] + 1) continue;
    const std::size_t q = nearestPoint(c.paths[i], e);
    const double d = (c.paths[i].points[q].position - e).norm();
    if (d <= c.maxLink) candidates.push_back({d, i, q});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.distance < b.distance; });
  for (const Candidate& candidate : candidates) {
    std::optional<std::vector<SurfacePoint>> link =
        makeLink(c, e, last, candidate.ring, candidate.point);
    if (!link) {
      ++rejected;
      continue;
    }
    used[candidate.ring] = true;
    chain.rings.push_back(candidate.ring);
    chain.entries.push_back(candidate.point);
    chain.links.push_back(std::move(*link));
    return true;
  }
  return false;
}

/// Every path in a chain (most of one path alone), chains in the deposition order of their first
/// path.
std::vector<Chain> findChains(const JoinContext& c, std::size_t& rejected) {
  const std::size_t n = c.paths.size();
  std::vector<std::size_t> byLevel(n);
  std::iota(byLevel.begin(), byLevel.end(), std::size_t{0});
  std::stable_sort(byLevel.begin(), byLevel.end(),
                   [&](std::size_t a, std::size_t b) { return c.levels[a] < c.levels[b]; });
  std::vector<bool> used(n, false);
  std::vector<std::optional<Chain>> chainAt(n);
  for (const std::size_t head : byLevel) {
    if (used[head]) continue;
    used[head] = true;
    Chain chain;
    chain.rings.push_back(head);
    chain.entries.push_back(0);
    if (c.isRing(head)) {
      while (extendChain(c, chain, used, rejected)) {
      }
    }
    chainAt[head] = std::move(chain);
  }
  std::vector<Chain> chains;
  for (std::optional<Chain>& chain : chainAt) {
    if (chain) chains.push_back(std::move(*chain));
  }
  return chains;
}

/// The joined path of a chain of two or more rings (file comment, 3.).
PlanPath buildJoinedPath(const JoinContext& c, const Chain& chain) {
  PlanPath joined = c.paths[chain.rings.front()];
  joined.closed = false;
  joined.points.clear();
  for (std::size_t r = 0; r < chain.rings.size(); ++r) {
    const std::vector<PathPoint>& ring = c.paths[chain.rings[r]].points;
    if (r > 0) {
      const double width = ring[chain.entries[r]].width;
      for (const SurfacePoint& sp : chain.links[r - 1]) {
        PathPoint p;
        p.position = sp.point;
        p.normal = sp.normal;
        p.deposition = -sp.normal;
        p.width = width;
        joined.points.push_back(p);
      }
    }
    for (std::size_t i = 0; i <= ring.size(); ++i) {
      joined.points.push_back(ring[(chain.entries[r] + i) % ring.size()]);
    }
  }
  joined.length = 0.0;
  for (std::size_t i = 1; i < joined.points.size(); ++i) {
    joined.length += (joined.points[i].position - joined.points[i - 1].position).norm();
  }
  return joined;
}

}  // namespace

ConnectedInsetResult connectInsets(std::vector<PlanPath>& paths, const std::vector<int>& levels,
                                   const SurfaceProjection& project,
                                   const ConnectedInsetOptions& options) {
  if (levels.size() != paths.size()) {
    throw InvalidInput(
        "connected insets need one level per path: " + std::to_string(levels.size()) +
        " levels for " + std::to_string(paths.size()) + " paths; pass −1 for paths not to join");
  }
  JoinContext c{paths, levels, project};
  resolveOptions(options, c);
  ConnectedInsetResult result;
  result.arcStartsBefore = paths.size();
  const std::vector<Chain> chains = findChains(c, result.rejectedLinks);
  std::vector<PlanPath> out;
  out.reserve(chains.size());
  for (const Chain& chain : chains) {
    for (std::size_t r = 0; r < chain.rings.size(); ++r) {
      result.seams.push_back(paths[chain.rings[r]].points[chain.entries[r]].position);
    }
    result.links += chain.links.size();
    out.push_back(chain.rings.size() > 1 ? buildJoinedPath(c, chain)
                                         : std::move(paths[chain.rings.front()]));
  }
  for (std::size_t i = 0; i < out.size(); ++i) out[i].index = static_cast<int>(i);
  paths = std::move(out);
  result.arcStartsAfter = paths.size();
  return result;
}

std::vector<JoinedPathPart> splitJoinedPath(const PlanPath& path) {
  const std::vector<PathPoint>& p = path.points;
  const std::size_t n = p.size();
  if (n == 0) return {};
  if (path.closed) return {{0, n - 1, true}};
  const auto repeatOf = [&](std::size_t i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (p[j].position == p[i].position) return j;
    }
    return n;
  };
  std::vector<JoinedPathPart> parts;
  std::size_t i = 0;
  while (i + 1 < n) {
    const std::size_t end = repeatOf(i);
    if (end == n) {  // no ring from here: the rest is an open piece (or a trailing link)
      parts.push_back({i, n - 1, false});
      break;
    }
    parts.push_back({i, end, true});
    std::size_t next = end + 1;
    while (next < n && repeatOf(next) == n) ++next;
    if (next >= n) {
      if (end + 1 < n) parts.push_back({end, n - 1, false});
      break;
    }
    parts.push_back({end, next, false});
    i = next;
  }
  return parts;
}

}  // namespace curvedslicer
