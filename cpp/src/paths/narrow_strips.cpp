#include "curvedslicer/paths/narrow_strips.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <numbers>
#include <unordered_map>

#include "curvedslicer/core/error.hpp"
#include "narrow_strips_internal.hpp"

namespace curvedslicer {

namespace {

using paths_detail::cutLine;
using paths_detail::linkOpenEnds;
using paths_detail::makeTrack;
using paths_detail::pointAt;
using paths_detail::shortenCrowdedEnds;
using paths_detail::Track;

std::string formatMm(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.3g", value);
  return buffer;
}

std::string formatPoint(const Vec3& p) {
  char buffer[128];
  std::snprintf(buffer, sizeof(buffer), "(%.1f, %.1f, %.1f)", p.x(), p.y(), p.z());
  return buffer;
}

/// Uniform hash grid of track samples.
class SampleGrid {
 public:
  explicit SampleGrid(double cell) : cell_(cell) {}

  void add(std::uint32_t track, std::uint32_t sample, const Vec3& p) {
    cells_[key(cellOf(p))].push_back({track, sample});
  }

  /// Calls f(track, sample) for every sample in the cells within `radius` of p.
  template <typename F>
  void visit(const Vec3& p, double radius, F&& f) const {
    const Eigen::Vector3i lo = cellOf(p - Vec3::Constant(radius));
    const Eigen::Vector3i hi = cellOf(p + Vec3::Constant(radius));
    for (int x = lo.x(); x <= hi.x(); ++x) {
      for (int y = lo.y(); y <= hi.y(); ++y) {
        for (int z = lo.z(); z <= hi.z(); ++z) {
          const auto it = cells_.find(key(Eigen::Vector3i(x, y, z)));
          if (it == cells_.end()) continue;
          for (const auto& [track, sample] : it->second) f(track, sample);
        }
      }
    }
  }

 private:
  Eigen::Vector3i cellOf(const Vec3& p) const {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / cell_)),
                           static_cast<int>(std::floor(p.y() / cell_)),
                           static_cast<int>(std::floor(p.z() / cell_)));
  }
  static std::uint64_t key(const Eigen::Vector3i& c) {
    const auto u = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)); };
    return (u(c.x()) * 73856093ULL) ^ (u(c.y()) * 19349663ULL << 1) ^ (u(c.z()) * 83492791ULL << 2);
  }
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::uint32_t>>> cells_;
};

Vec3 closestOnSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double u = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return a + u * ab;
}

/// A narrow sample's nearest point on another part of its level.
struct Partner {
  int track = -1;
  std::size_t sample = 0;
  Vec3 point = Vec3::Zero();  // refined onto the facing segments
  double distance = kInf;
};

/// A maximal stretch of narrow samples of one track.
struct Run {
  int track = 0;
  std::size_t first = 0;  // sample index (closed tracks: may wrap)
  std::size_t count = 0;
  bool whole = false;  // every sample of a closed track
  int partner = -1;    // run holding most of the partners
};

/// Narrow samples, their runs and partners within one group of tracks (one level).
struct Narrowing {
  std::vector<std::vector<Partner>> partners;  // per track, per sample
  std::vector<Run> runs;
  std::vector<std::vector<int>> runOf;      // per track, per sample: run or −1
  std::vector<std::vector<int>> trackRuns;  // per track, its runs in order along it
  double closest = kInf;

  bool mutual(int a, int b) const { return a != b && runs[a].partner == b && runs[b].partner == a; }
  /// Arc length from run a's last sample to run b's first (same track, forwards).
  double gapLength(const std::vector<Track>& tracks, int a, int b) const {
    const Track& tr = tracks[runs[a].track];
    const std::size_t n = tr.samples.size();
    const std::size_t last = (runs[a].first + runs[a].count - 1) % n;
    return static_cast<double>((runs[b].first + n - last) % n) * tr.step;
  }
  /// The run before run r on its track (cyclic).
  int previousRun(int r) const {
    const std::vector<int>& rs = trackRuns[runs[r].track];
    const auto at = static_cast<std::size_t>(std::find(rs.begin(), rs.end(), r) - rs.begin());
    return rs[(at + rs.size() - 1) % rs.size()];
  }
};

/// The nearest sample to sample k of track t on another part of the level (the same track
/// further than `exclusion` along it) within `reach`, refined onto the partner's neighbouring
/// segments; track −1 when there is none.
Partner findPartner(const std::vector<Track>& tracks, const SampleGrid& grid, std::size_t t,
                    std::size_t k, double reach, double exclusion) {
  const Track& tr = tracks[t];
  const Vec3& p = tr.samples[k];
  Partner best;
  grid.visit(p, reach, [&](std::uint32_t ot, std::uint32_t ok) {
    if (ot == t && tr.arcDistance(tr.arcOf(k), tr.arcOf(ok)) <= exclusion) return;
    const double d = (tracks[ot].samples[ok] - p).norm();
    if (d < best.distance) best = {static_cast<int>(ot), ok, tracks[ot].samples[ok], d};
  });
  if (best.distance >= reach) return Partner{};
  // Refine onto the partner's neighbouring segments.
  const Track& o = tracks[best.track];
  const std::size_t m = o.samples.size();
  const std::size_t at = best.sample;
  for (const int side : {-1, 1}) {
    if (!o.line.closed && ((side < 0 && at == 0) || (side > 0 && at + 1 >= m))) continue;
    const std::size_t j = side < 0 ? (at + m - 1) % m : (at + 1) % m;
    const Vec3 q = closestOnSegment(p, o.samples[at], o.samples[j]);
    if ((q - p).norm() < best.distance) {
      best.point = q;
      best.distance = (q - p).norm();
    }
  }
  return best;
}

