// The planner on hand-made layer surfaces: a flat layer over a plate, concentric spherical shells,
// a stack of flat layers (seams), a thin cylindrical wall, and each bad input with its message.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "common/shapes.hpp"
#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "paths/joined_paths.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;

double angleDegrees(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / kPi;
}

/// A flat rectangle [x0, x1] × [y0, y1] at height z, n × m cells, normals +z.
TriMesh makeFlatPatch(double x0, double x1, double y0, double y1, double z, int n, int m) {
  return testing::makeFlatGrid(x0, x1, y0, y1, z, n, m);
}

LayerSurface makeLayer(int index, double level, TriMesh mesh) {
  LayerSurface s;
  s.index = index;
  s.level = level;
  s.mesh = std::move(mesh);
  return s;
}

/// The side of a cylinder of radius r around the z axis, z in [0, height], open at both ends,
/// normals outward.
/// A surface of revolution about z, open at both ends: rows + 1 rings of `segments` vertices,
/// ring j of radius and height ring(j).
template <class Ring>
TriMesh makeRevolvedSide(int segments, int rows, Ring&& ring) {
  TriMesh mesh;
  for (int j = 0; j <= rows; ++j) {
    const auto [r, z] = ring(j);
    for (int i = 0; i < segments; ++i) {
      const double a = 2.0 * kPi * i / segments;
      mesh.vertices.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
  }
  const auto id = [segments](int i, int j) { return j * segments + (i % segments); };
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < segments; ++i) {
      mesh.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      mesh.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return mesh;
}

TriMesh makeCylinderSide(double r, double height, int segments, int rows) {
  return makeRevolvedSide(segments, rows, [&](int j) { return std::pair(r, height * j / rows); });
}

void expectMessage(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
    FAIL() << "no InvalidInput; expected one containing: " << needle;
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Planner, FlatFirstLayerAbovePlate) {
  // Layer 1 of a 40 × 30 mm block on a plate at z = 0, h = 1.5, s = 3.7.
  const std::vector<LayerSurface> layers = {
      makeLayer(1, 1.5, makeFlatPatch(0, 40, 0, 30, 1.5, 40, 30))};
  const TriMesh plate = makeFlatPatch(-10, 50, -10, 40, 0.0, 2, 2);
  PlannerOptions options;
  const PlanResult result = planLayers(layers, plate, options);
  const Plan& plan = result.plan;
  ASSERT_EQ(plan.layers.size(), 1u);
  // Contour-parallel rings at (k + ½)·s from the edge: the short side (30 mm) fits 4 rings,
  // deposited as one path (connected insets).
  EXPECT_EQ(plan.layers[0].paths.size(), 1u);
  EXPECT_EQ(testing::splitLayerBeads(plan.layers[0].paths).rings, 4u);
  std::size_t points = 0;
  for (const PlanPath& path : plan.layers[0].paths) {
    EXPECT_GT(path.length, 0.0);
    for (const PathPoint& q : path.points) {
      ++points;
      EXPECT_NEAR(q.position.z(), 1.5, 1e-9);
      EXPECT_LT(angleDegrees(q.normal, Vec3::UnitZ()), 1e-6);
      EXPECT_LT(angleDegrees(q.deposition, Vec3(0, 0, -1)), 1.0);
    }
  }
  EXPECT_EQ(result.stats.deposition.towardsSurface, points);
  // The outer ring keeps s/2 from the edge (within the fit tolerance).
  double minEdge = kInf;
  for (const PathPoint& q : plan.layers[0].paths.front().points) {
    const Vec3& p = q.position;
    minEdge = std::min({minEdge, p.x(), 40 - p.x(), p.y(), 30 - p.y()});
  }
  EXPECT_NEAR(minEdge, 1.85, 0.06 + 0.05);
  EXPECT_EQ(plan.parameters.initialCurve, "boundary");
  EXPECT_EQ(plan.parameters.beadSpacing, 3.7);
  EXPECT_NO_THROW(validatePlan(plan));
  // Stage times are reported for every stage.
  ASSERT_EQ(result.stats.stageTimes.size(), 8u);
  EXPECT_EQ(result.stats.stageTimes[0].name, "surface index");
  EXPECT_EQ(result.stats.stageTimes[2].name, "surface geodesic");
  EXPECT_EQ(result.stats.stageTimes[7].name, "coverage");
}

TEST(Planner, MeasuresEveryLayersCoverage) {
  // The 40 × 30 layer with 4 rings at (k + ½)·3.7 from the edge: what the planner records is the
  // coverage of the layer surface by the planned paths; the largest void is the 10.4 × 0.4 mm
  // strip inside the innermost ring (at the centre); the rest are the rings' corners (at most
  // 16 · r²(1 − π/4) = 11.8 mm² for sharp corners, more where the fit rounds them).
  const std::vector<LayerSurface> layers = {
      makeLayer(1, 1.5, makeFlatPatch(0, 40, 0, 30, 1.5, 40, 30))};
  PlannerOptions options;
  options.connectInsets = false;  // four rings, four arc starts, no step-over overlap
  options.fillGaps = false;       // the strip stays void (gap fill widens the ring into it)
  const PlanResult result = planLayers(layers, TriMesh{}, options);
  const LayerCoverage& c = result.plan.layers[0].coverage;
  EXPECT_TRUE(c.measured);
  EXPECT_NEAR(c.area, 1200.0, 1e-6);
  EXPECT_EQ(c.arcStarts, 4u);
  EXPECT_DOUBLE_EQ(c.beadWidth, 3.7);
  const LayerCoverage direct =
      computeLayerCoverage(layers[0].mesh, result.plan.layers[0].paths, 3.7);
  EXPECT_EQ(c.voidShare, direct.voidShare);
  EXPECT_EQ(c.overlapShare, direct.overlapShare);
  EXPECT_GT(c.voidShare * c.area, 10.4 * 0.4);
  EXPECT_LT(c.voidShare, 0.03);
  EXPECT_LT(c.overlapShare, 0.01);
  ASSERT_FALSE(c.voids.empty());
  EXPECT_NEAR((c.voids[0].centre - Vec3(20, 15, 1.5)).norm(), 0.0, 0.5);

  PlannerOptions off;
  off.measureCoverage = false;
  EXPECT_FALSE(planLayers(layers, TriMesh{}, off).plan.layers[0].coverage.measured);
}

TEST(Planner, SphericalShellLayersPointRadiallyInward) {
  // Closed spherical layers (no boundary): the initial curve is the equator (plane z = c.z).
  const Vec3 c(0.0, 0.0, 0.0);
  const double r1 = 20.0, h = 1.5;
  std::vector<LayerSurface> layers;
  for (int k = 1; k <= 3; ++k) {
    layers.push_back(makeLayer(k, k * h, testing::makeSphere(c, r1 + k * h, 5)));
  }
  PlannerOptions options;
  options.beadSpacing = 4.0;
  options.initialCurve.kind = InitialCurveKind::Plane;
  options.initialCurve.planePoint = c;
  options.initialCurve.planeNormal = Vec3::UnitZ();
  const PlanResult result = planLayers(layers, testing::makeSphere(c, r1, 5), options);
  double worst = 0.0;
  for (const PlanLayer& layer : result.plan.layers) {
    EXPECT_GT(testing::splitLayerBeads(layer.paths).rings, 6u) << "layer " << layer.index;
    for (const PlanPath& path : layer.paths) {
      for (const PathPoint& q : path.points) {
        const Vec3 inward = (c - q.position).normalized();
        worst = std::max(worst, angleDegrees(q.deposition, inward));
        EXPECT_LT(angleDegrees(q.normal, -inward), 2.0);
      }
    }
  }
  EXPECT_LT(worst, 2.0);
  std::printf("spherical shell layers: largest angle between V and the radial direction %.3f deg\n",
              worst);
  EXPECT_EQ(result.stats.deposition.normalFallbacks, 0u);
}

TEST(Planner, SeamsOfConsecutiveLayersAreApart) {
  const double s = 3.7;
  std::vector<LayerSurface> layers;
  for (int k = 1; k <= 6; ++k) {
    layers.push_back(makeLayer(k, 1.5 * k, makeFlatPatch(0, 36, 0, 24, 1.5 * k, 36, 24)));
  }
  PlannerOptions options;
  options.beadSpacing = s;
  const PlanResult result = planLayers(layers, {}, options);
  const Plan& plan = result.plan;
  // Every arc start keeps 2·s from where the previous layer's ring parts start (its arc starts
  // and where its links reach a ring).
  std::size_t arcStarts = 0;
  for (std::size_t l = 1; l < plan.layers.size(); ++l) {
    const testing::SplitBeads previous = testing::splitLayerBeads(plan.layers[l - 1].paths);
    for (const PlanPath& path : plan.layers[l].paths) {
      if (path.length <= 8.0 * s) continue;
      ++arcStarts;
      for (const Polyline& prev : previous.beads) {
        const double d = (path.points.front().position - prev.points.front()).norm();
        EXPECT_GE(d, 2.0 * s) << "layer " << l << " path " << path.index;
      }
    }
  }
  EXPECT_GE(arcStarts, plan.layers.size() - 1);
  EXPECT_EQ(result.stats.seamsTooClose, 0u);
  // Layers bottom to top, paths indexed in order.
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    EXPECT_EQ(plan.layers[l].index, static_cast<int>(l));
    EXPECT_FALSE(plan.layers[l].paths.empty());
  }
}

