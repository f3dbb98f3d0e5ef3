#include "curvedslicer/paths/thin_regions.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <numeric>
#include <optional>
#include <queue>
#include <string>
#include <tuple>
#include <utility>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/paths/path_fit.hpp"
#include "paths_internal.hpp"

namespace curvedslicer {

namespace {

using paths_detail::formatNumber;

/// Union-find over vertex indices (path halving, union by index so labels are deterministic).
struct DisjointSets {
  std::vector<std::int32_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::int32_t find(std::int32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
  void unite(std::int32_t a, std::int32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

/// What the search needs of one region.
struct RegionInfo {
  double area = 0.0;
  Vec3 weightedCentroid = Vec3::Zero();
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  double maxDistance = -1.0;
  std::int32_t top = -1;                   // vertex with the largest GDTC (lowest index on ties)
  std::vector<std::pair<Vec3, Vec3>> rim;  // boundary edges of the region
};

/// The inscribed disc of a region: its centre and radius.
struct Inscribed {
  Vec3 centre = Vec3::Zero();
  double radius = 0.0;
};

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

/// Cheapest-path tree from one vertex over the region's edges; `arc` is the geometric length
/// along the tree path.
struct RidgeTree {
  std::vector<std::int32_t> parent;
  std::vector<double> arc;
  std::int32_t farthest = -1;  // largest arc among vertices with GDTC ≥ m/2 (the ridge's reach)
};

/// How an end of the centre line moves: outward by `shift` along `out` (negative: inward).
struct EndFit {
  Vec3 out = Vec3::UnitX();  ///< unit, the line's direction at the end, pointing out of it
  double shift = 0.0;        ///< mm
};

}  // namespace

struct ThinRegionPlanner::Impl {
  const TriMesh& mesh;
  const std::vector<double>& distance;
  ThinRegionOptions options;
  double s = 0.0;
  double minWidth = 0.0;
  std::vector<std::int32_t> triangleRegion;  // -1: a corner without GDTC
  std::vector<std::int32_t> vertexRegion;    // -1: no valid triangle
  std::vector<RegionInfo> regions;
  /// One region holding every triangle (the usual layer): every point is in region 0.
  bool singleRegion = false;
  // Built on first use (most layers have no region without a ring bead, and then need neither):
  std::optional<TriangleBvh> bvh;                       // closest points, regionAt / widthsAt
  std::vector<std::int32_t> adjacencyStart, adjacency;  // CSR over valid triangles' edges
  bool topology = false;                                // adjacency and region rims built

  Impl(const TriMesh& m, const std::vector<double>& d, const ThinRegionOptions& o)
      : mesh(m), distance(d), options(o), s(o.beadSpacing) {
    minWidth = o.minFeatureWidth < 0.0 ? 0.5 * s : o.minFeatureWidth;
    labelRegions();
    singleRegion = regions.size() == 1 && std::find(triangleRegion.begin(), triangleRegion.end(),
                                                    -1) == triangleRegion.end();
  }

  /// The closest-point tree of the mesh, built on the first call.
  const TriangleBvh& tree() {
    if (!bvh) bvh.emplace(mesh);
    return *bvh;
  }
  /// Builds the adjacency and the region rims on the first call (planRegion, widthsAt need them).
  void buildTopology() {
    if (topology) return;
    buildAdjacency();
    collectRims();
    topology = true;
  }

  bool validTriangle(std::size_t t) const {
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(distance[mesh.triangles[t][k]])) return false;
    }
    return true;
  }

