// Iso-lines by marching triangles (see curvedslicer/paths/iso_lines.hpp).
#include "curvedslicer/paths/iso_lines.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "curvedslicer/core/error.hpp"
#include "paths/paths_internal.hpp"

namespace curvedslicer {

namespace paths_detail {

namespace {

/// The crossed edges (one point each) and crossed triangles (one segment each, directed so that
/// the side above the level is on the left) of one level, in triangle order.
struct LevelSegments {
  struct Segment {
    std::int32_t from, to;
  };
  std::unordered_map<std::uint64_t, std::int32_t> nodeOfEdge;
  std::vector<Vec3> nodePoints;
  std::vector<Segment> segments;
};

/// Adds triangle `tri`'s segment of `level` (the caller has checked that the level crosses it).
void addTriangle(const TriMesh& mesh, const std::vector<double>& f, const Vec3i& tri, double level,
                 const CrossingPlacer& place, LevelSegments& out) {
  auto nodeFor = [&](std::int32_t a, std::int32_t b) {
    const auto [it, inserted] =
        out.nodeOfEdge.try_emplace(edgeKey(a, b), static_cast<std::int32_t>(out.nodePoints.size()));
    if (inserted) {
      // Interpolate from the lower index so both triangles of the edge get the same point.
      const std::int32_t lo = std::min(a, b), hi = std::max(a, b);
      const double fl = f[lo], fh = f[hi];
      const double t = std::clamp((level - fl) / (fh - fl), 0.0, 1.0);
      out.nodePoints.push_back(
          place ? place(lo, hi, t)
                : Vec3(mesh.vertices[lo] + t * (mesh.vertices[hi] - mesh.vertices[lo])));
    }
    return it->second;
  };
  bool above[3];
  for (int k = 0; k < 3; ++k) above[k] = f[tri[k]] >= level;
  std::int32_t start = -1, end = -1;
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    if (above[k] && !above[k1]) start = nodeFor(tri[k], tri[k1]);
    if (!above[k] && above[k1]) end = nodeFor(tri[k], tri[k1]);
  }
  if (start != end) out.segments.push_back({start, end});
}

/// Chains one level's segments into polylines.
std::vector<Polyline> chainSegments(const LevelSegments& level) {
  const auto& segments = level.segments;
  const auto& nodePoints = level.nodePoints;
  // Undirected adjacency (a node has ≤ 2 segments on a manifold; more ends the chain there).
  const std::size_t nodes = nodePoints.size();
  std::vector<std::vector<std::int32_t>> nodeSegments(nodes);
  for (std::size_t s = 0; s < segments.size(); ++s) {
    nodeSegments[segments[s].from].push_back(static_cast<std::int32_t>(s));
    nodeSegments[segments[s].to].push_back(static_cast<std::int32_t>(s));
  }
  std::vector<char> used(segments.size(), 0);
  auto otherEnd = [&](std::int32_t s, std::int32_t node) {
    return segments[s].from == node ? segments[s].to : segments[s].from;
  };
  auto nextSegment = [&](std::int32_t node, std::int32_t via) -> std::int32_t {
    if (nodeSegments[node].size() != 2) return -1;
    const std::int32_t s =
        nodeSegments[node][0] == via ? nodeSegments[node][1] : nodeSegments[node][0];
    return used[s] ? -1 : s;
  };
  std::vector<Polyline> lines;
  for (std::size_t s0 = 0; s0 < segments.size(); ++s0) {
    if (used[s0]) continue;
    // Walk backwards from s0's start to find the chain's beginning (or detect a cycle).
    std::int32_t seg = static_cast<std::int32_t>(s0);
    std::int32_t node = segments[s0].from;
    bool cycle = false;
    for (;;) {
      if (nodeSegments[node].size() != 2) break;
      const std::int32_t prev =
          nodeSegments[node][0] == seg ? nodeSegments[node][1] : nodeSegments[node][0];
      if (used[prev]) break;
      if (prev == static_cast<std::int32_t>(s0)) {
        cycle = true;
        break;
      }
      seg = prev;
      node = otherEnd(prev, node);
    }
    if (cycle) {
      seg = static_cast<std::int32_t>(s0);
      node = segments[s0].from;
    }
    // Walk forward collecting nodes.
    std::vector<std::int32_t> chainNodes{node};
    std::size_t forward = 0, backward = 0;
    while (seg >= 0) {
      used[seg] = 1;
      (segments[seg].from == node ? forward : backward) += 1;
      node = otherEnd(seg, node);
      chainNodes.push_back(node);
      seg = nextSegment(node, seg);
    }
    Polyline line;
    line.closed = cycle || (chainNodes.size() > 3 && chainNodes.front() == chainNodes.back());
    if (line.closed) chainNodes.pop_back();
    if (backward > forward) std::reverse(chainNodes.begin(), chainNodes.end());
    for (const std::int32_t n : chainNodes) {
      const Vec3& p = nodePoints[n];
      if (!line.points.empty() && (line.points.back() - p).squaredNorm() == 0.0) continue;
      line.points.push_back(p);
    }
    if (line.closed && line.points.size() > 1 &&
        (line.points.back() - line.points.front()).squaredNorm() == 0.0) {
      line.points.pop_back();
    }
    if (line.closed && line.points.size() < 3) line.closed = false;
    if (line.points.size() >= 2) lines.push_back(std::move(line));
  }
  return lines;
}

}  // namespace

std::vector<std::vector<Polyline>> traceLevelSets(const TriMesh& mesh, const std::vector<double>& f,
                                                  const std::vector<double>& levels,
                                                  const CrossingPlacer& place) {
  // Levels in increasing order (indices into `levels`): a triangle is crossed by exactly the
  // levels in (min, max] of its corner values, found by binary search.
  std::vector<std::size_t> order(levels.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return levels[a] < levels[b]; });
  std::vector<double> sorted(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = levels[order[i]];
  std::vector<LevelSegments> perLevel(levels.size());
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3i& tri = mesh.triangles[t];
    const double a = f[tri[0]], b = f[tri[1]], c = f[tri[2]];
    if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c)) continue;
    const double lo = std::min({a, b, c}), hi = std::max({a, b, c});
    // First level > lo (vertices at a level count as above it, so a level equal to the minimum
    // leaves every corner above), then every level <= hi.
    for (auto it = std::upper_bound(sorted.begin(), sorted.end(), lo);
         it != sorted.end() && *it <= hi; ++it) {
      const std::size_t k = order[static_cast<std::size_t>(it - sorted.begin())];
      addTriangle(mesh, f, tri, levels[k], place, perLevel[k]);
    }
  }
  std::vector<std::vector<Polyline>> lines(levels.size());
  for (std::size_t k = 0; k < levels.size(); ++k) lines[k] = chainSegments(perLevel[k]);
  return lines;
}

