#include "curvedslicer/paths/gap_fill.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "curvedslicer/core/error.hpp"
#include "paths_internal.hpp"

namespace curvedslicer {

namespace {

using paths_detail::formatNumber;

/// One bead segment with the bead's width at both ends, mm.
struct WideSegment {
  Vec3 a, b;
  double widthA = 0.0, widthB = 0.0;
};

/// Distance from `p` to the edge of the bead along segment g (negative inside the bead).
double distanceBeyondBead(const Vec3& p, const WideSegment& g) {
  const Vec3 ab = g.b - g.a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - g.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  const double w = g.widthA + t * (g.widthB - g.widthA);
  return (p - (g.a + t * ab)).norm() - 0.5 * w;
}

std::vector<WideSegment> collectWideSegments(const std::vector<LayerBead>& beads, double s) {
  std::vector<WideSegment> segments;
  for (const LayerBead& bead : beads) {
    const std::vector<Vec3>& pts = bead.line->points;
    const std::size_t n = pts.size();
    const auto widthAt = [&](std::size_t i) {
      return i < bead.widths.size() && bead.widths[i] > 0.0 ? bead.widths[i] : s;
    };
    if (n == 1) segments.push_back({pts[0], pts[0], widthAt(0), widthAt(0)});
    const std::size_t count = n < 2 ? 0 : (bead.line->closed && n >= 3 ? n : n - 1);
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t j = (i + 1) % n;
      segments.push_back({pts[i], pts[j], widthAt(i), widthAt(j)});
    }
  }
  return segments;
}

/// A dense grid of cells `cell` wide over a box; each cell lists the segments whose bead, grown
/// by `reach`, touches it.
class SegmentGrid {
 public:
  SegmentGrid(const std::vector<WideSegment>& segments, const Aabb& box, double cell, double reach)
      : origin_(box.min), cell_(cell) {
    const Vec3 size = box.size();
    for (int k = 0; k < 3; ++k) {
      dims_[k] = std::max(1, static_cast<int>(std::ceil(size[k] / cell)) + 1);
    }
    cells_.resize(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2]);
    for (std::size_t i = 0; i < segments.size(); ++i) {
      const WideSegment& g = segments[i];
      const Vec3 grow = Vec3::Constant(0.5 * std::max(g.widthA, g.widthB) + reach);
      const std::array<int, 3> lo = cellOf(g.a.cwiseMin(g.b) - grow);
      const std::array<int, 3> hi = cellOf(g.a.cwiseMax(g.b) + grow);
      for (int x = lo[0]; x <= hi[0]; ++x) {
        for (int y = lo[1]; y <= hi[1]; ++y) {
          for (int z = lo[2]; z <= hi[2]; ++z) cells_[index(x, y, z)].push_back(i);
        }
      }
    }
  }
  const std::vector<std::size_t>& at(const Vec3& p) const {
    const std::array<int, 3> c = cellOf(p);
    return cells_[index(c[0], c[1], c[2])];
  }

 private:
  std::array<int, 3> cellOf(const Vec3& p) const {
    std::array<int, 3> c{};
    for (int k = 0; k < 3; ++k) {
      const double f = std::floor((p[k] - origin_[k]) / cell_);
      c[k] = static_cast<int>(std::clamp(f, 0.0, static_cast<double>(dims_[k] - 1)));
    }
    return c;
  }
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0] + x;
  }
  Vec3 origin_;
  double cell_;
  std::array<int, 3> dims_{};
  std::vector<std::vector<std::size_t>> cells_;
};