/// Bridges short wide stretches between narrow samples of a track: `partners` (the narrow
/// ones) takes the `nearest` partners of a stretch shorter than `bridge` whose samples all have
/// one.
void bridgeWideStretches(const Track& tr, const std::vector<Partner>& nearest, double bridge,
                         std::vector<Partner>& partners) {
  const std::size_t n = tr.samples.size();
  const auto narrow = [&](std::size_t k) { return partners[k % n].track >= 0; };
  const std::size_t maxGap =
      tr.step > 0.0 ? static_cast<std::size_t>(std::min(bridge / tr.step, double(n))) : 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!narrow(k) || narrow(k + 1)) continue;
    if (!tr.line.closed && k + 1 >= n) break;
    std::size_t gap = 1;  // wide samples after k
    while (gap <= maxGap && gap < n && !narrow(k + 1 + gap)) ++gap;
    if (gap > maxGap || gap >= n) continue;
    if (!tr.line.closed && k + 1 + gap >= n) continue;
    bool near = true;
    for (std::size_t i = 1; i <= gap; ++i) near = near && nearest[(k + i) % n].track >= 0;
    if (!near) continue;
    for (std::size_t i = 1; i <= gap; ++i) partners[(k + i) % n] = nearest[(k + i) % n];
  }
}

/// The runs of narrow samples of track t (a closed track narrow all round: one whole run).
void collectRuns(const std::vector<Track>& tracks, std::size_t t, Narrowing& g) {
  const std::size_t n = tracks[t].samples.size();
  g.runOf[t].assign(n, -1);
  const auto narrow = [&](std::size_t k) { return g.partners[t][k % n].track >= 0; };
  std::size_t start = 0;
  if (tracks[t].line.closed) {
    std::size_t wide = n;
    for (std::size_t k = 0; k < n && wide == n; ++k) {
      if (!narrow(k)) wide = k;
    }
    if (wide == n) {
      g.runs.push_back({static_cast<int>(t), 0, n, true, -1});
      std::fill(g.runOf[t].begin(), g.runOf[t].end(), static_cast<int>(g.runs.size()) - 1);
      g.trackRuns[t].push_back(static_cast<int>(g.runs.size()) - 1);
      return;
    }
    start = wide;
  }
  for (std::size_t i = 0; i < n;) {
    if (!narrow(start + i)) {
      ++i;
      continue;
    }
    Run run{static_cast<int>(t), (start + i) % n, 0, false, -1};
    while (i < n && narrow(start + i)) {
      g.runOf[t][(start + i) % n] = static_cast<int>(g.runs.size());
      ++run.count;
      ++i;
    }
    g.trackRuns[t].push_back(static_cast<int>(g.runs.size()));
    g.runs.push_back(run);
  }
}

/// Each run's partner: the run holding most of its samples' partners.
void votePartnerRuns(const std::vector<Track>& tracks, Narrowing& g) {
  for (Run& run : g.runs) {
    std::map<int, std::size_t> votes;
    const std::size_t n = tracks[run.track].samples.size();
    for (std::size_t i = 0; i < run.count; ++i) {
      const Partner& p = g.partners[run.track][(run.first + i) % n];
      const int pr = g.runOf[p.track][p.sample];
      if (pr >= 0) ++votes[pr];
    }
    std::size_t most = 0;
    for (const auto& [pr, count] : votes) {
      if (count > most) {
        most = count;
        run.partner = pr;
      }
    }
  }
}

/// `bridge`: a stretch of wide samples shorter than this (mm) between narrow ones of the same
/// track, whose samples all face a point within 1.25 × threshold, counts as narrow (so one strip
/// whose width wavers around the threshold gives one centre bead, not pieces and gaps).
/// `keepWide` (optional): per track, per sample, non-zero = never narrow (set after bridging).
Narrowing findNarrowing(const std::vector<Track>& tracks, double threshold, double exclusion,
                        double bridge, const std::vector<std::vector<char>>* keepWide = nullptr) {
  Narrowing g;
  const double reach = 1.25 * threshold;
  SampleGrid grid(reach);
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    for (std::size_t k = 0; k < tracks[t].samples.size(); ++k) {
      grid.add(static_cast<std::uint32_t>(t), static_cast<std::uint32_t>(k), tracks[t].samples[k]);
    }
  }
  g.partners.resize(tracks.size());
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    const std::size_t n = tracks[t].samples.size();
    g.partners[t].resize(n);
    std::vector<Partner> nearest(n);
    for (std::size_t k = 0; k < n; ++k) {
      nearest[k] = findPartner(tracks, grid, t, k, reach, exclusion);
      if (nearest[k].track >= 0 && nearest[k].distance < threshold) {
        g.closest = std::min(g.closest, nearest[k].distance);
        g.partners[t][k] = nearest[k];
      }
    }
    bridgeWideStretches(tracks[t], nearest, bridge, g.partners[t]);
    if (keepWide != nullptr) {
      for (std::size_t k = 0; k < n; ++k) {
        if ((*keepWide)[t][k]) g.partners[t][k] = Partner{};
      }
    }
  }
  g.runOf.resize(tracks.size());
  g.trackRuns.resize(tracks.size());
  for (std::size_t t = 0; t < tracks.size(); ++t) collectRuns(tracks, t, g);
  votePartnerRuns(tracks, g);
  return g;
}

