// Thin features and small islands (paths/thin_regions.hpp) through the planner on
// flat layers with known answers: a strip narrower than one bead gets one bead on its centre line
// (y = half its width) and a shortfall note; a tiny disc gets a spot with the dwell rule; a disc
// whose ring at s/2 is shorter than the fragment length keeps that ring; a strip narrower than
// the minimum feature width is left out; a wide region's rings do not change beside an island;
// adaptive width follows the strip; bad options name themselves.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/shapes.hpp"
#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/paths/thin_regions.hpp"
#include "curvedslicer/plan/plan_io.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;
using testing::kS;

/// Flat rectangle [x0, x1] × [y0, y1] at height z, n × m cells.
TriMesh makeRectangle(double x0, double x1, double y0, double y1, double z, int n, int m) {
  return testing::makeFlatGrid(x0, x1, y0, y1, z, n, m);
}

/// Flat disc of radius r around `centre` (normal +z): a centre vertex and `rings` rings of
/// `segments` vertices.
TriMesh makeDisc(const Vec3& centre, double r, int rings, int segments) {
  TriMesh mesh;
  mesh.vertices.push_back(centre);
  for (int k = 1; k <= rings; ++k) {
    for (int i = 0; i < segments; ++i) {
      const double a = 2.0 * kPi * i / segments;
      mesh.vertices.push_back(centre + Vec3(std::cos(a), std::sin(a), 0.0) * (r * k / rings));
    }
  }
  const auto id = [segments](int k, int i) { return 1 + (k - 1) * segments + (i % segments); };
  for (int i = 0; i < segments; ++i) mesh.triangles.emplace_back(0, id(1, i), id(1, i + 1));
  for (int k = 1; k < rings; ++k) {
    for (int i = 0; i < segments; ++i) {
      mesh.triangles.emplace_back(id(k, i), id(k + 1, i), id(k + 1, i + 1));
      mesh.triangles.emplace_back(id(k, i), id(k + 1, i + 1), id(k, i + 1));
    }
  }
  return mesh;
}

/// Both meshes as one (two separate regions).
TriMesh joined(const TriMesh& a, const TriMesh& b) {
  TriMesh out = a;
  const int offset = static_cast<int>(a.vertexCount());
  out.vertices.insert(out.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const Vec3i& t : b.triangles)
    out.triangles.emplace_back(t[0] + offset, t[1] + offset, t[2] + offset);
  return out;
}

std::vector<LayerSurface> oneLayer(TriMesh mesh) {
  LayerSurface s;
  s.index = 1;
  s.level = mesh.vertices.empty() ? 0.0 : mesh.vertices.front().z();
  s.mesh = std::move(mesh);
  return {s};
}

bool hasWarning(const PlanLayer& layer, const std::string& needle) {
  return std::any_of(layer.warnings.begin(), layer.warnings.end(),
                     [&](const std::string& w) { return w.find(needle) != std::string::npos; });
}

TEST(ThinRegions, StripNarrowerThanOneBeadGetsOneCentreBeadAndAShortfallNote) {
  // 30 × 2 mm: GDTC reaches 1 mm < s/2, so no ring; W = 2 ≥ 0.5·s. The bead lies on y = 1 and
  // ends s/2 before each tip, so its round ends reach the tips.
  const auto layers = oneLayer(makeRectangle(0, 30, 0, 2, 1.5, 120, 8));
  const PlanResult result = planLayers(layers, TriMesh{}, PlannerOptions{});
  const PlanLayer& layer = result.plan.layers[0];
  ASSERT_EQ(layer.paths.size(), 1u) << ::testing::PrintToString(layer.warnings);
  const PlanPath& path = layer.paths[0];
  EXPECT_FALSE(path.closed);
  EXPECT_EQ(path.dwell, 0.0);
  EXPECT_NEAR(path.length, 30.0 - kS, 0.1);
  for (const PathPoint& p : path.points) {
    EXPECT_NEAR(p.position.y(), 1.0, 0.05);
    EXPECT_EQ(p.width, kS);  // fixed width: s on every point
  }
  EXPECT_TRUE(hasWarning(layer, "1 bead(s) on their centre line"));
  EXPECT_TRUE(
      hasWarning(layer, "narrower than one bead (s = 3.7 mm), width shortfall up to 1.7 mm"))
      << ::testing::PrintToString(layer.warnings);
  EXPECT_FALSE(hasWarning(layer, "no room for a bead"));
  // Voids only at the four corners beyond the round bead ends: 4 · (1 − π/4)-ish of 1 mm² at most.
  EXPECT_LT(layer.coverage.voidShare * layer.coverage.area, 4.0 * 1.0 * 1.0 * (1.0 - kPi / 4.0));
  EXPECT_EQ(result.stats.layersWithoutPaths, 0u);
}