TEST(Planner, PlaneInitialCurveGivesParallelPaths) {
  // Plane x = 19 through a 38 × 20 patch: lines at x = 19 ± k·s, all straight along y.
  const std::vector<LayerSurface> layers = {
      makeLayer(1, 1.5, makeFlatPatch(0, 38, 0, 20, 1.5, 38, 20))};
  PlannerOptions options;
  options.beadSpacing = 4.0;
  options.initialCurve.kind = InitialCurveKind::Plane;
  options.initialCurve.planePoint = Vec3(19, 0, 0);
  options.initialCurve.planeNormal = Vec3::UnitX();
  const PlanResult result = planLayers(layers, {}, options);
  std::vector<double> xs;
  for (const PlanPath& path : result.plan.layers[0].paths) {
    EXPECT_FALSE(path.closed);
    const double x = path.points.front().position.x();
    for (const PathPoint& q : path.points) EXPECT_NEAR(q.position.x(), x, 0.05);
    xs.push_back(x);
  }
  std::sort(xs.begin(), xs.end());
  // x = 3, 7, …, 35 (k = 0 is the section itself)
  ASSERT_EQ(xs.size(), 9u) << ::testing::PrintToString(xs);
  for (std::size_t i = 0; i < xs.size(); ++i) EXPECT_NEAR(xs[i], 3.0 + 4.0 * i, 0.04);
  EXPECT_EQ(result.plan.parameters.initialCurve, "plane:19,0,0,1,0,0");
}