/// The midline of run r and the points facing it; caps (short turns to the partner run on the
/// same track, flagged in capAfter) extend it to the turn's middle. dMin/dMax: separations.
Polyline drawMidline(const std::vector<Track>& tracks, const Narrowing& g, int r,
                     const std::vector<bool>& capAfter, double& dMin, double& dMax) {
  const Run& run = g.runs[r];
  const Track& tr = tracks[run.track];
  const std::size_t n = tr.samples.size();
  Polyline centre;
  centre.closed = run.whole && run.partner >= 0 && g.runs[run.partner].whole;
  dMin = kInf;
  dMax = 0.0;
  for (std::size_t i = 0; i < run.count; ++i) {
    const std::size_t k = (run.first + i) % n;
    const Partner& p = g.partners[run.track][k];
    // A run facing itself (a thin U without a break at its turn): draw only up to the fold.
    if (g.runOf[p.track][p.sample] == r && (p.sample + n - run.first) % n <= i) continue;
    centre.points.push_back(0.5 * (tr.samples[k] + p.point));
    dMin = std::min(dMin, p.distance);
    dMax = std::max(dMax, p.distance);
  }
  const auto turnMiddle = [&](int a, int b) {  // middle of the turn from run a to run b
    const double from = tr.arcOf((g.runs[a].first + g.runs[a].count - 1) % n);
    double to = tr.arcOf(g.runs[b].first);
    if (to < from) to += tr.length;
    return pointAt(tr, 0.5 * (from + to));
  };
  if (!run.whole && capAfter[r]) centre.points.push_back(turnMiddle(r, run.partner));
  if (!run.whole && run.partner >= 0 && capAfter[run.partner] && tr.line.closed &&
      g.runs[run.partner].track == run.track && g.previousRun(r) == run.partner) {
    centre.points.insert(centre.points.begin(), turnMiddle(run.partner, r));
  }
  std::size_t w = 0;
  for (std::size_t i = 0; i < centre.points.size(); ++i) {
    if (w > 0 && (centre.points[i] - centre.points[w - 1]).norm() <= 1e-7) continue;
    centre.points[w++] = centre.points[i];
  }
  centre.points.resize(w);
  if (centre.closed && centre.points.size() < 3) centre.closed = false;
  return centre;
}

/// Does run r draw the bead of its pair? The longer run of a mutual pair does (ties: lower index).
bool drawsBead(const Narrowing& g, int r) {
  const Run& run = g.runs[r];
  if (run.partner < 0 || !g.mutual(r, run.partner)) return true;
  const Run& other = g.runs[run.partner];
  return !(other.count > run.count || (other.count == run.count && run.partner < r));
}

/// The kept pieces of a track: the stretches between its runs that are not caps.
void collectPieces(const std::vector<Track>& tracks, const Narrowing& g, std::size_t t,
                   const std::vector<bool>& capAfter, std::vector<Polyline>& pieces) {
  const Track& tr = tracks[t];
  const std::vector<int>& rs = g.trackRuns[t];
  if (rs.empty()) {
    pieces.push_back(tr.line);
    return;
  }
  if (g.runs[rs[0]].whole) return;
  const std::size_t n = tr.samples.size();
  const std::size_t m = rs.size();
  const auto add = [&](double a, double b) {
    Polyline piece = cutLine(tr, a, b);
    if (piece.points.size() >= 2) pieces.push_back(std::move(piece));
  };
  if (tr.line.closed) {
    for (std::size_t i = 0; i < m; ++i) {
      if (capAfter[rs[i]]) continue;
      const Run& a = g.runs[rs[i]];
      const Run& b = g.runs[rs[(i + 1) % m]];
      add(tr.arcOf((a.first + a.count) % n), tr.arcOf((b.first + n - 1) % n));
    }
    return;
  }
  if (g.runs[rs[0]].first > 0) add(0.0, tr.arcOf(g.runs[rs[0]].first - 1));
  for (std::size_t i = 0; i + 1 < m; ++i) {
    if (capAfter[rs[i]]) continue;
    const Run& a = g.runs[rs[i]];
    add(tr.arcOf(a.first + a.count), tr.arcOf(g.runs[rs[i + 1]].first - 1));
  }
  const Run& last = g.runs[rs[m - 1]];
  if (last.first + last.count < n) add(tr.arcOf(last.first + last.count), tr.length);
}

/// Marks caps: short turns of a track between two runs that face each other.
std::vector<bool> findCaps(const std::vector<Track>& tracks, const Narrowing& g, double capLimit,
                           std::size_t& caps) {
  std::vector<bool> capAfter(g.runs.size(), false);
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    const std::vector<int>& rs = g.trackRuns[t];
    if (rs.empty() || g.runs[rs[0]].whole) continue;
    const std::size_t m = rs.size();
    for (std::size_t i = 0; i < m; ++i) {
      if (!tracks[t].line.closed && i + 1 == m) break;
      const int a = rs[i], b = rs[(i + 1) % m];
      if (g.mutual(a, b) && g.gapLength(tracks, a, b) <= capLimit) {
        capAfter[a] = true;
        ++caps;
      }
    }
  }
  return capAfter;
}

/// An output path being built: a track with the arc ranges it keeps.
struct OutPath {
  Track track;
  bool centre = false;
  std::vector<std::pair<double, double>> keep;
  std::string what;  // for warnings: "GDTC x mm near (…)"
};