  bool fixedWidth() const { return options.widthMin == 1.0 && options.widthMax == 1.0; }
  double beadWidthFor(double regionWidth) const {
    if (fixedWidth()) return s;
    return std::clamp(regionWidth, options.widthMin * s, options.widthMax * s);
  }
  void labelRegions();
  void buildAdjacency();
  void collectRims();
  EndFit findEndShift(std::int32_t region, const Polyline& line, double w) const;
  double clearance(std::int32_t region, const Vec3& p) const;
  double clearanceAbove(std::int32_t region, const Vec3& p, double floor,
                        std::size_t& nearest) const;
  Inscribed findInscribed(std::int32_t region) const;
  std::int32_t regionAt(const Vec3& p, ClosestPoint& hint);
  double distanceAt(const ClosestPoint& c) const;
  RidgeTree searchRidge(std::int32_t from, double m) const;
  Polyline findCentreLine(std::int32_t region) const;
  bool findRimSpan(std::int32_t region, const Vec3& p, const Vec3& across, const Vec3& normal,
                   double& plus, double& minus) const;
  void centreBetweenRims(std::int32_t region, Polyline& line) const;
  void planRegion(std::int32_t region, ThinRegionResult& result) const;
};

void ThinRegionPlanner::Impl::labelRegions() {
  DisjointSets sets(mesh.vertexCount());
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (!validTriangle(t)) continue;
    const Vec3i& tri = mesh.triangles[t];
    sets.unite(tri[0], tri[1]);
    sets.unite(tri[0], tri[2]);
  }
  vertexRegion.assign(mesh.vertexCount(), -1);
  triangleRegion.assign(mesh.triangleCount(), -1);
  std::vector<std::int32_t> labelOfRoot(mesh.vertexCount(), -1);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (!validTriangle(t)) continue;
    const Vec3i& tri = mesh.triangles[t];
    const std::int32_t root = sets.find(tri[0]);
    if (labelOfRoot[root] < 0) {
      labelOfRoot[root] = static_cast<std::int32_t>(regions.size());
      regions.emplace_back();
    }
    const std::int32_t label = labelOfRoot[root];
    triangleRegion[t] = label;
    RegionInfo& r = regions[label];
    const double a = mesh.triangleArea(t);
    r.area += a;
    for (int k = 0; k < 3; ++k) {
      const std::int32_t v = tri[k];
      vertexRegion[v] = label;
      const Vec3& p = mesh.vertices[v];
      r.weightedCentroid += (a / 3.0) * p;
      r.lo = r.lo.cwiseMin(p);
      r.hi = r.hi.cwiseMax(p);
      if (distance[v] > r.maxDistance || (distance[v] == r.maxDistance && v < r.top)) {
        r.maxDistance = distance[v];
        r.top = v;
      }
    }
  }
}

void ThinRegionPlanner::Impl::buildAdjacency() {
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (triangleRegion[t] < 0) continue;
    const Vec3i& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      edges.emplace_back(tri[k], tri[(k + 1) % 3]);
      edges.emplace_back(tri[(k + 1) % 3], tri[k]);
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  adjacencyStart.assign(mesh.vertexCount() + 1, 0);
  for (const auto& e : edges) ++adjacencyStart[e.first + 1];
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) adjacencyStart[v + 1] += adjacencyStart[v];
  adjacency.resize(edges.size());
  for (std::size_t i = 0; i < edges.size(); ++i) adjacency[i] = edges[i].second;
}

/// Boundary edges: edges of exactly one triangle with a region.
void ThinRegionPlanner::Impl::collectRims() {
  std::vector<std::tuple<std::int32_t, std::int32_t, std::int32_t>> edges;  // (lo, hi, region)
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (triangleRegion[t] < 0) continue;
    const Vec3i& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = tri[k], b = tri[(k + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b), triangleRegion[t]);
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) &&
           std::get<1>(edges[j]) == std::get<1>(edges[i])) {
      ++j;
    }
    if (j - i == 1) {
      const auto [a, b, region] = edges[i];
      regions[region].rim.emplace_back(mesh.vertices[a], mesh.vertices[b]);
    }
    i = j;
  }
}

/// Straight-line distance from `p` to the region's boundary edges, mm (+inf: no boundary).
double ThinRegionPlanner::Impl::clearance(std::int32_t region, const Vec3& p) const {
  double best = kInf;
  for (const auto& [a, b] : regions[region].rim) best = std::min(best, distanceToSegment(p, a, b));
  return best;
}