TEST(ThinRegions, TinyIslandGetsASpotWithTheDwellRule) {
  // A disc 2.4 mm across: its centre line is shorter than one bead, so it gets a spot at its
  // centre: two points 0.1 mm apart, width s, dwell w / spotWeldSpeed = 3.7 / 8 s; the spot's
  // disc of diameter s covers it all.
  const auto layers = oneLayer(makeDisc(Vec3(5, 5, 2), 1.2, 12, 48));
  const PlanResult result = planLayers(layers, TriMesh{}, PlannerOptions{});
  const PlanLayer& layer = result.plan.layers[0];
  ASSERT_EQ(layer.paths.size(), 1u) << ::testing::PrintToString(layer.warnings);
  const PlanPath& spot = layer.paths[0];
  ASSERT_EQ(spot.points.size(), 2u);
  const double gap = (spot.points[1].position - spot.points[0].position).norm();
  EXPECT_GE(gap, 0.05);
  EXPECT_NEAR(gap, 0.1, 1e-6);
  EXPECT_NEAR(spot.dwell, kS / 8.0, 1e-12);
  EXPECT_NEAR((0.5 * (spot.points[0].position + spot.points[1].position) - Vec3(5, 5, 2)).norm(),
              0.0, 0.1);
  for (const PathPoint& p : spot.points) EXPECT_EQ(p.width, kS);
  EXPECT_TRUE(hasWarning(layer, "1 spot(s) on tiny islands (dwell up to 0.4625 s)"));
  EXPECT_EQ(layer.coverage.voidShare, 0.0);

  PlannerOptions slower;
  slower.spotWeldSpeed = 4.0;
  EXPECT_NEAR(planLayers(layers, TriMesh{}, slower).plan.layers[0].paths[0].dwell, kS / 4.0, 1e-12);
}

TEST(ThinRegions, SmallDiscKeepsItsShortRingAsItsOnlyCover) {
  // Radius 2.3: the ring at s/2 from the rim has radius 0.45, length 2.8 mm < the fragment length
  // s; it is the disc's only cover, and its bead (out to 0.45 + 1.85 = 2.3) covers it all.
  const auto layers = oneLayer(makeDisc(Vec3(0, 0, 1), 2.3, 23, 96));
  const PlanResult result = planLayers(layers, TriMesh{}, PlannerOptions{});
  const PlanLayer& layer = result.plan.layers[0];
  ASSERT_EQ(layer.paths.size(), 1u) << ::testing::PrintToString(layer.warnings);
  EXPECT_TRUE(layer.paths[0].closed);
  EXPECT_NEAR(layer.paths[0].length, 2.0 * kPi * 0.45, 0.1);
  for (const PathPoint& p : layer.paths[0].points) EXPECT_EQ(p.width, kS);
  EXPECT_TRUE(hasWarning(layer, "1 short ring(s) kept as their only cover"));
  EXPECT_LT(layer.coverage.voidShare, 0.01);
  EXPECT_EQ(result.stats.droppedFragments, 0u);
}