void checkNarrowStripInputs(const std::vector<std::vector<Polyline>>& levels,
                            const std::vector<double>& levelValues, double spacing,
                            const NarrowStripOptions& options,
                            const std::vector<std::vector<Polyline>>& innerEdges) {
  if (!std::isfinite(spacing) || spacing <= 0.0) {
    throw InvalidInput("bead spacing must be a positive number of mm: " + formatMm(spacing) +
                       "; pass a value such as 3.7");
  }
  if (levelValues.size() != levels.size() ||
      (!innerEdges.empty() && innerEdges.size() != levels.size())) {
    throw InvalidInput("narrow strips need one iso-value (and inner edge) per level: " +
                       std::to_string(levelValues.size()) + " values, " +
                       std::to_string(innerEdges.size()) + " inner edges for " +
                       std::to_string(levels.size()) + " levels; pass one per level");
  }
  if (!std::isfinite(options.minSeparation) || options.minSeparation <= 0.0 ||
      !std::isfinite(options.margin) || options.margin < 0.0 ||
      !std::isfinite(options.innerEdgeOffset) || options.innerEdgeOffset <= 0.0) {
    throw InvalidInput(
        "narrow-strip separation and inner-edge offset must be positive, the margin not "
        "negative: " +
        formatMm(options.minSeparation) + ", " + formatMm(options.innerEdgeOffset) + ", " +
        formatMm(options.margin) + "; pass e.g. 0.95, 0.1 and 0.1");
  }
}

/// The lengths (mm) every phase of resolveNarrowStrips works with.
struct StripLengths {
  double s = 0.0;          // bead spacing
  double delta = 0.0;      // δ: paths closer than this are narrow
  double exclusion = 0.0;  // arc length along a line not compared with itself
  double h = 0.0;          // sample spacing
  double minLength = 0.0;  // shorter centre beads and pieces are dropped
  double capLimit = 0.0;   // longest turn of a thin loop replaced by a centre bead's end
  double u = 0.0;          // inner-edge offset
};

StripLengths deriveStripLengths(double spacing, const NarrowStripOptions& options) {
  StripLengths len;
  len.s = spacing;
  len.delta = options.minSeparation * len.s + options.margin;
  len.exclusion =
      options.arcExclusion < 0.0 ? 0.5 * std::numbers::pi * len.s : options.arcExclusion;
  len.h = options.sampleSpacing > 0.0 ? options.sampleSpacing : len.s / 16.0;
  len.minLength = options.minLength < 0.0 ? len.s : options.minLength;
  len.capLimit = 1.5 * len.exclusion;
  len.u = options.innerEdgeOffset;
  return len;
}

/// "GDTC x mm" of a level, for warnings.
std::string levelName(const std::vector<double>& levelValues, std::size_t level) {
  return "GDTC " + formatMm(levelValues[level]) + " mm";
}

/// Phases 1 and 2 of resolveNarrowStrips, level by level: thin rings and leftover strips become
/// output paths (pieces and centre beads, whole).
class StripCollector {
 public:
  StripCollector(const std::vector<double>& levelValues, const StripLengths& len,
                 NarrowStripResult& result)
      : levelValues_(levelValues), len_(len), result_(result) {}

  void resolveThinRings(std::size_t level, const std::vector<Polyline>& lines);
  void resolveLeftoverStrips(std::size_t level, const std::vector<Polyline>& innerEdges,
                             const std::vector<Polyline>* nextLevel);
  std::vector<OutPath>& paths() { return out_; }

 private:
  void addOut(Polyline line, int level, bool centre, std::string what) {
    OutPath o;
    o.track = makeTrack(std::move(line), level, centre, len_.h);
    o.centre = centre;
    o.keep = {{0.0, o.track.length}};
    o.what = std::move(what);
    out_.push_back(std::move(o));
  }
  std::string where(std::size_t level, const Polyline& line) const {
    return levelName(levelValues_, level) + " near " +
           formatPoint(line.points[line.points.size() / 2]);
  }
  void keepShortStretchesAsIs(std::size_t level, const std::vector<Track>& tracks, Narrowing& g,
                              std::vector<bool>& capAfter, std::size_t& caps);
  void addPiecesBetweenStrips(std::size_t level, const std::vector<Track>& tracks,
                              const Narrowing& g, const std::vector<bool>& capAfter);
  void addCentreBeads(std::size_t level, const std::vector<Track>& tracks, const Narrowing& g,
                      const std::vector<bool>& capAfter);
  std::vector<Track> collectFreeInnerEdges(std::size_t level,
                                           const std::vector<Polyline>& innerEdges,
                                           const std::vector<Polyline>* nextLevel) const;
  void addLeftoverBeads(std::size_t level, const std::vector<Track>& edges);

  const std::vector<double>& levelValues_;
  const StripLengths& len_;
  NarrowStripResult& result_;
  std::vector<OutPath> out_;
};

// ---- thin rings: lines of the level closer than δ to themselves or each other ----

void StripCollector::resolveThinRings(std::size_t level, const std::vector<Polyline>& lines) {
  const int lv = static_cast<int>(level);
  std::vector<Track> tracks;
  for (const Polyline& line : lines) {
    if (line.points.size() >= 2) tracks.push_back(makeTrack(line, lv, false, len_.h));
  }
  Narrowing g = findNarrowing(tracks, len_.delta, len_.exclusion, len_.minLength);
  result_.closestBefore = std::min(result_.closestBefore, g.closest);
  std::size_t caps = 0;
  std::vector<bool> capAfter = findCaps(tracks, g, len_.capLimit, caps);
  keepShortStretchesAsIs(level, tracks, g, capAfter, caps);
  result_.droppedCaps += caps;
  addPiecesBetweenStrips(level, tracks, g, capAfter);
  addCentreBeads(level, tracks, g, capAfter);
}

