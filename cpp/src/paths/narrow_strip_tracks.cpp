// Lines sampled at even arc steps for resolveNarrowStrips (narrow_strips_internal.hpp).
#include "narrow_strips_internal.hpp"

namespace curvedslicer::paths_detail {

/// The point at arc length t along the line (t unwrapped: for closed lines 0 ≤ t < 2·length).
Vec3 pointAt(const Track& t, double arc) {
  const std::size_t n = t.line.points.size();
  if (n == 1 || !(t.length > 0.0)) return t.line.points.front();
  const std::size_t segments = t.line.segmentCount();
  if (t.line.closed) {
    arc = std::fmod(arc, t.length);
    if (arc < 0.0) arc += t.length;
  } else {
    arc = std::clamp(arc, 0.0, t.length);
  }
  // cum has segments + 1 entries; find the segment holding arc.
  const auto it = std::upper_bound(t.cum.begin(), t.cum.begin() + segments + 1, arc);
  std::size_t i = it == t.cum.begin() ? 0 : static_cast<std::size_t>(it - t.cum.begin()) - 1;
  i = std::min(i, segments - 1);
  const double a = t.cum[i], b = t.cum[i + 1];
  const double u = b > a ? std::clamp((arc - a) / (b - a), 0.0, 1.0) : 0.0;
  return (1.0 - u) * t.line.segmentStart(i) + u * t.line.segmentEnd(i);
}

Track makeTrack(Polyline line, int level, bool centre, double spacing) {
  Track t;
  t.line = std::move(line);
  t.level = level;
  t.centre = centre;
  t.cum = computeCumulativeLengths(t.line);
  t.length = t.line.length();
  const std::size_t n =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(t.length / spacing)));
  t.step = t.length / static_cast<double>(n);
  const std::size_t count = t.line.closed && t.length > 0.0 ? n : n + 1;
  t.samples.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    t.samples.push_back(pointAt(t, static_cast<double>(k) * t.step));
  }
  return t;
}

/// The stretch [a, b] of arc length (closed lines: b < a wraps past the start), as an open line.
Polyline cutLine(const Track& t, double a, double b) {
  Polyline out;
  if (t.line.closed && b < a) b += t.length;
  out.points.push_back(pointAt(t, a));
  const std::size_t n = t.line.points.size();
  const std::size_t rounds = t.line.closed ? 2 : 1;
  for (std::size_t r = 0; r < rounds; ++r) {
    for (std::size_t i = 0; i < n; ++i) {
      const double arc = t.cum[i] + static_cast<double>(r) * t.length;
      if (arc > a && arc < b) out.points.push_back(t.line.points[i]);
    }
  }
  out.points.push_back(pointAt(t, b));
  // Drop repeats (a cut next to a raw point).
  std::size_t w = 0;
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    if (w > 0 && (out.points[i] - out.points[w - 1]).norm() <= 1e-7) continue;
    out.points[w++] = out.points[i];
  }
  out.points.resize(w);
  return out;
}

}  // namespace curvedslicer::paths_detail
