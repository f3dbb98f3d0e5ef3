// Linking for resolveNarrowStrips (narrow_strips_internal.hpp): a centre bead continues the open
// path whose end is next to its own; ends crowded by the connectors are shortened.
#include <array>

#include "narrow_strips_internal.hpp"

namespace curvedslicer::paths_detail {

namespace {

/// Removes the lines with fewer than 2 points, and their `centre` flags, keeping the order.
void dropShortLines(std::vector<Polyline>& lines, std::vector<bool>& centre) {
  std::size_t w = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].points.size() < 2) continue;
    if (w != i) {
      lines[w] = std::move(lines[i]);
      centre[w] = centre[i];
    }
    ++w;
  }
  lines.resize(w);
  centre.resize(w);
}

/// Smallest distance from the segment a–b, sampled every `step`, to the lines other than
/// `skipA` and `skipB`.
double connectorClearance(const std::vector<Polyline>& lines, std::size_t skipA, std::size_t skipB,
                          const Vec3& a, const Vec3& b, double step) {
  const double length = (b - a).norm();
  const std::size_t n =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(length / step)));
  double nearest = kInf;
  for (std::size_t k = 0; k <= n; ++k) {
    const Vec3 p = a + (static_cast<double>(k) / static_cast<double>(n)) * (b - a);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      if (i == skipA || i == skipB) continue;
      nearest = std::min(nearest, closestPointOnPolyline(lines[i], p).distance);
    }
  }
  return nearest;
}

}  // namespace

/// Joins open lines end to end by straight connectors: a pair of ends at most `reach` apart, one
/// of them a centre bead's, is joined nearest first, when the connector keeps `clearance` from
/// every other line of the level and the join does not close a chain on itself. Joined lines
/// replace the first of the two; `centre` says whether a line holds a centre bead.
/// Returns the number of connectors.
std::size_t linkOpenEnds(std::vector<Polyline>& lines, std::vector<bool>& centre, double reach,
                         double clearance, double step) {
  struct End {
    std::size_t line;
    bool atEnd;  // the line's last point (else its first)
  };
  struct Pair {
    double distance;
    End a, b;
  };
  const auto endPoint = [&](const End& e) -> const Vec3& {
    return e.atEnd ? lines[e.line].points.back() : lines[e.line].points.front();
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].closed || lines[i].points.size() < 2) continue;
    for (std::size_t j = i + 1; j < lines.size(); ++j) {
      if (lines[j].closed || lines[j].points.size() < 2 || !(centre[i] || centre[j])) continue;
      for (const bool ei : {false, true}) {
        for (const bool ej : {false, true}) {
          const End a{i, ei}, b{j, ej};
          const double d = (endPoint(a) - endPoint(b)).norm();
          if (d <= reach) pairs.push_back({d, a, b});
        }
      }
    }
  }
  if (pairs.empty()) return 0;
  std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) {
    if (x.distance != y.distance) return x.distance < y.distance;
    if (x.a.line != y.a.line) return x.a.line < y.a.line;
    if (x.b.line != y.b.line) return x.b.line < y.b.line;
    return x.a.atEnd < y.a.atEnd || (x.a.atEnd == y.a.atEnd && x.b.atEnd < y.b.atEnd);
  });
  // Chains: every original line belongs to one chain (its current owner line index); an end can
  // take one connector.
  std::vector<std::size_t> owner(lines.size());
  for (std::size_t i = 0; i < lines.size(); ++i) owner[i] = i;
  const auto root = [&](std::size_t i) {
    while (owner[i] != i) i = owner[i];
    return i;
  };
  std::vector<std::array<bool, 2>> used(lines.size(), {false, false});
  // Where each original end now sits: its chain's line and whether at that line's end.
  std::vector<std::array<End, 2>> at(lines.size());
  for (std::size_t i = 0; i < lines.size(); ++i) at[i] = {End{i, false}, End{i, true}};
  std::size_t links = 0;
  for (const Pair& pair : pairs) {
    if (used[pair.a.line][pair.a.atEnd] || used[pair.b.line][pair.b.atEnd]) continue;
    const std::size_t ra = root(pair.a.line), rb = root(pair.b.line);
    if (ra == rb) continue;
    const End ea = at[pair.a.line][pair.a.atEnd], eb = at[pair.b.line][pair.b.atEnd];
    if (connectorClearance(lines, ra, rb, endPoint(ea), endPoint(eb), step) < clearance) continue;
    // New chain line = (ra oriented to end at ea) + (rb oriented to start at eb).
    Polyline& la = lines[ra];
    Polyline& lb = lines[rb];
    const bool flipA = !ea.atEnd, flipB = eb.atEnd;
    if (flipA) std::reverse(la.points.begin(), la.points.end());
    if (flipB) std::reverse(lb.points.begin(), lb.points.end());
    // Ends of the original lines that sat in ra or rb move.
    for (std::size_t i = 0; i < lines.size(); ++i) {
      for (End& e : at[i]) {
        if (e.line == ra && flipA) e.atEnd = !e.atEnd;
        if (e.line == rb && flipB) e.atEnd = !e.atEnd;
      }
    }
    for (std::size_t i = 0; i < lines.size(); ++i) {
      for (End& e : at[i]) {
        if (e.line == rb) e = End{ra, e.atEnd};  // rb's end stays an end; its start is joined
      }
    }
    la.points.insert(la.points.end(), lb.points.begin(), lb.points.end());
    lb.points.clear();
    centre[ra] = centre[ra] || centre[rb];
    owner[rb] = ra;
    used[pair.a.line][pair.a.atEnd] = true;
    used[pair.b.line][pair.b.atEnd] = true;
    ++links;
  }
  dropShortLines(lines, centre);
  return links;
}