TEST(ThinRegions, WideRegionsRingsStayAsTheyWereBesideAnIsland) {
  // A 40 × 30 rectangle alone and with a tiny disc beside it: every ring of the rectangle is the
  // same path (same points) in both plans; the disc adds one spot.
  const TriMesh rectangle = makeRectangle(0, 40, 0, 30, 1.5, 40, 30);
  const PlanResult alone = planLayers(oneLayer(rectangle), TriMesh{}, PlannerOptions{});
  const PlanResult both =
      planLayers(oneLayer(joined(rectangle, makeDisc(Vec3(60, 15, 1.5), 1.0, 10, 40))), TriMesh{},
                 PlannerOptions{});
  const std::vector<PlanPath>& a = alone.plan.layers[0].paths;
  const std::vector<PlanPath>& b = both.plan.layers[0].paths;
  ASSERT_EQ(b.size(), a.size() + 1);
  std::size_t spots = 0;
  for (const PlanPath& p : b) spots += p.dwell > 0.0;
  EXPECT_EQ(spots, 1u);
  for (const PlanPath& ring : a) {
    EXPECT_EQ(ring.dwell, 0.0);
    const bool found = std::any_of(b.begin(), b.end(), [&](const PlanPath& q) {
      if (q.points.size() != ring.points.size()) return false;
      for (std::size_t i = 0; i < q.points.size(); ++i) {
        if (q.points[i].position != ring.points[i].position) return false;
      }
      return true;
    });
    EXPECT_TRUE(found) << "ring of length " << ring.length << " changed";
  }
}

TEST(ThinRegions, AdaptiveWidthFollowsTheStripWithinTheRange) {
  // A 2.8 mm strip, widths allowed in [0.7·s, 1.3·s] = [2.59, 4.81]: the centre bead is 2.8 wide;
  // a 2 mm strip asks for less than 2.59 and gets the range's lower end.
  PlannerOptions options;
  options.widthMin = 0.7;
  options.widthMax = 1.3;
  const PlanResult wide =
      planLayers(oneLayer(makeRectangle(0, 30, 0, 2.8, 1.5, 120, 14)), TriMesh{}, options);
  ASSERT_EQ(wide.plan.layers[0].paths.size(), 1u);
  const PlanPath& path = wide.plan.layers[0].paths[0];
  EXPECT_NEAR(path.length, 30.0 - 2.8, 0.1);
  // Interior points: the strip's width; the end points lie about w/2 from the end edges, which
  // bound their local width from above.
  for (std::size_t i = 1; i + 1 < path.points.size(); ++i) {
    EXPECT_NEAR(path.points[i].width, 2.8, 0.02);
  }
  for (const PathPoint* p : {&path.points.front(), &path.points.back()}) {
    EXPECT_GE(p->width, 0.7 * kS);
    EXPECT_LE(p->width, 2.8 + 0.02);
  }
  const PlanResult narrow =
      planLayers(oneLayer(makeRectangle(0, 30, 0, 2, 1.5, 120, 8)), TriMesh{}, options);
  for (const PathPoint& p : narrow.plan.layers[0].paths.at(0).points) {
    EXPECT_NEAR(p.width, 0.7 * kS, 1e-12);
  }
}

TEST(ThinRegions, AdaptiveCentreBeadIsCentredOnACoarseMesh) {
  // A 3.2 mm strip meshed 4 cells across (0.8 mm): the GDTC ridge path runs on a mesh line, at
  // y = 1.6 only by luck of the vertex rows; with 3 cells (rows at 1.067 and 2.133) it runs
  // 0.53 mm off the middle. With adaptive width the bead is moved to the middle of the strip's
  // span: every interior point within 0.05 mm of y = 1.6, width 3.2, and (almost) no void.
  PlannerOptions options;
  options.widthMin = 0.7;
  options.widthMax = 1.3;
  const PlanResult result =
      planLayers(oneLayer(makeRectangle(0, 30, 0, 3.2, 1.5, 40, 3)), TriMesh{}, options);
  ASSERT_EQ(result.plan.layers[0].paths.size(), 1u);
  const PlanPath& path = result.plan.layers[0].paths[0];
  for (std::size_t i = 1; i + 1 < path.points.size(); ++i) {
    const PathPoint& p = path.points[i];
    if (p.position.x() < 3.0 || p.position.x() > 27.0) continue;  // away from the round ends
    EXPECT_NEAR(p.position.y(), 1.6, 0.05) << "x " << p.position.x();
    EXPECT_NEAR(p.width, 3.2, 0.1) << "x " << p.position.x();
  }
  // What stays uncovered: the strip's four corners outside the round ends, 4·(w/2)²·(1 − π/4).
  const LayerCoverage& c = result.plan.layers[0].coverage;
  EXPECT_LT(c.voidShare * c.area, 4.0 * 1.6 * 1.6 * (1.0 - kPi / 4.0) + 0.5);
}