/// clearance(region, p) when it exceeds `floor`; otherwise some value ≤ floor (the search stops
/// at the first edge within `floor`, trying edge `nearest` first and leaving there the nearest
/// edge found). The minimum does not depend on the order of the edges, so a value above `floor`
/// is exactly clearance's.
double ThinRegionPlanner::Impl::clearanceAbove(std::int32_t region, const Vec3& p, double floor,
                                               std::size_t& nearest) const {
  const std::vector<std::pair<Vec3, Vec3>>& rim = regions[region].rim;
  double best = distanceToSegment(p, rim[nearest].first, rim[nearest].second);
  if (best <= floor) return best;
  for (std::size_t e = 0; e < rim.size(); ++e) {
    const double d = distanceToSegment(p, rim[e].first, rim[e].second);
    if (d < best) {
      best = d;
      nearest = e;
      if (best <= floor) return best;
    }
  }
  return best;
}

/// The largest clearance over the region's vertices and a barycentric grid of step 1/4 on each
/// of its triangles (the vertex GDTC underestimates the half-width of a region a few edges wide).
Inscribed ThinRegionPlanner::Impl::findInscribed(std::int32_t region) const {
  Inscribed best;
  best.centre = mesh.vertices[regions[region].top];
  best.radius = std::max(regions[region].maxDistance, 0.0);
  if (regions[region].rim.empty()) return best;
  std::size_t nearestRim = 0;  // the previous sample's nearest edge: neighbours share it
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (triangleRegion[t] != region) continue;
    const Vec3i& tri = mesh.triangles[t];
    for (int i = 0; i <= 4; ++i) {
      for (int j = 0; i + j <= 4; ++j) {
        const Vec3 p = (i * mesh.vertices[tri[0]] + j * mesh.vertices[tri[1]] +
                        (4 - i - j) * mesh.vertices[tri[2]]) /
                       4.0;
        const double c = clearanceAbove(region, p, best.radius, nearestRim);
        if (c > best.radius) {
          best.radius = c;
          best.centre = p;
        }
      }
    }
  }
  return best;
}

std::int32_t ThinRegionPlanner::Impl::regionAt(const Vec3& p, ClosestPoint& hint) {
  if (singleRegion) return 0;
  hint = tree().closestPoint(p, hint);
  return hint.triangle < 0 ? -1 : triangleRegion[hint.triangle];
}

/// GDTC interpolated linearly on the triangle of a closest point (0 where it has no value).
double ThinRegionPlanner::Impl::distanceAt(const ClosestPoint& c) const {
  if (c.triangle < 0 || triangleRegion[c.triangle] < 0) return 0.0;
  const Vec3i& tri = mesh.triangles[c.triangle];
  const Vec3 a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]], d = mesh.vertices[tri[2]];
  const Vec3 v0 = b - a, v1 = d - a, v2 = c.point - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 0.0)) return distance[tri[0]];
  const double wb = (d11 * d20 - d01 * d21) / den, wd = (d00 * d21 - d01 * d20) / den;
  return (1.0 - wb - wd) * distance[tri[0]] + wb * distance[tri[1]] + wd * distance[tri[2]];
}

/// Dijkstra from `from` with edge cost ℓ/(d̄ + 0.1·m)² (the file comment, step 3).
RidgeTree ThinRegionPlanner::Impl::searchRidge(std::int32_t from, double m) const {
  const std::size_t n = mesh.vertexCount();
  RidgeTree tree;
  tree.parent.assign(n, -1);
  tree.arc.assign(n, 0.0);
  std::vector<double> cost(n, kInf);
  using Entry = std::pair<double, std::int32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  cost[from] = 0.0;
  queue.emplace(0.0, from);
  const double floor = 0.1 * std::max(m, 1e-6);
  double best = -1.0;
  while (!queue.empty()) {
    const auto [c, v] = queue.top();
    queue.pop();
    if (c > cost[v]) continue;
    if (distance[v] >= 0.5 * m && tree.arc[v] > best) {
      best = tree.arc[v];
      tree.farthest = v;
    }
    for (std::int32_t i = adjacencyStart[v]; i < adjacencyStart[v + 1]; ++i) {
      const std::int32_t u = adjacency[i];
      const double len = (mesh.vertices[u] - mesh.vertices[v]).norm();
      const double h = 0.5 * (distance[u] + distance[v]) + floor;
      const double next = c + len / (h * h);
      if (next < cost[u]) {
        cost[u] = next;
        tree.parent[u] = v;
        tree.arc[u] = tree.arc[v] + len;
        queue.emplace(next, u);
      }
    }
  }
  return tree;
}