/// Short narrow stretches (an acute corner of a ring, a brief pinch): the centre bead would
/// lose about δ at every end that meets a kept piece (clearance, step 5) and be dropped for
/// its length, leaving a hole where the ring was. There the ring is kept as it is: the
/// narrowing `g` and its caps are found again without those stretches.
void StripCollector::keepShortStretchesAsIs(std::size_t level, const std::vector<Track>& tracks,
                                            Narrowing& g, std::vector<bool>& capAfter,
                                            std::size_t& caps) {
  std::vector<std::vector<char>> keepAsIs(tracks.size());
  for (std::size_t t = 0; t < tracks.size(); ++t) keepAsIs[t].assign(tracks[t].samples.size(), 0);
  std::size_t shortStretches = 0;
  double shortest = kInf;
  for (std::size_t r = 0; r < g.runs.size(); ++r) {
    const Run& run = g.runs[r];
    if (run.whole || !drawsBead(g, static_cast<int>(r))) continue;
    double dMin = 0.0, dMax = 0.0;
    const Polyline centre = drawMidline(tracks, g, static_cast<int>(r), capAfter, dMin, dMax);
    int openEnds = 2;
    if (capAfter[r]) --openEnds;
    if (run.partner >= 0 && capAfter[run.partner] && g.runs[run.partner].track == run.track &&
        g.previousRun(static_cast<int>(r)) == run.partner) {
      --openEnds;
    }
    if (centre.length() - openEnds * len_.delta >= len_.minLength) continue;
    ++shortStretches;
    shortest = std::min(shortest, dMin);
    for (const int k : {static_cast<int>(r), run.partner}) {
      if (k < 0) continue;
      const Run& q = g.runs[k];
      const std::size_t n = tracks[q.track].samples.size();
      for (std::size_t i = 0; i < q.count; ++i) keepAsIs[q.track][(q.first + i) % n] = 1;
    }
  }
  if (shortStretches == 0) return;
  g = findNarrowing(tracks, len_.delta, len_.exclusion, len_.minLength, &keepAsIs);
  caps = 0;
  capAfter = findCaps(tracks, g, len_.capLimit, caps);
  result_.keptShortStretches += shortStretches;
  result_.warnings.push_back(levelName(levelValues_, level) + ": " +
                             std::to_string(shortStretches) +
                             " short stretch(es) where paths come " + formatMm(shortest) +
                             " mm close (under " + formatMm(len_.delta) +
                             " mm; e.g. an acute corner) kept as they are: a centre bead there "
                             "would be shorter than " +
                             formatMm(len_.minLength) + " mm; the beads overlap locally");
}

void StripCollector::addPiecesBetweenStrips(std::size_t level, const std::vector<Track>& tracks,
                                            const Narrowing& g, const std::vector<bool>& capAfter) {
  std::vector<Polyline> pieces;
  for (std::size_t t = 0; t < tracks.size(); ++t) collectPieces(tracks, g, t, capAfter, pieces);
  std::size_t shortPieces = 0;
  for (Polyline& piece : pieces) {
    // Dropped now, not after the centre beads have kept clear of them.
    if (piece.length() < len_.minLength) {
      ++shortPieces;
      continue;
    }
    addOut(std::move(piece), static_cast<int>(level), false, "");
  }
  if (shortPieces > 0) {
    result_.warnings.push_back(levelName(levelValues_, level) + ": " + std::to_string(shortPieces) +
                               " piece(s) of paths between narrow stretches shorter than " +
                               formatMm(len_.minLength) + " mm not deposited");
  }
}

void StripCollector::addCentreBeads(std::size_t level, const std::vector<Track>& tracks,
                                    const Narrowing& g, const std::vector<bool>& capAfter) {
  for (std::size_t r = 0; r < g.runs.size(); ++r) {
    if (!drawsBead(g, static_cast<int>(r))) continue;
    double dMin = 0.0, dMax = 0.0;
    Polyline centre = drawMidline(tracks, g, static_cast<int>(r), capAfter, dMin, dMax);
    if (centre.points.size() < 2) continue;
    const std::string what = where(level, centre) + ": paths " + formatMm(dMin) + "–" +
                             formatMm(dMax) + " mm apart (under " + formatMm(len_.delta) +
                             " mm = 0.95·s + margin)";
    if (centre.length() < len_.minLength) {
      ++result_.droppedCentreBeads;
      result_.warnings.push_back(what + " replaced by nothing: a centre bead would be " +
                                 formatMm(centre.length()) + " mm long, under " +
                                 formatMm(len_.minLength) + " mm; under-filled there");
      continue;
    }
    result_.widestUnderfill = std::max(result_.widestUnderfill, 0.5 * dMax);
    result_.warnings.push_back(what + " replaced by one centre bead of " +
                               formatMm(centre.length()) +
                               " mm; the strip beside it is under-filled by up to " +
                               formatMm(0.5 * dMax) + " mm on each side");
    addOut(std::move(centre), static_cast<int>(level), true, what);
  }
}

// ---- leftover strips: beyond the inner edge of the beads at this level ----