TEST(Planner, ThinWallBeadsAlongCylinder) {
  // The turbine-base case: a wall grown bead on bead from its lowest edge.
  const TriMesh wall = makeCylinderSide(25.0, 10.0, 120, 20);
  ThinWallOptions options;
  options.beadSpacing = 1.65;
  const PlanResult result = planThinWall(wall, options);
  const Plan& plan = result.plan;
  ASSERT_EQ(plan.layers.size(), 6u);  // 1.65 … 9.9 mm
  for (std::size_t k = 0; k < plan.layers.size(); ++k) {
    ASSERT_EQ(plan.layers[k].paths.size(), 1u);
    const PlanPath& bead = plan.layers[k].paths[0];
    EXPECT_TRUE(bead.closed);
    for (const PathPoint& q : bead.points) {
      EXPECT_NEAR(q.position.z(), 1.65 * (k + 1), 0.0165);  // spacing within 1 %
      EXPECT_LT(angleDegrees(q.normal, Vec3::UnitZ()), 1.0);
      EXPECT_LT(angleDegrees(q.deposition, Vec3(0, 0, -1)), 1.0);
    }
    if (k > 0) {  // seams stagger
      const double d =
          (bead.points[0].position - plan.layers[k - 1].paths[0].points[0].position).norm();
      EXPECT_GE(d, 2.0 * 1.65);
    }
  }
  EXPECT_EQ(plan.parameters.initialCurve, "thin-wall:lowest:0,0,1");
  // The edge nearest a point at the top: beads grow downwards.
  options.edge = WallEdgeKind::NearestToPoint;
  options.point = Vec3(25, 0, 10);
  const PlanResult down = planThinWall(wall, options);
  EXPECT_NEAR(down.plan.layers[0].paths[0].points[0].position.z(), 10.0 - 1.65, 0.0165);
  EXPECT_LT(angleDegrees(down.plan.layers[0].paths[0].points[0].deposition, Vec3::UnitZ()), 1.0);
}