namespace {

/// Two passes of a box filter `halfWindow` samples wide on each side; the end points stay.
void smoothOpenLine(std::vector<Vec3>& points, int halfWindow) {
  const int n = static_cast<int>(points.size());
  for (int pass = 0; pass < 2 && n > 2; ++pass) {
    std::vector<Vec3> out = points;
    for (int i = 1; i + 1 < n; ++i) {
      const int h = std::min({halfWindow, i, n - 1 - i});
      Vec3 sum = Vec3::Zero();
      for (int k = i - h; k <= i + h; ++k) sum += points[k];
      out[i] = sum / (2 * h + 1);
    }
    points = std::move(out);
  }
}

/// The stretch of an open line between arc lengths a < b.
Polyline cutOpenLine(const Polyline& line, double a, double b) {
  const std::vector<double> cum = computeCumulativeLengths(line);
  Polyline out;
  out.points.push_back(evaluatePolylineAt(line, a));
  for (std::size_t i = 0; i < line.points.size(); ++i) {
    if (cum[i] > a && cum[i] < b) out.points.push_back(line.points[i]);
  }
  out.points.push_back(evaluatePolylineAt(line, b));
  return out;
}

/// Arc length from the start of `line` to its first point `depth` (> 0) inward from the start
/// along −out (the ridge path may dip sideways into a corner near its end; the depth is measured
/// along the line's axis there).
double findArcAtDepth(const Polyline& line, const Vec3& out, double depth) {
  const std::vector<double> cum = computeCumulativeLengths(line);
  const Vec3 start = line.points.front();
  for (std::size_t i = 1; i < line.points.size(); ++i) {
    const double before = (start - line.points[i - 1]).dot(out);
    const double after = (start - line.points[i]).dot(out);
    if (after < depth) continue;
    const double t = after > before ? (depth - before) / (after - before) : 1.0;
    return cum[i - 1] + std::clamp(t, 0.0, 1.0) * (cum[i] - cum[i - 1]);
  }
  return cum.back();
}

/// The line with its start moved outward by front.shift (straight, along front.out) or trimmed to
/// the depth −front.shift, and likewise its end; the caller checks that something is left.
Polyline adjustEnds(const Polyline& line, const EndFit& front, const EndFit& back) {
  const double length = line.length();
  Polyline reversed = line;
  std::reverse(reversed.points.begin(), reversed.points.end());
  const double a = front.shift < 0.0 ? findArcAtDepth(line, front.out, -front.shift) : 0.0;
  double b = back.shift < 0.0 ? length - findArcAtDepth(reversed, back.out, -back.shift) : length;
  b = std::max(b, std::min(a + 1e-3, length));
  Polyline out = cutOpenLine(line, std::min(a, b), b);
  if (front.shift > 0.0) {
    out.points.insert(out.points.begin(), line.points.front() + front.shift * front.out);
  }
  if (back.shift > 0.0) out.points.push_back(line.points.back() + back.shift * back.out);
  return out;
}

}  // namespace

