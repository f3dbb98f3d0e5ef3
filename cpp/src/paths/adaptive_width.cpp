#include "curvedslicer/paths/adaptive_width.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace curvedslicer {

namespace {

/// Union-find root with path halving.
std::int32_t findRoot(std::vector<std::int32_t>& parent, std::int32_t v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

}  // namespace

RegionRings computeRegionRings(double halfWidth, double beadSpacing, double widthMin,
                               double widthMax, IsoValueStart start) {
  RegionRings rings;
  if (!std::isfinite(halfWidth) || !(halfWidth > 0.0)) return rings;
  const double s = beadSpacing;
  const bool fromBoundary = start == IsoValueStart::Boundary;
  // Boundary: K beads fill m exactly at w' = m/K; interior curve: K + 1 beads (k = 0 … K) at
  // w' = m/(K + ½) (the bead on the curve is centred on it).
  const double offset = fromBoundary ? 0.0 : 0.5;
  const double k = std::max(fromBoundary ? 1.0 : 0.0, std::round(halfWidth / s - offset));
  rings.wholeWidth = halfWidth / (k + offset);
  rings.width = std::clamp(rings.wholeWidth, widthMin * s, widthMax * s);
  rings.widthClamped = rings.width != rings.wholeWidth;
  // A region from its boundary too narrow for one ring of the narrowest bead (two beads across)
  // gets no ring: the thin-region rule gives it one bead on its centre line at its own width.
  if (fromBoundary && k == 1.0 && rings.wholeWidth < widthMin * s) return RegionRings{};
  if (rings.widthClamped) {
    rings.values = computeIsoValues(rings.width, halfWidth, start);
    return rings;
  }
  const double first = fromBoundary ? 0.5 : 0.0;
  const int count = static_cast<int>(k) + (fromBoundary ? 0 : 1);
  for (int i = 0; i < count; ++i) rings.values.push_back((i + first) * rings.width);
  return rings;
}

std::vector<std::int32_t> labelMeshRegions(const TriMesh& mesh, std::int32_t& count) {
  const auto n = static_cast<std::int32_t>(mesh.vertexCount());
  std::vector<std::int32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (const Vec3i& t : mesh.triangles) {
    for (int e = 0; e < 2; ++e) {
      const std::int32_t a = findRoot(parent, t[e]), b = findRoot(parent, t[e + 1]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  std::vector<std::int32_t> label(n, -1);
  count = 0;
  for (std::int32_t v = 0; v < n; ++v) {
    const std::int32_t root = findRoot(parent, v);
    if (label[root] < 0) label[root] = count++;
    label[v] = label[root];
  }
  return label;
}

}  // namespace curvedslicer