/// The mesh clipped to c > 0 (file comment, step 2); `field` gets c on the clipped mesh (0 on
/// the cut). Vertices with c ≤ 0 or not finite are outside.
TriMesh clipToUncovered(const TriMesh& mesh, const std::vector<double>& c,
                        std::vector<double>& field) {
  TriMesh out;
  field.clear();
  const auto inside = [&](std::int32_t v) { return std::isfinite(c[v]) && c[v] > 0.0; };
  std::vector<std::int32_t> kept(mesh.vertexCount(), -1);
  std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> cuts;
  const auto vertexOf = [&](std::int32_t v) {
    if (kept[v] < 0) {
      kept[v] = static_cast<std::int32_t>(out.vertices.size());
      out.vertices.push_back(mesh.vertices[v]);
      field.push_back(c[v]);
    }
    return kept[v];
  };
  // The zero of c on edge (in, out): in has c > 0, out has c ≤ 0 (or none: the edge's middle).
  const auto cutOf = [&](std::int32_t in, std::int32_t outside) {
    const auto key = std::make_pair(std::min(in, outside), std::max(in, outside));
    const auto it = cuts.find(key);
    if (it != cuts.end()) return it->second;
    const double t = std::isfinite(c[outside]) ? c[in] / (c[in] - c[outside]) : 0.5;
    const auto index = static_cast<std::int32_t>(out.vertices.size());
    out.vertices.push_back(mesh.vertices[in] + t * (mesh.vertices[outside] - mesh.vertices[in]));
    field.push_back(0.0);
    cuts.emplace(key, index);
    return index;
  };
  for (const Vec3i& tri : mesh.triangles) {
    const int count = inside(tri[0]) + inside(tri[1]) + inside(tri[2]);
    if (count == 0) continue;
    if (count == 3) {
      out.triangles.emplace_back(vertexOf(tri[0]), vertexOf(tri[1]), vertexOf(tri[2]));
      continue;
    }
    // Rotate (keeping the orientation) so that a is the lone inside (count 1) or lone outside
    // vertex's successor (count 2: a, b inside, d outside).
    int r = 0;
    for (; r < 3; ++r) {
      const bool ia = inside(tri[r]), ib = inside(tri[(r + 1) % 3]), id = inside(tri[(r + 2) % 3]);
      if (count == 1 ? ia : (ia && ib && !id)) break;
    }
    const std::int32_t a = tri[r], b = tri[(r + 1) % 3], d = tri[(r + 2) % 3];
    if (count == 1) {
      out.triangles.emplace_back(vertexOf(a), cutOf(a, b), cutOf(a, d));
    } else {
      const std::int32_t va = vertexOf(a), vb = vertexOf(b), bd = cutOf(b, d), da = cutOf(a, d);
      out.triangles.emplace_back(va, vb, bd);
      out.triangles.emplace_back(va, bd, da);
    }
  }
  return out;
}

/// The stretches of an open `line` where the patch is at least `minWidth` wide (`widths` per
/// point; the ends of a stretch interpolated to where the width crosses minWidth) and that are
/// at least `minLength` long.
std::vector<Polyline> keepWideStretches(const Polyline& line, const std::vector<double>& widths,
                                        double minWidth, double minLength) {
  std::vector<Polyline> kept;
  Polyline run;
  const auto crossing = [&](std::size_t i, std::size_t j) {
    const double t = (minWidth - widths[i]) / (widths[j] - widths[i]);
    return Vec3(line.points[i] + std::clamp(t, 0.0, 1.0) * (line.points[j] - line.points[i]));
  };
  const auto close = [&] {
    if (run.points.size() >= 2 && run.length() >= minLength) kept.push_back(run);
    run.points.clear();
  };
  for (std::size_t i = 0; i < line.points.size(); ++i) {
    const bool wide = widths[i] >= minWidth;
    const bool wasWide = i > 0 && widths[i - 1] >= minWidth;
    if (wide && !wasWide && i > 0) run.points.push_back(crossing(i - 1, i));
    if (wide) run.points.push_back(line.points[i]);
    if (!wide && wasWide) {
      run.points.push_back(crossing(i - 1, i));
      close();
    }
  }
  close();
  return kept;
}

void validateGapFillOptions(const GapFillOptions& o) {
  if (!std::isfinite(o.beadSpacing) || o.beadSpacing <= 0.0) {
    throw InvalidInput("bead spacing must be a positive number of mm: " +
                       formatNumber(o.beadSpacing) + "; pass a value such as 3.7");
  }
  if (!std::isfinite(o.minGapWidth) || o.minGapWidth == 0.0) {
    throw InvalidInput(
        "minimum gap width must be a positive number of mm: " + formatNumber(o.minGapWidth) +
        "; pass a value such as 1.85, or a negative one for half the bead spacing");
  }
  if (!std::isfinite(o.minGapArea) || o.minGapArea == 0.0) {
    throw InvalidInput(
        "minimum gap area must be a positive number of mm²: " + formatNumber(o.minGapArea) +
        "; pass a value such as 14, or a negative one for s²");
  }
  if (!std::isfinite(o.minRunLength) || o.minRunLength == 0.0) {
    throw InvalidInput(
        "minimum gap bead length must be a positive number of mm: " + formatNumber(o.minRunLength) +
        "; pass a value such as 1.85, or a negative one for half the bead spacing");
  }
  if (!std::isfinite(o.reach) || o.reach == 0.0) {
    throw InvalidInput(
        "gap clearance reach must be a positive number of mm: " + formatNumber(o.reach) +
        "; pass a value such as 3.7, or a negative one for the bead spacing");
  }
}

}  // namespace