void StripCollector::resolveLeftoverStrips(std::size_t level,
                                           const std::vector<Polyline>& innerEdges,
                                           const std::vector<Polyline>* nextLevel) {
  if (innerEdges.empty()) return;
  const std::vector<Track> edges = collectFreeInnerEdges(level, innerEdges, nextLevel);
  if (edges.empty()) return;
  addLeftoverBeads(level, edges);
}

/// Appends the stretches of `tr` whose samples are `free` to `edges`, as open lines.
void appendFreeStretches(const Track& tr, const std::vector<bool>& free, int lv, double h,
                         std::vector<Track>& edges) {
  const std::size_t n = tr.samples.size();
  std::size_t start = 0;
  if (tr.line.closed) {
    while (free[start]) ++start;  // a taken sample exists
  }
  for (std::size_t i = 0; i < n;) {
    if (!free[(start + i) % n]) {
      ++i;
      continue;
    }
    const std::size_t a = start + i;
    while (i < n && free[(start + i) % n]) ++i;
    const std::size_t b = start + i - 1;
    if (b > a) {
      Polyline piece = cutLine(tr, tr.arcOf(a % n), tr.arcOf(b % n));
      if (piece.points.size() >= 2) edges.push_back(makeTrack(std::move(piece), lv, false, h));
    }
  }
}

/// The level's inner edges, without the stretches next to a ring of the next level: where the
/// next level has a ring, the inner edge runs s/2 − u outside it: not a leftover.
std::vector<Track> StripCollector::collectFreeInnerEdges(
    std::size_t level, const std::vector<Polyline>& innerEdges,
    const std::vector<Polyline>* nextLevel) const {
  const int lv = static_cast<int>(level);
  std::vector<Track> next;
  if (nextLevel != nullptr) {
    for (const Polyline& line : *nextLevel) {
      if (line.points.size() >= 2) next.push_back(makeTrack(line, lv + 1, false, len_.h));
    }
  }
  const double reach = 0.5 * len_.s - len_.u + 0.25 * len_.s;
  SampleGrid nextGrid(reach);
  for (std::size_t t = 0; t < next.size(); ++t) {
    for (std::size_t k = 0; k < next[t].samples.size(); ++k) {
      nextGrid.add(static_cast<std::uint32_t>(t), static_cast<std::uint32_t>(k),
                   next[t].samples[k]);
    }
  }
  std::vector<Track> edges;
  for (const Polyline& line : innerEdges) {
    if (line.points.size() < 2) continue;
    const Track tr = makeTrack(line, lv, false, len_.h);
    const std::size_t n = tr.samples.size();
    std::vector<bool> free(n, true);
    for (std::size_t k = 0; k < n; ++k) {
      nextGrid.visit(tr.samples[k], reach, [&](std::uint32_t ot, std::uint32_t ok) {
        if ((next[ot].samples[ok] - tr.samples[k]).norm() < reach) free[k] = false;
      });
    }
    if (std::all_of(free.begin(), free.end(), [](bool f) { return f; })) {
      edges.push_back(tr);
      continue;
    }
    appendFreeStretches(tr, free, lv, len_.h, edges);
  }
  return edges;
}

/// The two sides of a leftover strip are less than s − 2u apart; its width is that + 2u.
void StripCollector::addLeftoverBeads(std::size_t level, const std::vector<Track>& edges) {
  const double s = len_.s, u = len_.u, delta = len_.delta;
  const Narrowing e = findNarrowing(edges, s, len_.exclusion, len_.minLength);
  const std::vector<bool> edgeCaps = findCaps(edges, e, len_.capLimit, result_.droppedCaps);
  std::size_t shortLeftovers = 0;
  for (std::size_t r = 0; r < e.runs.size(); ++r) {
    if (!drawsBead(e, static_cast<int>(r))) continue;
    double dMin = 0.0, dMax = 0.0;
    Polyline centre = drawMidline(edges, e, static_cast<int>(r), edgeCaps, dMin, dMax);
    if (centre.points.size() < 2) continue;
    if (centre.length() < len_.minLength) {  // a spot, like an iso-line fragment: counted only
      ++shortLeftovers;
      continue;
    }
    const std::string what = where(level, centre) + ": a leftover strip " + formatMm(dMin + 2 * u) +
                             "–" + formatMm(dMax + 2 * u) + " mm wide and about " +
                             formatMm(centre.length()) + " mm long";
    result_.warnings.push_back(what +
                               " lies beyond the inner edge of these beads; a centre bead "
                               "fills it where it is at least " +
                               formatMm(2 * delta - s) + " mm wide (" + formatMm(delta) +
                               " mm from the beads beside it), the rest is left empty");
    addOut(std::move(centre), static_cast<int>(level), true, what);
  }
  if (shortLeftovers > 0) {
    result_.warnings.push_back(levelName(levelValues_, level) + ": " +
                               std::to_string(shortLeftovers) + " leftover strip(s) shorter than " +
                               formatMm(len_.minLength) +
                               " mm beyond the inner edge of these beads left empty");
  }
}

// ---- clearance: centre beads split (longest first), then piece ends shortened ----

/// Phase 3 of resolveNarrowStrips: every output path keeps the arc ranges that are δ from the
/// paths settled before it. A centre bead yields to the pieces and to the centre beads settled
/// before it (longer ones), so two beads drawn on one ridge keep the longer one whole.
class ClearancePass {
 public:
  ClearancePass(std::vector<OutPath>& out, std::size_t levelCount, const StripLengths& len,
                NarrowStripResult& result)
      : out_(out),
        len_(len),
        result_(result),
        grid_(len.delta),
        settled_(out.size(), false),
        longestCut_(levelCount, 0.0),
        cutEnds_(levelCount, 0) {
    for (std::size_t t = 0; t < out_.size(); ++t) {
      for (std::size_t k = 0; k < out_[t].track.samples.size(); ++k) {
        grid_.add(static_cast<std::uint32_t>(t), static_cast<std::uint32_t>(k),
                  out_[t].track.samples[k]);
      }
    }
  }