/// The side of a cone standing on the plate z = 0: its wall leaves the lower rim (radius r0)
/// inwards at `slopeDeg` above the plate, `length` mm along the wall; rows along it.
TriMesh makeConeSide(double r0, double slopeDeg, double length, int segments, int rows) {
  const double c = std::cos(slopeDeg * kPi / 180.0), s = std::sin(slopeDeg * kPi / 180.0);
  return makeRevolvedSide(segments, rows, [&](int j) {
    const double t = length * j / rows;
    return std::pair(r0 - t * c, t * s);
  });
}

TEST(Planner, ThinWallBeadsNearThePlateAreLaidOntoIt) {
  // A wall leaving the plate at 10° (the turbine base's foot lies at 4-6°): bead k sits
  // z = t sin 10° above the plate, t = 1.65 (k + 1) along the wall, and 1.65 mm from the bead
  // (or edge) before it. The plate is a support (the paper's first case): under Nearest it
  // carries the beads with z < 1.65 (k <= 4); under Growth also those farther from it by less
  // than half a bead, z <= 1.65 + 0.825 (k <= 7). Every other bead leans on the one before it:
  // V along the wall, outwards and down.
  const double slope = 10.0;
  const TriMesh wall = makeConeSide(60.0, slope, 20.0, 240, 40);
  const double c = std::cos(slope * kPi / 180.0), s = std::sin(slope * kPi / 180.0);
  for (const DepositionMethod method : {DepositionMethod::Growth, DepositionMethod::Nearest}) {
    SCOPED_TRACE(method == DepositionMethod::Growth ? "growth" : "nearest");
    ThinWallOptions options;
    options.beadSpacing = 1.65;
    options.deposition.method = method;
    const Plan plan = planThinWall(wall, options).plan;
    ASSERT_EQ(plan.layers.size(), 12u);  // t = 1.65 … 19.8 mm
    const int lastOnPlate = method == DepositionMethod::Growth ? 7 : 4;
    for (std::size_t k = 0; k < plan.layers.size(); ++k) {
      ASSERT_EQ(plan.layers[k].paths.size(), 1u);
      for (const PathPoint& q : plan.layers[k].paths[0].points) {
        const double t = 1.65 * (k + 1);
        ASSERT_NEAR(q.position.z(), t * s, 0.02);
        const Vec3 out = Vec3(q.position.x(), q.position.y(), 0.0).normalized();
        const Vec3 expected =
            static_cast<int>(k) <= lastOnPlate ? Vec3(0, 0, -1) : Vec3(c * out + Vec3(0, 0, -s));
        // 1.5°: the bead before is a polyline of 2 mm chords on a 58 mm radius; a chord turns
        // up to 1° from the tangent at the point, and so does the nearest point's direction
        ASSERT_LT(angleDegrees(q.deposition, expected), 1.5) << "bead " << k;
      }
    }
  }
}

TEST(Planner, RejectsNonPositiveBeadSpacing) {
  const std::vector<LayerSurface> layers = {makeLayer(1, 1.5, makeFlatPatch(0, 9, 0, 9, 1, 9, 9))};
  PlannerOptions options;
  options.beadSpacing = -1.0;
  expectMessage([&] { planLayers(layers, {}, options); },
                "bead spacing must be a positive number of mm: -1");
  options.beadSpacing = 0.0;
  expectMessage([&] { planLayers(layers, {}, options); },
                "bead spacing must be a positive number of mm: 0");
  ThinWallOptions wall;
  wall.beadSpacing = std::nan("");
  expectMessage([&] { planThinWall(makeCylinderSide(5, 5, 12, 4), wall); },
                "bead spacing must be a positive number of mm: nan");
}