TEST(ThinRegions, MinimumFeatureWidthDecidesWhatIsLeftOut) {
  // The 2 mm strip is left out when the minimum is 2.5 mm, and reported with its size and place.
  PlannerOptions options;
  options.minFeatureWidth = 2.5;
  const auto layers = oneLayer(makeRectangle(0, 30, 0, 2, 1.5, 120, 8));
  const auto plan = [&] { planLayers(layers, TriMesh{}, options); };
  try {
    plan();
    FAIL() << "no InvalidInput for a layer with no path at all";
  } catch (const InvalidInput& e) {
    // The layers' GDTC reaches 0.9992 mm on this mesh (the exact half-width is 1 mm).
    EXPECT_NE(std::string(e.what()).find("or a minimum feature width below 1.998 mm"),
              std::string::npos)
        << e.what();
  }
  std::vector<LayerSurface> two = oneLayer(makeRectangle(0, 30, 0, 20, 0.0, 30, 20));
  two.push_back(layers[0]);
  const PlanResult result = planLayers(two, TriMesh{}, options);
  EXPECT_TRUE(result.plan.layers[1].paths.empty());
  EXPECT_TRUE(hasWarning(result.plan.layers[1],
                         "region at 15,1,1.5 mm, 2 mm wide, 30 mm long, 60 mm² left out: "
                         "narrower than the minimum feature width 2.5 mm"))
      << ::testing::PrintToString(result.plan.layers[1].warnings);
}

TEST(ThinRegions, RejectsBadOptionsNamingThem) {
  const auto layers = oneLayer(makeRectangle(0, 30, 0, 2, 1.5, 60, 4));
  PlannerOptions options;
  options.minFeatureWidth = 0.0;
  try {
    planLayers(layers, TriMesh{}, options);
    FAIL() << "no InvalidInput for a zero minimum feature width";
  } catch (const InvalidInput& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("minimum feature width"), std::string::npos) << message;
    EXPECT_NE(message.find("must be a positive number of mm: 0"), std::string::npos) << message;
  }
  options.minFeatureWidth = -1.0;
  options.spotWeldSpeed = 0.0;
  EXPECT_THROW(planLayers(layers, TriMesh{}, options), InvalidInput);
  ThinRegionOptions thin;
  thin.widthMin = 1.2;
  EXPECT_THROW(ThinRegionPlanner(layers[0].mesh,
                                 std::vector<double>(layers[0].mesh.vertexCount(), 0.0), thin),
               InvalidInput);
  EXPECT_THROW(ThinRegionPlanner(layers[0].mesh, std::vector<double>(3, 0.0)), InvalidInput);
}

TEST(ThinRegions, IsDeterministic) {
  const auto layers = oneLayer(
      joined(makeRectangle(0, 30, 0, 2.5, 1.5, 60, 5), makeDisc(Vec3(50, 0, 1.5), 1.0, 10, 40)));
  const PlanResult a = planLayers(layers, TriMesh{}, PlannerOptions{});
  const PlanResult b = planLayers(layers, TriMesh{}, PlannerOptions{});
  EXPECT_EQ(formatPlanJson(a.plan), formatPlanJson(b.plan));
  EXPECT_EQ(a.plan.layers[0].paths.size(), 2u);
}

}  // namespace
}  // namespace curvedslicer