  void run(const std::vector<double>& levelValues);

 private:
  bool active(std::size_t t, std::size_t k) const {
    const double arc = out_[t].track.arcOf(k);
    for (const auto& [a, b] : out_[t].keep) {
      if (arc >= a - 1e-9 && arc <= b + 1e-9) return true;
    }
    return false;
  }
  bool clear(std::size_t t, std::size_t k) const;
  std::vector<std::pair<double, double>> clearStretches(std::size_t t) const;
  std::vector<std::pair<double, double>> trimEnds(std::size_t t);
  std::vector<std::pair<double, double>> keepLongEnough(
      std::size_t t, const std::vector<std::pair<double, double>>& keep, double& keptLength) const;
  void warnAboutCentreBead(const OutPath& o, double keptLength);

  std::vector<OutPath>& out_;
  const StripLengths& len_;
  NarrowStripResult& result_;
  SampleGrid grid_;
  std::vector<bool> settled_;
  std::vector<double> longestCut_;
  std::vector<std::size_t> cutEnds_;
};

bool ClearancePass::clear(std::size_t t, std::size_t k) const {
  const Track& tr = out_[t].track;
  const Vec3& p = tr.samples[k];
  bool ok = true;
  grid_.visit(p, len_.delta, [&](std::uint32_t ot, std::uint32_t ok2) {
    if (!ok) return;
    const Track& o = out_[ot].track;
    const int dl = std::abs(o.level - tr.level);
    if (dl > 1 || (dl == 1 && !out_[t].centre)) return;
    if (ot == t && tr.arcDistance(tr.arcOf(k), tr.arcOf(ok2)) <= len_.exclusion) return;
    if (ot != t && out_[ot].centre && !settled_[ot]) return;
    if (!active(ot, ok2)) return;
    if ((o.samples[ok2] - p).norm() < len_.delta) ok = false;
  });
  return ok;
}

void ClearancePass::run(const std::vector<double>& levelValues) {
  std::vector<std::size_t> order(out_.size());
  for (std::size_t t = 0; t < out_.size(); ++t) order[t] = t;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (out_[a].centre != out_[b].centre) return out_[a].centre;
    return out_[a].centre && out_[a].track.length > out_[b].track.length;
  });
  for (const std::size_t t : order) {
    OutPath& o = out_[t];
    if (o.track.line.closed && !o.centre) {
      settled_[t] = true;
      continue;
    }
    const std::vector<std::pair<double, double>> keep = o.centre ? clearStretches(t) : trimEnds(t);
    double keptLength = 0.0;
    o.keep = keepLongEnough(t, keep, keptLength);
    settled_[t] = true;
    warnAboutCentreBead(o, keptLength);
  }
  for (std::size_t level = 0; level < cutEnds_.size(); ++level) {
    result_.shortenedEnds += cutEnds_[level];
    if (cutEnds_[level] > 0) {
      result_.warnings.push_back(
          levelName(levelValues, level) + ": " + std::to_string(cutEnds_[level]) +
          " path end(s) shortened by up to " + formatMm(longestCut_[level]) + " mm to keep " +
          formatMm(len_.delta) + " mm from the neighbouring paths; under-filled there");
    }
  }
}

/// A centre bead: every clear stretch.
std::vector<std::pair<double, double>> ClearancePass::clearStretches(std::size_t t) const {
  const Track& tr = out_[t].track;
  const std::size_t n = tr.samples.size();
  std::vector<std::pair<double, double>> keep;
  for (std::size_t k = 0; k < n;) {
    if (!clear(t, k)) {
      ++k;
      continue;
    }
    const std::size_t a = k;
    while (k < n && clear(t, k)) ++k;
    // A closed centre ring clear all round stays closed; otherwise its stretches are open.
    keep.emplace_back(tr.arcOf(a),
                      a == 0 && k == n && tr.line.closed ? tr.length : tr.arcOf(k - 1));
  }
  return keep;
}

/// An open piece: its ends shortened up to the first clear sample.
std::vector<std::pair<double, double>> ClearancePass::trimEnds(std::size_t t) {
  const Track& tr = out_[t].track;
  const std::size_t n = tr.samples.size();
  std::vector<std::pair<double, double>> keep;
  std::size_t a = 0;
  while (a < n && !clear(t, a)) ++a;
  if (a < n) {
    std::size_t b = n - 1;
    while (b > a && !clear(t, b)) --b;
    keep.emplace_back(tr.arcOf(a), tr.arcOf(b));
    for (const double cut : {tr.arcOf(a), tr.length - tr.arcOf(b)}) {
      if (cut > 0.0) {
        ++cutEnds_[tr.level];
        longestCut_[tr.level] = std::max(longestCut_[tr.level], cut);
      }
    }
  }
  return keep;
}