TEST(Planner, RejectsCornerAngleOutsideHalfTurn) {
  const std::vector<LayerSurface> layers = {makeLayer(1, 1.5, makeFlatPatch(0, 9, 0, 9, 1, 9, 9))};
  PlannerOptions options;
  for (const double bad : {0.0, -30.0, 180.5, std::nan("")}) {
    options.cornerAngle = bad;
    expectMessage([&] { planLayers(layers, {}, options); },
                  "corner angle must be in (0, 180] degrees: ");
  }
  options.cornerAngle = 0.0;
  expectMessage([&] { planLayers(layers, {}, options); },
                "corner angle must be in (0, 180] degrees: 0; pass a value such as 30, or 180");
  ThinWallOptions wall;
  wall.cornerAngle = 270.0;
  expectMessage([&] { planThinWall(makeCylinderSide(5, 5, 12, 4), wall); },
                "corner angle must be in (0, 180] degrees: 270");
}

TEST(Planner, RejectsSpacingWiderThanEveryLayer) {
  // A 3 mm wide strip reaches 1.5 mm from its edge; s = 8 needs 4 for a ring, and the strip is
  // narrower than the minimum feature width 0.5·s = 4 for a centre bead.
  const std::vector<LayerSurface> layers = {
      makeLayer(1, 1.5, makeFlatPatch(0, 30, 0, 3, 1.5, 60, 6)),
      makeLayer(2, 3.0, makeFlatPatch(0, 30, 0, 3, 3.0, 60, 6))};
  PlannerOptions options;
  options.beadSpacing = 8.0;
  expectMessage([&] { planLayers(layers, {}, options); },
                "bead spacing is wider than every layer: 8 mm, the layers reach at most ");
}

TEST(Planner, NamesLayerWithoutRoomForABead) {
  // Layer 2 is a 1.2 mm strip: no room for s = 3.7, and narrower than the minimum feature width
  // 0.5·s = 1.85 for a centre bead; layer 1 is fine.
  const std::vector<LayerSurface> layers = {
      makeLayer(1, 1.5, makeFlatPatch(0, 30, 0, 20, 1.5, 30, 20)),
      makeLayer(2, 3.0, makeFlatPatch(0, 30, 0, 1.2, 3.0, 60, 4))};
  const PlanResult result = planLayers(layers, {}, PlannerOptions{});
  EXPECT_FALSE(result.plan.layers[0].paths.empty());
  EXPECT_TRUE(result.plan.layers[1].paths.empty());
  const std::vector<std::string>& warnings = result.plan.layers[1].warnings;
  const auto has = [&](const std::string& needle) {
    return std::any_of(warnings.begin(), warnings.end(),
                       [&](const std::string& w) { return w.find(needle) != std::string::npos; });
  };
  EXPECT_TRUE(has("no room for a bead")) << ::testing::PrintToString(warnings);
  // The strip is reported with its location (centroid), width, length and area.
  EXPECT_TRUE(
      has("region at 15,0.6,3 mm, 1.2 mm wide, 30 mm long, 36 mm² left out: narrower "
          "than the minimum feature width 1.85 mm"))
      << ::testing::PrintToString(warnings);
  EXPECT_EQ(result.stats.layersWithoutPaths, 1u);
}

