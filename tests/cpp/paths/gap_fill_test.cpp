// Gap fill (paths/gap_fill.hpp) on a flat rectangle with its exact distance to the
// boundary as GDTC and one closed ring at s/2 inward as the layer's bead: the uncovered strip in
// the middle, 2.6 mm = 0.70·s wide, gets one bead on its centre line whose round ends reach the
// strip's ends; a strip narrower than the minimum gap width stays; adaptive width gives the bead
// the strip's width; the uncovered clearance is the distance to the covered area; bad options are
// named.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/shapes.hpp"
#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/gap_fill.hpp"

namespace curvedslicer {
namespace {

using testing::kS;

/// Flat rectangle [0, a] × [0, b] at z = 0, cells of `h` mm, and its distance to the boundary.
TriMesh makeRectangle(double a, double b, double h, std::vector<double>& distance) {
  const int n = static_cast<int>(std::lround(a / h)), m = static_cast<int>(std::lround(b / h));
  TriMesh mesh = testing::makeFlatGrid(0.0, a, 0.0, b, 0.0, n, m);
  for (const Vec3& v : mesh.vertices)
    distance.push_back(std::min({v.x(), a - v.x(), v.y(), b - v.y()}));
  return mesh;
}

/// The closed ring `inset` mm inside the rectangle's edge.
Polyline makeRing(double a, double b, double inset) {
  Polyline ring;
  ring.closed = true;
  ring.points = {Vec3(inset, inset, 0), Vec3(a - inset, inset, 0), Vec3(a - inset, b - inset, 0),
                 Vec3(inset, b - inset, 0)};
  return ring;
}

/// The largest patch of a result.
const ThinRegion& largestGap(const GapFillResult& r) {
  return *std::max_element(
      r.gaps.begin(), r.gaps.end(),
      [](const ThinRegion& a, const ThinRegion& b) { return a.area < b.area; });
}

// A 40 × 10 rectangle with its ring at s/2: covered to s from the edge, so the strip
// [s, 40 − s] × [s, 10 − s] (32.6 × 2.6 mm) is uncovered, and so are the rectangle's four corners
// outside the ring's round outer corners ((s/2)²·(1 − π/4) = 0.73 mm² each, too narrow to fill).
TEST(GapFill, StripBetweenRingsGetsOneCentreBead) {
  std::vector<double> distance;
  const TriMesh mesh = makeRectangle(40, 10, 0.5, distance);
  const Polyline ring = makeRing(40, 10, 0.5 * kS);
  GapFillOptions options;
  options.beadSpacing = kS;
  const GapFillPlanner planner(mesh, distance, {{&ring, {}}}, options);
  const GapFillResult& r = planner.result();
  ASSERT_EQ(r.gaps.size(), 5u);
  const double corner = 0.25 * kS * kS * (1.0 - 0.25 * 3.14159265358979323846);
  EXPECT_NEAR(largestGap(r).area, 32.6 * 2.6, 0.3);
  EXPECT_NEAR(largestGap(r).width, 2.6, 0.05);
  for (const ThinRegion& g : r.gaps) {
    if (&g == &largestGap(r)) continue;
    // c is interpolated linearly on 0.5 mm cells: the curved corner patch comes out smaller.
    EXPECT_TRUE(g.leftOut);
    EXPECT_GT(g.area, 0.0);
    EXPECT_LT(g.area, corner);
  }
  ASSERT_EQ(r.beads.size(), 1u);
  EXPECT_EQ(r.filled, 1u);
  const ThinBead& bead = r.beads[0];
  EXPECT_EQ(bead.kind, ThinBeadKind::CentreLine);
  EXPECT_DOUBLE_EQ(bead.width, kS);
  double lo = kInf, hi = -kInf;
  for (const Vec3& p : bead.line.points) {
    EXPECT_NEAR(p.y(), 5.0, 0.1);
    lo = std::min(lo, p.x());
    hi = std::max(hi, p.x());
  }
  // The round ends (s/2) reach the strip's ends at x = s and 40 − s.
  EXPECT_NEAR(lo, 1.5 * kS, 0.3);
  EXPECT_NEAR(hi, 40 - 1.5 * kS, 0.3);
  const std::vector<double> widths = planner.widthsAt(bead.line.points);
  for (const double w : widths) EXPECT_DOUBLE_EQ(w, kS);
}

TEST(GapFill, AdaptiveWidthGivesTheStripItsWidth) {
  std::vector<double> distance;
  const TriMesh mesh = makeRectangle(40, 10, 0.5, distance);
  const Polyline ring = makeRing(40, 10, 0.5 * kS);
  GapFillOptions options;
  options.beadSpacing = kS;
  options.widthMin = 0.6;
  options.widthMax = 1.3;
  const GapFillPlanner planner(mesh, distance, {{&ring, {}}}, options);
  ASSERT_EQ(planner.result().beads.size(), 1u);
  const ThinBead& bead = planner.result().beads[0];
  EXPECT_NEAR(bead.width, 2.6, 0.05);
  // Along the middle of the strip (away from its ends) the local width is the strip's.
  std::vector<Vec3> middle;
  for (const Vec3& p : bead.line.points) {
    if (std::abs(p.x() - 20.0) < 10.0) middle.push_back(p);
  }
  ASSERT_FALSE(middle.empty());
  for (const double w : planner.widthsAt(middle)) EXPECT_NEAR(w, 2.6, 0.1);
}

// Ring at 0.65·s: covered to 1.15·s = 4.255 mm from the edge; the strip is 10 − 8.51 = 1.49 mm
// wide, under the default minimum s/2 = 1.85 mm: it stays uncovered; a minimum of 1.2 mm fills
// it. The band between the ring and the edge (0.555 mm wide, 1.25 mm at the corners) stays: its
// stretches wider than 1.2 mm are shorter than s/2.
TEST(GapFill, StripNarrowerThanTheMinimumStays) {
  std::vector<double> distance;
  const TriMesh mesh = makeRectangle(40, 10, 0.5, distance);
  const Polyline ring = makeRing(40, 10, 0.65 * kS);
  GapFillOptions options;
  options.beadSpacing = kS;
  {
    const GapFillPlanner planner(mesh, distance, {{&ring, {}}}, options);
    const std::vector<ThinRegion>& gaps = planner.result().gaps;
    EXPECT_TRUE(
        std::all_of(gaps.begin(), gaps.end(), [](const ThinRegion& g) { return g.leftOut; }));
    EXPECT_TRUE(std::any_of(gaps.begin(), gaps.end(), [](const ThinRegion& g) {
      return std::abs(g.width - 1.49) < 0.05 && std::abs(g.extent - 31.49) < 0.05;
    }));
    EXPECT_TRUE(planner.result().beads.empty());
    EXPECT_EQ(planner.result().filled, 0u);
  }
  options.minGapWidth = 1.2;
  const GapFillPlanner planner(mesh, distance, {{&ring, {}}}, options);
  EXPECT_EQ(planner.result().beads.size(), 1u);
}

// A patch below the minimum area (default s²) stays even when wide enough.
TEST(GapFill, PatchSmallerThanTheMinimumAreaStays) {
  std::vector<double> distance;
  const TriMesh mesh = makeRectangle(40, 10, 0.5, distance);
  const Polyline ring = makeRing(40, 10, 0.5 * kS);
  GapFillOptions options;
  options.beadSpacing = kS;
  options.minGapArea = 100.0;  // the strip has 84.8 mm²
  const GapFillPlanner planner(mesh, distance, {{&ring, {}}}, options);
  EXPECT_TRUE(planner.result().beads.empty());
  EXPECT_TRUE(largestGap(planner.result()).leftOut);
}

TEST(GapFill, ClearanceIsTheDistanceToTheCoveredArea) {
  std::vector<double> distance;
  const TriMesh mesh = makeRectangle(40, 10, 0.5, distance);
  const Polyline ring = makeRing(40, 10, 0.5 * kS);
  const std::vector<double> c = computeUncoveredClearance(mesh, distance, {{&ring, {}}}, kS, kS);
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const Vec3& p = mesh.vertices[v];
    // Exact: inside the strip, the distance to its edge; elsewhere −(depth inside the bead), or
    // the distance to the boundary where that is smaller.
    const double inStrip = std::min({p.x() - kS, 40 - kS - p.x(), p.y() - kS, 10 - kS - p.y()});
    const double toRing = std::min({std::abs(p.x() - 0.5 * kS), std::abs(p.x() - 40 + 0.5 * kS),
                                    std::abs(p.y() - 0.5 * kS), std::abs(p.y() - 10 + 0.5 * kS)});
    if (inStrip > 0.0) {
      EXPECT_NEAR(c[v], inStrip, 1e-9) << p.transpose();
    } else if (toRing <= 0.5 * kS && p.x() >= kS && p.x() <= 40 - kS) {  // away from corners
      EXPECT_LE(c[v], 1e-9) << p.transpose();
    }
  }
}

TEST(GapFill, RejectsBadOptionsNamingThem) {
  std::vector<double> distance;
  const TriMesh mesh = makeRectangle(10, 10, 1.0, distance);
  const auto message = [&](GapFillOptions o, const std::vector<double>& d) {
    try {
      const GapFillPlanner planner(mesh, d, {}, o);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  GapFillOptions o;
  o.minGapWidth = 0.0;
  EXPECT_NE(message(o, distance).find("minimum gap width"), std::string::npos);
  o = {};
  o.minGapArea = std::nan("");
  EXPECT_NE(message(o, distance).find("minimum gap area"), std::string::npos);
  o = {};
  o.beadSpacing = -1.0;
  EXPECT_NE(message(o, distance).find("bead spacing"), std::string::npos);
  o = {};
  o.reach = 0.0;
  EXPECT_NE(message(o, distance).find("reach"), std::string::npos);
  EXPECT_NE(message({}, {1.0, 2.0}).find("one GDTC value per vertex"), std::string::npos);
}

TEST(GapFill, IsDeterministic) {
  std::vector<double> distance;
  const TriMesh mesh = makeRectangle(40, 10, 0.5, distance);
  const Polyline ring = makeRing(40, 10, 0.5 * kS);
  const GapFillPlanner a(mesh, distance, {{&ring, {}}});
  const GapFillPlanner b(mesh, distance, {{&ring, {}}});
  ASSERT_EQ(a.result().beads.size(), b.result().beads.size());
  for (std::size_t i = 0; i < a.result().beads.size(); ++i) {
    EXPECT_EQ(a.result().beads[i].line.points, b.result().beads[i].line.points);
  }
}

}  // namespace
}  // namespace curvedslicer
