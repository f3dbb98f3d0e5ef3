// Internal pieces of resolveNarrowStrips (narrow_strips.cpp) kept in their own sources (not part
// of the public API): lines sampled at even arc steps (narrow_strip_tracks.cpp) and the linking of
// centre beads to the open paths they continue (narrow_strip_links.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer::paths_detail {

/// A line with its arc lengths and evenly spaced samples (sample k at arc k·step).
struct Track {
  Polyline line;
  std::vector<double> cum;  // computeCumulativeLengths
  double length = 0.0;
  std::vector<Vec3> samples;
  double step = 0.0;
  int level = 0;
  bool centre = false;

  double arcOf(std::size_t k) const { return std::min(length, static_cast<double>(k) * step); }
  double arcDistance(double a, double b) const {
    const double d = std::abs(a - b);
    return line.closed ? std::min(d, length - d) : d;
  }
};

/// The point at arc length t along the line (t unwrapped: for closed lines 0 ≤ t < 2·length).
Vec3 pointAt(const Track& t, double arc);

/// The line sampled every `spacing` mm or less (evenly), with its level and centre flag.
Track makeTrack(Polyline line, int level, bool centre, double spacing);

/// The stretch [a, b] of arc length (closed lines: b < a wraps past the start), as an open line.
Polyline cutLine(const Track& t, double a, double b);

/// Joins open lines end to end by straight connectors: a pair of ends at most `reach` apart, one
/// of them a centre bead's, is joined nearest first, when the connector keeps `clearance` from
/// every other line of the level and the join does not close a chain on itself. Joined lines
/// replace the first of the two; `centre` says whether a line holds a centre bead.
/// Returns the number of connectors.
std::size_t linkOpenEnds(std::vector<Polyline>& lines, std::vector<bool>& centre, double reach,
                         double clearance, double step);

/// Shortens the open lines' ends that come closer than `delta` to another line of the level, or
/// to their own line further than `exclusion` along it (a connector passing the other end of the
/// ring piece it joined). Lines left shorter than `minLength` are removed. Returns the number of
/// ends shortened and the longest cut (mm).
std::size_t shortenCrowdedEnds(std::vector<Polyline>& lines, std::vector<bool>& centre,
                               double delta, double exclusion, double minLength, double step,
                               double& longestCut);

}  // namespace curvedslicer::paths_detail