TEST(Planner, NamesLayerMissedByInitialPlane) {
  // The plane x = 25 crosses layer 1 (x up to 30) but not layer 2 (x up to 20).
  const std::vector<LayerSurface> layers = {
      makeLayer(1, 1.5, makeFlatPatch(0, 30, 0, 20, 1.5, 30, 20)),
      makeLayer(2, 3.0, makeFlatPatch(0, 20, 0, 20, 3.0, 20, 20))};
  PlannerOptions options;
  options.initialCurve.kind = InitialCurveKind::Plane;
  options.initialCurve.planePoint = Vec3(25, 0, 0);
  const PlanResult result = planLayers(layers, {}, options);
  EXPECT_FALSE(result.plan.layers[0].paths.empty());
  EXPECT_TRUE(result.plan.layers[1].paths.empty());
  ASSERT_FALSE(result.plan.layers[1].warnings.empty());
  EXPECT_NE(result.plan.layers[1].warnings[0].find("the initial plane misses this layer"),
            std::string::npos);
  // Missing every layer is an error naming the first one.
  options.initialCurve.planePoint = Vec3(100, 0, 0);
  expectMessage([&] { planLayers(layers, {}, options); },
                "no layer got a path: layer 0: the initial plane misses this layer");
}

TEST(Planner, NamesClosedLayerWithoutBoundary) {
  const std::vector<LayerSurface> layers = {
      makeLayer(1, 1.5, testing::makeSphere(Vec3::Zero(), 10, 2))};
  expectMessage([&] { planLayers(layers, {}, PlannerOptions{}); },
                "layer 0: the layer is a closed surface without a boundary");
}

TEST(Planner, RejectsEmptyInputs) {
  expectMessage([] { planLayers({}, {}, PlannerOptions{}); }, "no layer surfaces to plan");
  PlannerOptions options;
  options.initialCurve.kind = InitialCurveKind::Surface;
  expectMessage([&] { validatePlannerOptions(options); }, "initial surface has no triangles");
  expectMessage([] { planThinWall(testing::makeSphere(Vec3::Zero(), 5, 1)); },
                "thin-wall surface has no boundary edge");
  ThinWallOptions tall;
  tall.beadSpacing = 20.0;
  expectMessage([&] { planThinWall(makeCylinderSide(5, 10, 24, 4), tall); },
                "thin wall is lower than one bead: it reaches 10 mm");
}

TEST(Planner, CancelsThroughProgress) {
  const std::vector<LayerSurface> layers = {
      makeLayer(1, 1.5, makeFlatPatch(0, 30, 0, 20, 1.5, 30, 20))};
  const Progress cancel([](double, std::string_view) { return false; });
  EXPECT_THROW(planLayers(layers, {}, PlannerOptions{}, cancel), Cancelled);
}

TEST(Planner, IsDeterministicAndRoundTrips) {
  std::vector<LayerSurface> layers;
  for (int k = 1; k <= 2; ++k) {
    layers.push_back(makeLayer(k, 1.5 * k, makeFlatPatch(0, 25, 0, 15, 1.5 * k, 25, 15)));
  }
  const std::string a = formatPlanJson(planLayers(layers, {}, PlannerOptions{}).plan);
  const std::string b = formatPlanJson(planLayers(layers, {}, PlannerOptions{}).plan);
  EXPECT_EQ(a, b);
  EXPECT_EQ(formatPlanJson(parsePlanJson(a)), a);
}

/// Eleven layers of different cost and outcome (more than one batch of layers on 2 threads):
/// rectangles of several sizes, a strip with a centre bead, a layer without room for a bead.
std::vector<LayerSurface> makeMixedStack() {
  std::vector<LayerSurface> layers;
  for (int k = 0; k < 11; ++k) {
    const double z = 1.5 * (k + 1);
    const double w = 20.0 + 3.0 * (k % 4), d = 12.0 + 2.0 * (k % 3);
    TriMesh mesh = k == 4 ? makeFlatPatch(0, 30, 0, 3, z, 60, 6)  // centre bead
                   : k == 7
                       ? makeFlatPatch(0, 30, 0, 1.2, z, 60, 4)  // no room for a bead
                       : makeFlatPatch(0, w, 0, d, z, static_cast<int>(w), static_cast<int>(d));
    layers.push_back(makeLayer(k, z, std::move(mesh)));
  }
  return layers;
}

