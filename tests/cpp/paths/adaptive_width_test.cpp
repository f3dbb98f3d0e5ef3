// Adaptive bead width: ring widths per region against closed form, and a
// rectangle 23 mm wide (not a whole number of 3.7 mm beads) filled without void or overlap.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/adaptive_width.hpp"
#include "curvedslicer/paths/planner.hpp"

namespace curvedslicer {
namespace {

/// A flat rectangle [x0, x1] × [y0, y1] at height z, n × m cells, normals +z.
TriMesh makeFlatPatch(double x0, double x1, double y0, double y1, double z, int n, int m) {
  TriMesh mesh;
  const auto first = static_cast<int>(mesh.vertexCount());
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= n; ++i) {
      mesh.vertices.emplace_back(x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / m, z);
    }
  }
  const auto id = [n, first](int i, int j) { return first + j * (n + 1) + i; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      mesh.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return mesh;
}

/// Shares of a flat rectangle's area (sampled on a 0.05 mm grid) that no bead covers (void) and
/// that two or more paths cover (overlap); a path covers a point within half its width
/// (PathPoint::width, or s where 0) of its centre line. Independent of the planner's own
/// coverage measurement.
struct Coverage {
  double voidShare = 0.0;
  double overlapShare = 0.0;
};

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

Coverage measureRectangleCoverage(const PlanLayer& layer, double x1, double y1, double z,
                                  double s) {
  const double step = 0.05;
  std::size_t samples = 0, voids = 0, overlaps = 0;
  for (double y = 0.5 * step; y < y1; y += step) {
    for (double x = 0.5 * step; x < x1; x += step) {
      const Vec3 p(x, y, z);
      int covering = 0;
      for (const PlanPath& path : layer.paths) {
        const std::size_t n = path.points.size();
        const std::size_t segments = path.closed ? n : n - 1;
        for (std::size_t i = 0; i < segments; ++i) {
          const PathPoint& a = path.points[i];
          const PathPoint& b = path.points[(i + 1) % n];
          const double w = 0.5 * ((a.width > 0 ? a.width : s) + (b.width > 0 ? b.width : s));
          if (distanceToSegment(p, a.position, b.position) <= 0.5 * w) {
            ++covering;
            break;
          }
        }
      }
      ++samples;
      if (covering == 0) ++voids;
      if (covering >= 2) ++overlaps;
    }
  }
  return {static_cast<double>(voids) / samples, static_cast<double>(overlaps) / samples};
}

PlanResult planRectangle(double widthMin, double widthMax) {
  // One layer of a 23 × 60 × 6 mm box on a plate (flat layers from a plane start), h = 1.5, on
  // 0.25 mm cells: the triangles' diagonals run one way, so iso-line corners where the medial
  // axis crosses them the other way are cut by about a cell (0.5 mm cells: 1.03 % void instead
  // of the 0.69 % that round beads leave in the rings' square corners).
  LayerSurface layer;
  layer.index = 0;
  layer.level = 1.5;
  layer.mesh = makeFlatPatch(0, 23, 0, 60, 1.5, 92, 240);
  const TriMesh plate = makeFlatPatch(-10, 33, -10, 70, 0.0, 2, 2);
  PlannerOptions options;
  options.beadSpacing = 3.7;
  options.widthMin = widthMin;
  options.widthMax = widthMax;
  return planLayers({layer}, plate, options);
}

TEST(AdaptiveWidth, BoundaryRingsFillTheHalfWidth) {
  // m = 11.5, s = 3.7: K = round(3.11) = 3 rings of 11.5/3 mm at (k + ½)·w'.
  const RegionRings rings = computeRegionRings(11.5, 3.7, 0.7, 1.3, IsoValueStart::Boundary);
  EXPECT_FALSE(rings.widthClamped);
  EXPECT_DOUBLE_EQ(rings.width, 11.5 / 3);
  ASSERT_EQ(rings.values.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(rings.values[k], (k + 0.5) * 11.5 / 3);
  // m = 13.6: m/s = 3.68 → K = 4, w' = 3.4.
  const RegionRings four = computeRegionRings(13.6, 3.7, 0.7, 1.3, IsoValueStart::Boundary);
  EXPECT_DOUBLE_EQ(four.width, 3.4);
  EXPECT_EQ(four.values.size(), 4u);
}

TEST(AdaptiveWidth, InteriorCurveRingsFillTheHalfWidth) {
  // m = 10, s = 3.7: K = round(10/3.7 − ½) = 2, w' = 10/2.5 = 4, beads at 0, 4, 8.
  const RegionRings rings = computeRegionRings(10.0, 3.7, 0.7, 1.3, IsoValueStart::InteriorCurve);
  EXPECT_DOUBLE_EQ(rings.width, 4.0);
  ASSERT_EQ(rings.values.size(), 3u);
  EXPECT_DOUBLE_EQ(rings.values[0], 0.0);
  EXPECT_DOUBLE_EQ(rings.values[2], 8.0);
}

TEST(AdaptiveWidth, WidthOutsideTheRangeIsClamped) {
  // m = 5: K = 1 would need 5 mm beads, above 1.3·3.7 = 4.81: 4.81 mm rings as usual.
  const RegionRings wide = computeRegionRings(5.0, 3.7, 0.7, 1.3, IsoValueStart::Boundary);
  EXPECT_TRUE(wide.widthClamped);
  EXPECT_DOUBLE_EQ(wide.wholeWidth, 5.0);
  EXPECT_DOUBLE_EQ(wide.width, 1.3 * 3.7);
  ASSERT_EQ(wide.values.size(), 1u);
  EXPECT_DOUBLE_EQ(wide.values[0], 0.5 * 1.3 * 3.7);
  // Fixed range: always s, the usual values.
  const RegionRings fixed = computeRegionRings(11.5, 3.7, 1.0, 1.0, IsoValueStart::Boundary);
  EXPECT_DOUBLE_EQ(fixed.width, 3.7);
  EXPECT_EQ(fixed.values, computeIsoValues(3.7, 11.5, IsoValueStart::Boundary));
  // Nothing to fill.
  EXPECT_TRUE(computeRegionRings(0.0, 3.7, 0.7, 1.3, IsoValueStart::Boundary).values.empty());
  EXPECT_TRUE(computeRegionRings(kInf, 3.7, 0.7, 1.3, IsoValueStart::Boundary).values.empty());
  // Narrower than two beads of the narrowest width: no ring (a centre bead from the thin-region
  // rule covers it at its own width).
  EXPECT_TRUE(computeRegionRings(1.4, 3.7, 0.7, 1.3, IsoValueStart::Boundary).values.empty());
  EXPECT_EQ(computeRegionRings(1.4, 3.7, 1.0, 1.0, IsoValueStart::Boundary).values.size(), 0u);
}

TEST(AdaptiveWidth, LabelsConnectedRegions) {
  TriMesh mesh = makeFlatPatch(0, 1, 0, 1, 0, 2, 2);
  const TriMesh other = makeFlatPatch(5, 6, 0, 1, 0, 1, 1);
  const auto offset = static_cast<int>(mesh.vertexCount());
  for (const Vec3& v : other.vertices) mesh.vertices.push_back(v);
  for (const Vec3i& t : other.triangles) mesh.triangles.push_back(t + Vec3i::Constant(offset));
  std::int32_t count = 0;
  const std::vector<std::int32_t> label = labelMeshRegions(mesh, count);
  EXPECT_EQ(count, 2);
  EXPECT_EQ(std::count(label.begin(), label.end(), 0), 9);
  EXPECT_EQ(std::count(label.begin(), label.end(), 1), 4);
}

TEST(AdaptiveWidth, RectangleNotAWholeNumberOfBeadsIsFilled) {
  const PlanResult adaptive = planRectangle(0.7, 1.3);
  const PlanLayer& layer = adaptive.plan.layers.at(0);
  // The 3 rings, joined by connected insets (on by default) into one path with 2 step-overs.
  ASSERT_EQ(layer.paths.size(), 1u);
  EXPECT_EQ(adaptive.stats.insetLinks, 2u);
  for (const PlanPath& path : layer.paths) {
    for (const PathPoint& q : path.points) EXPECT_NEAR(q.width, 23.0 / 6.0, 0.02);
  }
  // The plan's own coverage numbers (paths/coverage.hpp; measured void 0.89 %, overlap 4.6 %,
  // of which 1.0 % without connected insets) and the independent sampling here (different paths
  // only, so it sees no overlap within the joined path).
  ASSERT_TRUE(layer.coverage.measured);
  EXPECT_LE(layer.coverage.voidShare, 0.01);
  EXPECT_LE(layer.coverage.overlapShare, 0.05);
  const Coverage on = measureRectangleCoverage(layer, 23, 60, 1.5, 3.7);
  EXPECT_LE(on.voidShare, 0.01);
  EXPECT_LE(on.overlapShare, 0.05);
  // Range off: the 3 fixed rings leave a strip 23 − 6·3.7 = 0.8 mm wide along the middle, too
  // narrow for a fill bead; gap fill widens the innermost ring into it (paths/bead_widening.hpp):
  // widths from s to 1.25·s, none narrower, and the strip is no longer void.
  const PlanResult fixed = planRectangle(1.0, 1.0);
  double widest = 0.0;
  for (const PlanPath& path : fixed.plan.layers.at(0).paths) {
    for (const PathPoint& q : path.points) {
      EXPECT_TRUE(q.width == 0.0 || (q.width >= 3.7 - 1e-9 && q.width <= 1.25 * 3.7 + 1e-9))
          << q.width;
      widest = std::max(widest, q.width);
    }
  }
  EXPECT_GT(widest, 3.7 + 0.3);
  EXPECT_LE(fixed.plan.layers[0].coverage.voidShare, 0.01);
  const Coverage off = measureRectangleCoverage(fixed.plan.layers.at(0), 23, 60, 1.5, 3.7);
  std::printf(
      "rectangle 23 x 60, s 3.7: adaptive void %.4f overlap %.4f (plan: %.4f, %.4f); "
      "fixed void %.4f overlap %.4f (plan: %.4f, %.4f)\n",
      on.voidShare, on.overlapShare, layer.coverage.voidShare, layer.coverage.overlapShare,
      off.voidShare, off.overlapShare, fixed.plan.layers[0].coverage.voidShare,
      fixed.plan.layers[0].coverage.overlapShare);
}

TEST(AdaptiveWidth, RejectsRangeWithoutTheBeadSpacing) {
  PlannerOptions options;
  for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{
           {0.0, 1.3}, {1.1, 1.3}, {0.7, 0.9}, {-0.5, 1.0}, {0.7, std::nan("")}}) {
    options.widthMin = lo;
    options.widthMax = hi;
    try {
      validatePlannerOptions(options);
      ADD_FAILURE() << "no error for " << lo << "," << hi;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("bead width range"), std::string::npos) << e.what();
    }
  }
  options.widthMin = 0.7;
  options.widthMax = 1.3;
  EXPECT_NO_THROW(validatePlannerOptions(options));
}

}  // namespace
}  // namespace curvedslicer