/// The stretches at least minLength long; those of one centre bead become separate paths, each
/// δ from those kept before it (where the midline folds back, the arc exclusion no longer
/// applies between them). `keptLength` returns their total length.
std::vector<std::pair<double, double>> ClearancePass::keepLongEnough(
    std::size_t t, const std::vector<std::pair<double, double>>& keep, double& keptLength) const {
  const OutPath& o = out_[t];
  const Track& tr = o.track;
  const std::size_t n = tr.samples.size();
  std::vector<std::pair<double, double>> longEnough;
  const auto take = [&](double a, double b) {
    if (b - a >= len_.minLength) {
      longEnough.emplace_back(a, b);
      keptLength += b - a;
    }
  };
  if (!o.centre || keep.size() <= 1) {
    for (const auto& [a, b] : keep) take(a, b);
    return longEnough;
  }
  const auto nearKept = [&](std::size_t k) {
    for (const auto& [a, b] : longEnough) {
      for (std::size_t j = 0; j < n; ++j) {
        const double arc = tr.arcOf(j);
        if (arc >= a - 1e-9 && arc <= b + 1e-9 &&
            (tr.samples[j] - tr.samples[k]).norm() < len_.delta) {
          return true;
        }
      }
    }
    return false;
  };
  for (const auto& [a, b] : keep) {
    std::size_t k = static_cast<std::size_t>(std::llround(a / tr.step));
    const std::size_t last = std::min(n - 1, static_cast<std::size_t>(std::llround(b / tr.step)));
    while (k <= last) {
      if (nearKept(k)) {
        ++k;
        continue;
      }
      const std::size_t first = k;
      while (k <= last && !nearKept(k)) ++k;
      take(tr.arcOf(first), k > last && b >= tr.length ? b : tr.arcOf(k - 1));
    }
  }
  return longEnough;
}

void ClearancePass::warnAboutCentreBead(const OutPath& o, double keptLength) {
  const Track& tr = o.track;
  if (o.centre && o.keep.empty()) {
    ++result_.droppedCentreBeads;
    result_.warnings.push_back(o.what + ": the centre bead (" + formatMm(tr.length) +
                               " mm) has no stretch of at least " + formatMm(len_.minLength) +
                               " mm that is " + formatMm(len_.delta) +
                               " mm from the other paths; dropped, the strip is left empty");
  } else if (o.centre && keptLength < tr.length - 1e-9) {
    result_.warnings.push_back(o.what + ": the centre bead keeps " + formatMm(keptLength) + " of " +
                               formatMm(tr.length) + " mm in " + std::to_string(o.keep.size()) +
                               " piece(s) (" + formatMm(len_.delta) + " mm from the other paths)");
  }
}

// ---- output ----

void emitKeptPaths(const std::vector<OutPath>& out, std::size_t levelCount,
                   NarrowStripResult& result) {
  result.levels.assign(levelCount, {});
  result.centreBead.assign(levelCount, {});
  for (const OutPath& o : out) {
    const Track& tr = o.track;
    for (const auto& [a, b] : o.keep) {
      const bool whole = a <= 0.0 && b >= tr.length;
      Polyline line = whole || (tr.line.closed && !o.centre) ? tr.line : cutLine(tr, a, b);
      if (line.points.size() < 2) continue;
      if (o.centre) ++result.centreBeads;
      result.levels[tr.level].push_back(std::move(line));
      result.centreBead[tr.level].push_back(o.centre);
    }
  }
}

// ---- linking: a centre bead continues the open path whose end is next to its own ----

void linkCentreBeads(const std::vector<double>& levelValues, const StripLengths& len,
                     double linkDistance, NarrowStripResult& result) {
  for (std::size_t level = 0; level < result.levels.size(); ++level) {
    const std::size_t links = linkOpenEnds(result.levels[level], result.centreBead[level],
                                           linkDistance, 0.5 * len.s, len.h);
    if (links == 0) continue;
    result.links += links;
    // A connector passes the other end of the piece it joined at about 0.87·δ.
    double longest = 0.0;
    const std::size_t cut =
        shortenCrowdedEnds(result.levels[level], result.centreBead[level], len.delta, len.exclusion,
                           len.minLength, len.h, longest);
    if (cut > 0) {
      result.shortenedEnds += cut;
      result.warnings.push_back(levelName(levelValues, level) + ": " + std::to_string(cut) +
                                " path end(s) beside a joined centre " +
                                "bead shortened by up to " + formatMm(longest) + " mm to keep " +
                                formatMm(len.delta) + " mm from it; under-filled there");
    }
  }
}

}  // namespace

NarrowStripResult resolveNarrowStrips(const std::vector<std::vector<Polyline>>& levels,
                                      const std::vector<double>& levelValues, double spacing,
                                      const NarrowStripOptions& options,
                                      const std::vector<std::vector<Polyline>>& innerEdges) {
  checkNarrowStripInputs(levels, levelValues, spacing, options, innerEdges);
  const StripLengths len = deriveStripLengths(spacing, options);
  NarrowStripResult result;
  StripCollector collector(levelValues, len, result);
  for (std::size_t level = 0; level < levels.size(); ++level) {
    collector.resolveThinRings(level, levels[level]);
    if (innerEdges.empty()) continue;
    collector.resolveLeftoverStrips(level, innerEdges[level],
                                    level + 1 < levels.size() ? &levels[level + 1] : nullptr);
  }
  std::vector<OutPath>& out = collector.paths();
  ClearancePass(out, levels.size(), len, result).run(levelValues);
  emitKeptPaths(out, levels.size(), result);
  const double linkDistance = options.linkDistance < 0.0 ? 1.25 * len.delta : options.linkDistance;
  if (linkDistance > 0.0) linkCentreBeads(levelValues, len, linkDistance, result);
  return result;
}

}  // namespace curvedslicer