/// How far the start of `line` (an end of the ridge path, inside the region) must move outward
/// along the line's direction there (negative: inward, a trim) so that the bead's round end, w/2
/// beyond it, just reaches the region's tip: the farthest boundary point ahead of the end within
/// w/2 of the line's axis.
EndFit ThinRegionPlanner::Impl::findEndShift(std::int32_t region, const Polyline& line,
                                             double w) const {
  const Vec3 end = line.points.front();
  const double length = line.length();
  EndFit fit;
  // The direction of the line between w and 2·w from the end (past the end's dip into a corner).
  Vec3 out = evaluatePolylineAt(line, std::min(length / 3.0, w)) -
             evaluatePolylineAt(line, std::min(2.0 * length / 3.0, 2.0 * w));
  if (!(out.norm() > 1e-12)) {
    fit.shift = -0.5 * w;
    return fit;
  }
  out.normalize();
  fit.out = out;
  double tip = 0.0;
  for (const auto& [a, b] : regions[region].rim) {
    for (const Vec3& p : {a, b, Vec3(0.5 * (a + b))}) {
      const Vec3 r = p - end;
      const double along = r.dot(out);
      if ((r - along * out).norm() <= 0.5 * w) tip = std::max(tip, along);
    }
  }
  fit.shift = tip - 0.5 * w;
  return fit;
}

/// The ridge path A→B of the region (file comment, step 3), resampled and smoothed, not trimmed.
Polyline ThinRegionPlanner::Impl::findCentreLine(std::int32_t region) const {
  const RegionInfo& r = regions[region];
  const RidgeTree fromTop = searchRidge(r.top, r.maxDistance);
  const std::int32_t a = fromTop.farthest;
  const RidgeTree fromA = searchRidge(a, r.maxDistance);
  Polyline path;
  for (std::int32_t v = fromA.farthest; v >= 0; v = fromA.parent[v]) {
    path.points.push_back(mesh.vertices[v]);
  }
  if (path.points.size() < 2) return path;
  const double meanEdge = path.length() / static_cast<double>(path.points.size() - 1);
  const double step = std::max(meanEdge / 8.0, 1e-3);
  path = resamplePolyline(path, step);
  smoothOpenLine(path.points, static_cast<int>(std::lround(meanEdge / step)));
  return path;
}

/// Distances from `p` to the region's rim along +across and −across (unit, tangent to the
/// surface, `normal` the surface normal at p): where the rim edges cross the plane through p
/// normal to the line (spanned by across and normal), the nearest on each side. False when a side
/// has no crossing within `reach` (2·widthMax·s).
bool ThinRegionPlanner::Impl::findRimSpan(std::int32_t region, const Vec3& p, const Vec3& across,
                                          const Vec3& normal, double& plus, double& minus) const {
  const Vec3 along = across.cross(normal);
  const double reach = 2.0 * options.widthMax * s;
  plus = minus = kInf;
  for (const auto& [a, b] : regions[region].rim) {
    const double ta = (a - p).dot(along), tb = (b - p).dot(along);
    if ((ta > 0.0) == (tb > 0.0) || ta == tb) continue;
    const Vec3 x = a + (ta / (ta - tb)) * (b - a);
    if (std::abs((x - p).dot(normal)) > reach) continue;
    const double u = (x - p).dot(across);
    if (u >= 0.0) plus = std::min(plus, u);
    if (u <= 0.0) minus = std::min(minus, -u);
  }
  return plus <= reach && minus <= reach;
}

/// Adaptive width: every interior point of the centre line moves across the line to the middle
/// of the region's span there (the ridge path of a region a few edges wide runs off the medial
/// axis by up to half an edge; a bead 2·d wide there would leave a sliver on the far side).
void ThinRegionPlanner::Impl::centreBetweenRims(std::int32_t region, Polyline& line) const {
  const std::vector<Vec3> points = line.points;
  ClosestPoint hint;
  for (std::size_t i = 1; i + 1 < points.size(); ++i) {
    hint = bvh->closestPoint(points[i], hint);  // built by plan() before adaptive regions
    if (hint.triangle < 0) continue;
    const Vec3 normal = mesh.areaNormal(hint.triangle).normalized();
    Vec3 tangent = points[i + 1] - points[i - 1];
    tangent -= tangent.dot(normal) * normal;
    if (!(tangent.norm() > 1e-9)) continue;
    const Vec3 across = normal.cross(tangent.normalized());
    double plus = 0.0, minus = 0.0;
    if (findRimSpan(region, points[i], across, normal, plus, minus)) {
      line.points[i] = points[i] + 0.5 * (plus - minus) * across;
    }
  }
}