/// Shortens the open lines' ends that come closer than `delta` to another line of the level, or
/// to their own line further than `exclusion` along it (a connector passing the other end of the
/// ring piece it joined). Lines left shorter than `minLength` are removed. Returns the number of
/// ends shortened and the longest cut (mm).
std::size_t shortenCrowdedEnds(std::vector<Polyline>& lines, std::vector<bool>& centre,
                               double delta, double exclusion, double minLength, double step,
                               double& longestCut) {
  std::size_t cut = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].closed || lines[i].points.size() < 2) continue;
    const Track tr = makeTrack(lines[i], 0, false, step);
    const std::size_t n = tr.samples.size();
    const auto clear = [&](std::size_t k) {
      const Vec3& p = tr.samples[k];
      for (std::size_t j = 0; j < lines.size(); ++j) {
        if (j == i || lines[j].points.size() < 2) continue;
        if (closestPointOnPolyline(lines[j], p).distance < delta) return false;
      }
      for (std::size_t m = 0; m < n; ++m) {
        if (tr.arcDistance(tr.arcOf(k), tr.arcOf(m)) > exclusion &&
            (tr.samples[m] - p).norm() < delta) {
          return false;
        }
      }
      return true;
    };
    std::size_t a = 0;
    while (a < n && !clear(a)) ++a;
    if (a == n) {
      lines[i].points.clear();
      ++cut;
      longestCut = std::max(longestCut, tr.length);
      continue;
    }
    std::size_t b = n - 1;
    while (b > a && !clear(b)) --b;
    if (a == 0 && b == n - 1) continue;
    const double from = tr.arcOf(a), to = b + 1 == n ? tr.length : tr.arcOf(b);
    cut += (a > 0 ? 1 : 0) + (b + 1 < n ? 1 : 0);
    longestCut = std::max({longestCut, from, tr.length - to});
    lines[i] = to - from >= minLength ? cutLine(tr, from, to) : Polyline{};
  }
  dropShortLines(lines, centre);
  return cut;
}

}  // namespace curvedslicer::paths_detail