TEST(Planner, ParallelLayersGiveTheSequentialPlan) {
  const std::vector<LayerSurface> layers = makeMixedStack();
  const TriMesh plate = makeFlatPatch(-10, 40, -10, 30, 0.0, 2, 2);
  PlannerOptions options;
  options.threads = 1;
  const PlanResult sequential = planLayers(layers, plate, options);
  const std::string expected = formatPlanJson(sequential.plan);
  ASSERT_EQ(sequential.plan.layers.size(), layers.size());
  EXPECT_TRUE(sequential.plan.layers[7].paths.empty());
  EXPECT_GT(sequential.stats.seamsTooClose + sequential.stats.insetLinks, 0u);
  for (const int threads : {2, 3, 0}) {
    options.threads = threads;
    const PlanResult parallel = planLayers(layers, plate, options);
    EXPECT_EQ(formatPlanJson(parallel.plan), expected) << threads << " threads";
    const PlanStats& a = sequential.stats;
    const PlanStats& b = parallel.stats;
    EXPECT_EQ(b.droppedFragments, a.droppedFragments) << threads << " threads";
    EXPECT_EQ(b.seamsTooClose, a.seamsTooClose) << threads << " threads";
    EXPECT_EQ(b.insetLinks, a.insetLinks) << threads << " threads";
    EXPECT_EQ(b.travel, a.travel) << threads << " threads";
    EXPECT_EQ(b.arcLength, a.arcLength) << threads << " threads";
    EXPECT_EQ(b.maxFitDeviation, a.maxFitDeviation) << threads << " threads";
    EXPECT_EQ(b.layersWithoutPaths, a.layersWithoutPaths) << threads << " threads";
    EXPECT_EQ(b.deposition.towardsSurface, a.deposition.towardsSurface) << threads << " threads";
    EXPECT_EQ(b.deposition.minDistance, a.deposition.minDistance) << threads << " threads";
    EXPECT_EQ(b.deposition.maxDistance, a.deposition.maxDistance) << threads << " threads";
    ASSERT_EQ(b.stageTimes.size(), 8u);
  }
}

TEST(Planner, ParallelLayersNameTheFirstLayerWithoutPaths) {
  // Every layer misses the plane: the error names layer 0 whichever thread planned it first.
  std::vector<LayerSurface> layers;
  for (int k = 0; k < 9; ++k) {
    layers.push_back(makeLayer(k, 1.5 * (k + 1), makeFlatPatch(0, 20, 0, 20, 1.5 * (k + 1), 8, 8)));
  }
  PlannerOptions options;
  options.threads = 2;
  options.initialCurve.kind = InitialCurveKind::Plane;
  options.initialCurve.planePoint = Vec3(100, 0, 0);
  expectMessage([&] { planLayers(layers, {}, options); },
                "no layer got a path: layer 0: the initial plane misses this layer");
}

TEST(Planner, ParallelLayersCancelThroughProgress) {
  const std::vector<LayerSurface> layers = makeMixedStack();
  PlannerOptions options;
  options.threads = 2;
  int calls = 0;
  const Progress cancelLater([&calls](double, std::string_view) { return ++calls < 3; });
  EXPECT_THROW(planLayers(layers, {}, options, cancelLater), Cancelled);
}

TEST(Planner, ParallelLayersRethrowTheErrorOfALayerInTheMiddle) {
  // Layer 9 (beyond the first window of drafts on 2 threads) has a non-finite vertex: every
  // thread count stops with the error the layer-by-layer run gives.
  std::vector<LayerSurface> layers = makeMixedStack();
  layers[9].mesh.vertices[3].x() = std::nan("");
  PlannerOptions options;
  options.threads = 1;
  std::string expected;
  try {
    planLayers(layers, {}, options);
  } catch (const InvalidInput& e) {
    expected = e.what();
  }
  ASSERT_FALSE(expected.empty());
  for (const int threads : {2, 3}) {
    options.threads = threads;
    expectMessage([&] { planLayers(layers, {}, options); }, expected);
  }
}

TEST(Planner, RejectsNegativeThreads) {
  PlannerOptions options;
  options.threads = -1;
  expectMessage([&] { validatePlannerOptions(options); },
                "planner threads must not be negative: -1");
}

}  // namespace
}  // namespace curvedslicer