void ThinRegionPlanner::Impl::planRegion(std::int32_t region, ThinRegionResult& result) const {
  const RegionInfo& r = regions[region];
  ThinRegion info;
  info.area = r.area;
  info.centroid = r.area > 0.0 ? Vec3(r.weightedCentroid / r.area) : mesh.vertices[r.top];
  info.extent = (r.hi - r.lo).maxCoeff();
  const Inscribed inscribed = findInscribed(region);
  info.width = 2.0 * inscribed.radius;
  if (info.width < minWidth) {
    info.leftOut = true;
    result.regions.push_back(info);
    return;
  }
  const double w = beadWidthFor(info.width);
  const Polyline centre = findCentreLine(region);
  const double length = centre.length();
  ThinBead bead;
  bead.width = w;
  EndFit front, back;
  if (centre.points.size() >= 2) {
    front = findEndShift(region, centre, w);
    Polyline reversed = centre;
    std::reverse(reversed.points.begin(), reversed.points.end());
    back = findEndShift(region, reversed, w);
  }
  if (centre.points.size() >= 2 && length + front.shift + back.shift >= 0.25 * w) {
    bead.kind = ThinBeadKind::CentreLine;
    bead.line = adjustEnds(centre, front, back);
    if (!fixedWidth()) centreBetweenRims(region, bead.line);
  } else {
    bead.kind = ThinBeadKind::Spot;
    const Vec3 middle = inscribed.centre;
    Vec3 along = centre.points.size() >= 2 ? Vec3(centre.points.back() - centre.points.front())
                                           : Vec3::Zero();
    if (!(along.norm() > 1e-9)) along = r.hi - r.lo;
    if (!(along.norm() > 1e-9)) along = Vec3::UnitX();
    along.normalize();
    const double half = 0.5 * options.spotSeparation;
    bead.line.points = {middle - half * along, middle + half * along};
    // A spot covers the disc of its width: wide enough to reach the island's farthest rim point
    // (an island longer than it is wide), within the allowed range (fixed width: s).
    double reach = 0.0;
    for (const auto& [a, b] : r.rim) {
      reach = std::max({reach, (a - middle).norm(), (b - middle).norm()});
    }
    bead.width = beadWidthFor(std::max(info.width, 2.0 * reach));
  }
  info.kind = bead.kind;
  result.regions.push_back(info);
  result.beads.push_back(std::move(bead));
}

double ThinRegionPlanner::beadWidthFor(double regionWidth) const {
  return impl_->beadWidthFor(regionWidth);
}

ThinRegionPlanner::ThinRegionPlanner(const TriMesh& mesh, const std::vector<double>& distance,
                                     const ThinRegionOptions& options) {
  if (distance.size() != mesh.vertexCount()) {
    throw InvalidInput(
        "thin regions need one GDTC value per vertex: " + std::to_string(distance.size()) +
        " values for " + std::to_string(mesh.vertexCount()) +
        " vertices; pass the field of the same mesh");
  }
  if (!std::isfinite(options.beadSpacing) || options.beadSpacing <= 0.0) {
    throw InvalidInput("bead spacing must be a positive number of mm: " +
                       formatNumber(options.beadSpacing) + "; pass a value such as 3.7");
  }
  if (!std::isfinite(options.minFeatureWidth) || options.minFeatureWidth == 0.0) {
    throw InvalidInput("minimum feature width must be a positive number of mm: " +
                       formatNumber(options.minFeatureWidth) +
                       "; pass a value such as 1.85, or a negative one for half the bead spacing");
  }
  if (!std::isfinite(options.widthMin) || !std::isfinite(options.widthMax) ||
      !(options.widthMin > 0.0) || options.widthMin > 1.0 || options.widthMax < 1.0) {
    throw InvalidInput("bead width range must hold the bead spacing, 0 < min <= 1 <= max: " +
                       formatNumber(options.widthMin) + "," + formatNumber(options.widthMax) +
                       "; pass e.g. 0.7,1.3, or 1,1 for a fixed width");
  }
  if (!std::isfinite(options.spotSeparation) || options.spotSeparation < 0.05) {
    throw InvalidInput("spot point separation must be at least 0.05 mm: " +
                       formatNumber(options.spotSeparation) + "; pass e.g. 0.1");
  }
  impl_ = std::make_unique<Impl>(mesh, distance, options);
}