std::vector<Polyline> traceLevelSet(const TriMesh& mesh, const std::vector<double>& f, double level,
                                    const CrossingPlacer& place) {
  return std::move(traceLevelSets(mesh, f, {level}, place).front());
}

}  // namespace paths_detail

namespace {

void checkIsoInputs(const TriMesh& mesh, const std::vector<double>& field,
                    const std::vector<double>& values) {
  if (field.size() != mesh.vertexCount()) {
    throw InvalidInput("iso-line field size differs from the vertex count: " +
                       std::to_string(field.size()) + " values for " +
                       std::to_string(mesh.vertexCount()) + " vertices; pass one value per vertex");
  }
  for (const double value : values) {
    if (!std::isfinite(value)) {
      throw InvalidInput("iso-line value is not finite: " + std::to_string(value) +
                         "; pass a finite value");
    }
  }
}

}  // namespace

std::vector<Polyline> extractIsoLines(const TriMesh& mesh, const std::vector<double>& field,
                                      double value) {
  checkIsoInputs(mesh, field, {value});
  return paths_detail::traceLevelSet(mesh, field, value);
}

std::vector<std::vector<Polyline>> extractIsoLines(const TriMesh& mesh,
                                                   const std::vector<double>& field,
                                                   const std::vector<double>& values) {
  checkIsoInputs(mesh, field, values);
  return paths_detail::traceLevelSets(mesh, field, values);
}

std::vector<double> computeIsoValues(double spacing, double maxValue, IsoValueStart start) {
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InvalidInput("bead spacing must be positive: " + std::to_string(spacing) +
                       " mm; pass a value such as 3.7");
  }
  std::vector<double> values;
  if (!(maxValue >= 0.0)) return values;
  const double offset = start == IsoValueStart::Boundary ? 0.5 : 0.0;
  const double count = std::floor(maxValue / spacing - offset) + 1.0;
  if (count > 1e6) {
    throw InvalidInput("too many bead paths for the spacing: " + std::to_string(count) +
                       " paths of " + std::to_string(spacing) + " mm; pass a larger bead spacing");
  }
  for (int k = 0; k < static_cast<int>(count); ++k) {
    const double v = (k + offset) * spacing;
    if (v <= maxValue) values.push_back(v);
  }
  return values;
}

}  // namespace curvedslicer