std::vector<double> computeUncoveredClearance(const TriMesh& mesh,
                                              const std::vector<double>& distance,
                                              const std::vector<LayerBead>& beads,
                                              double beadSpacing, double reach) {
  std::vector<double> c(mesh.vertexCount());
  for (std::size_t v = 0; v < c.size(); ++v) c[v] = std::min(distance[v], reach);
  const std::vector<WideSegment> segments = collectWideSegments(beads, beadSpacing);
  if (segments.empty() || mesh.vertices.empty()) return c;
  Aabb box = mesh.bounds();
  const SegmentGrid grid(segments, box, beadSpacing, reach);
  for (std::size_t v = 0; v < c.size(); ++v) {
    const Vec3& p = mesh.vertices[v];
    for (const std::size_t i : grid.at(p))
      c[v] = std::min(c[v], distanceBeyondBead(p, segments[i]));
  }
  return c;
}

GapFillPlanner::GapFillPlanner(const TriMesh& mesh, const std::vector<double>& distance,
                               const std::vector<LayerBead>& beads, const GapFillOptions& options) {
  if (distance.size() != mesh.vertexCount()) {
    throw InvalidInput(
        "gap fill needs one GDTC value per vertex: " + std::to_string(distance.size()) +
        " values for " + std::to_string(mesh.vertexCount()) +
        " vertices; pass the field of the same mesh");
  }
  validateGapFillOptions(options);
  planPatches(mesh, distance, beads, options);
}

void GapFillPlanner::planPatches(const TriMesh& mesh, const std::vector<double>& distance,
                                 const std::vector<LayerBead>& beads,
                                 const GapFillOptions& options) {
  const double s = options.beadSpacing;
  beadSpacing_ = s;
  const double reach = options.reach < 0.0 ? s : options.reach;
  const double minArea = options.minGapArea < 0.0 ? s * s : options.minGapArea;
  const double minWidth = options.minGapWidth < 0.0 ? 0.5 * s : options.minGapWidth;
  const double minLength = options.minRunLength < 0.0 ? 0.5 * s : options.minRunLength;
  result_.clearance = computeUncoveredClearance(mesh, distance, beads, s, reach);
  patches_ = clipToUncovered(mesh, result_.clearance, patchClearance_);
  ThinRegionOptions thin;
  thin.beadSpacing = s;
  thin.minFeatureWidth = options.minGapWidth;
  thin.widthMin = options.widthMin;
  thin.widthMax = options.widthMax;
  if (patches_.empty()) return;
  planner_ = std::make_unique<ThinRegionPlanner>(patches_, patchClearance_, thin);
  ThinRegionResult planned = planner_->plan({}, {});
  // Every region that is not left out got one bead, in region order.
  std::size_t next = 0;
  for (const ThinRegion& gap : planned.regions) {
    result_.uncoveredArea += gap.area;
    result_.gaps.push_back(gap);
    if (gap.leftOut) continue;
    ThinBead& bead = planned.beads[next++];
    if (gap.area < minArea || (bead.kind == ThinBeadKind::Spot && !options.allowSpots)) {
      result_.gaps.back().leftOut = true;
      continue;
    }
    if (bead.kind == ThinBeadKind::Spot) {
      addFill(gap, {std::move(bead)});
      continue;
    }
    std::vector<ThinBead> stretches;
    for (Polyline& line : keepWideStretches(bead.line, planner_->localWidthsAt(bead.line.points),
                                            minWidth, minLength)) {
      stretches.push_back({ThinBeadKind::CentreLine, std::move(line), bead.width});
    }
    if (stretches.empty()) result_.gaps.back().leftOut = true;
    addFill(gap, std::move(stretches));
  }
}

void GapFillPlanner::addFill(const ThinRegion& gap, std::vector<ThinBead> beads) {
  if (beads.empty()) return;
  ++result_.filled;
  result_.filledArea += gap.area;
  for (ThinBead& b : beads) result_.beads.push_back(std::move(b));
}

GapFillPlanner::~GapFillPlanner() = default;

std::vector<double> GapFillPlanner::widthsAt(const std::vector<Vec3>& points) const {
  if (!planner_) return std::vector<double>(points.size(), beadSpacing_);
  return planner_->widthsAt(points);
}

}  // namespace curvedslicer