ThinRegionPlanner::~ThinRegionPlanner() = default;

ThinRegionResult ThinRegionPlanner::plan(const std::vector<Polyline>& beads,
                                         const std::vector<Polyline>& shortRings) const {
  ThinRegionResult result;
  result.regionCount = impl_->regions.size();
  std::vector<char> covered(impl_->regions.size(), 0);
  for (const Polyline& bead : beads) {
    ClosestPoint hint;
    for (const Vec3& p : bead.points) {
      const std::int32_t region = impl_->regionAt(p, hint);
      if (region >= 0) covered[region] = 1;
    }
  }
  // Step 1: short rings in regions without beads are their only cover.
  std::vector<char> ringCovered(impl_->regions.size(), 0);
  for (const Polyline& ring : shortRings) {
    if (ring.points.empty()) continue;
    ClosestPoint hint;
    const std::int32_t region = impl_->regionAt(ring.points.front(), hint);
    if (region < 0 || covered[region]) continue;
    ThinBead bead;
    bead.kind = ThinBeadKind::KeptRing;
    bead.line = ring;
    bead.width = impl_->s;
    result.beads.push_back(std::move(bead));
    ringCovered[region] = 1;
  }
  for (std::size_t region = 0; region < impl_->regions.size(); ++region) {
    if (covered[region] || ringCovered[region]) continue;
    impl_->buildTopology();
    if (!impl_->fixedWidth()) impl_->tree();  // centreBetweenRims needs closest points
  }
  for (std::size_t region = 0; region < impl_->regions.size(); ++region) {
    if (covered[region]) continue;
    if (ringCovered[region]) {
      const RegionInfo& r = impl_->regions[region];
      ThinRegion info;
      info.area = r.area;
      info.centroid = r.area > 0.0 ? Vec3(r.weightedCentroid / r.area) : Vec3::Zero();
      info.extent = (r.hi - r.lo).maxCoeff();
      info.width = 2.0 * std::max(r.maxDistance, 0.0);
      info.kind = ThinBeadKind::KeptRing;
      result.regions.push_back(info);
      continue;
    }
    impl_->planRegion(static_cast<std::int32_t>(region), result);
  }
  return result;
}

std::vector<double> ThinRegionPlanner::widthsAt(const std::vector<Vec3>& points) const {
  if (impl_->fixedWidth()) return std::vector<double>(points.size(), impl_->s);
  std::vector<double> widths = localWidthsAt(points);
  for (double& w : widths) w = beadWidthFor(w);
  return widths;
}

std::vector<double> ThinRegionPlanner::localWidthsAt(const std::vector<Vec3>& points) const {
  std::vector<double> widths;
  widths.reserve(points.size());
  ClosestPoint hint;
  for (const Vec3& p : points) {
    impl_->buildTopology();
    hint = impl_->tree().closestPoint(p, hint);
    double half = impl_->distanceAt(hint);
    const std::int32_t region = hint.triangle < 0 ? -1 : impl_->triangleRegion[hint.triangle];
    if (region >= 0) half = std::max(half, std::min(impl_->clearance(region, hint.point), kInf));
    widths.push_back(2.0 * half);
  }
  return widths;
}

}  // namespace curvedslicer
