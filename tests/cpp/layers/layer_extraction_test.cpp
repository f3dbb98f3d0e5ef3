// extractLayers (layers/layer_extraction.hpp) on hand-built grids with analytic distance fields:
// planes in a cylinder, spheres in a thick shell, exact extension of linear fields, eq. 13 voxel
// sets, bad input, cancellation and determinism.
#include "curvedslicer/layers/layer_extraction.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <utility>

#include "common/shapes.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"

namespace curvedslicer {
namespace {

using std::numbers::pi;

struct HandCase {
  VoxelGrid grid;
  DistanceField field;
};

/// Model-aligned grid over [lo, hi] plus 2 cells of padding; inside = predicate at cell centres;
/// field = `distance` at inside centres, +inf elsewhere.
HandCase makeCase(const Vec3& lo, const Vec3& hi, double L,
                  const std::function<bool(const Vec3&)>& inside,
                  const std::function<double(const Vec3&)>& distance) {
  HandCase c;
  GridGeometry& g = c.grid.geometry;
  g.voxelSize = L;
  g.corner = lo - Vec3::Constant(2 * L);
  for (int a = 0; a < 3; ++a) g.dims[a] = static_cast<int>(std::ceil((hi[a] - lo[a]) / L)) + 4;
  c.grid.inside.assign(g.cellCount(), 0);
  c.field.geometry = g;
  c.field.distance.assign(g.cellCount(), kInfF);
  for (std::size_t n = 0; n < g.cellCount(); ++n) {
    const Vec3 p = g.centerInPart(n);
    if (!inside(p)) continue;
    c.grid.inside[n] = 1;
    ++c.grid.insideCount;
    c.field.distance[n] = static_cast<float>(distance(p));
  }
  return c;
}

/// Two triangles covering the square |x|, |y| <= half at height z.
TriMesh makeSquare(double z, double half) {
  TriMesh m;
  m.vertices = {Vec3(-half, -half, z), Vec3(half, -half, z), Vec3(half, half, z),
                Vec3(-half, half, z)};
  m.triangles = {Vec3i(0, 1, 2), Vec3i(0, 2, 3)};
  return m;
}

/// Topology summary: V − E + F, edges used by more than two triangles, boundary edges, and
/// directed edges used twice (inconsistent orientation).
struct Topology {
  long euler = 0;
  std::size_t nonManifoldEdges = 0, boundaryEdges = 0, misorientedEdges = 0;
  std::vector<int> boundaryVertices;
};

Topology topologyOf(const TriMesh& m) {
  std::map<std::pair<int, int>, int> undirected, directed;
  for (const Vec3i& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      ++undirected[std::minmax(a, b)];
      ++directed[{a, b}];
    }
  }
  Topology topo;
  topo.euler = static_cast<long>(m.vertices.size()) - static_cast<long>(undirected.size()) +
               static_cast<long>(m.triangles.size());
  std::vector<char> onBoundary(m.vertices.size(), 0);
  for (const auto& [edge, uses] : undirected) {
    if (uses > 2) ++topo.nonManifoldEdges;
    if (uses == 1) {
      ++topo.boundaryEdges;
      onBoundary[edge.first] = onBoundary[edge.second] = 1;
    }
  }
  for (const auto& [edge, uses] : directed) topo.misorientedEdges += uses > 1 ? 1 : 0;
  for (std::size_t v = 0; v < onBoundary.size(); ++v) {
    if (onBoundary[v]) topo.boundaryVertices.push_back(static_cast<int>(v));
  }
  return topo;
}

// ---- cylinder: d = z − z0 -------------------------------------------------------------------

constexpr double kR = 5.0, kH = 10.0, kZ0 = 0.3, kL = 0.25;
constexpr int kSegments = 64;

HandCase makeCylinderCase(double z0 = kZ0, double L = kL) {
  return makeCase(
      Vec3(-kR, -kR, z0), Vec3(kR, kR, z0 + kH), L,
      [&](const Vec3& p) { return p.head<2>().norm() < kR && p.z() > z0 && p.z() < z0 + kH; },
      [z0](const Vec3& p) { return p.z() - z0; });
}

double polygonArea() {
  return 0.5 * kSegments * kR * kR * std::sin(2 * pi / kSegments);
}

/// The clipped layer is the polygon, less tiny corner cuts where its rim chord skips a polygon
/// corner (rim vertices lie on the facets).
void expectPolygonArea(double area, double polygon) {
  EXPECT_LE(area, polygon * (1 + 1e-9));
  EXPECT_GE(area, polygon * (1 - 0.005));
}

void expectCylinderLayers(const LayersResult& result, double z0, double h, int expected) {
  const TriangleBvh model(testing::makeCylinder(Vec3(0, 0, z0), kR, kH, kSegments));
  ASSERT_EQ(static_cast<int>(result.surfaces.size()), expected);
  for (const LayerSurface& layer : result.surfaces) {
    SCOPED_TRACE("layer " + std::to_string(layer.index));
    EXPECT_DOUBLE_EQ(layer.level, layer.index * h);
    ASSERT_FALSE(layer.mesh.empty());
    double maxDeviation = 0.0;
    for (const Vec3& v : layer.mesh.vertices) {
      maxDeviation = std::max(maxDeviation, std::abs(v.z() - (z0 + layer.level)));
    }
    EXPECT_LT(maxDeviation, 1e-5);  // << 0.25 L
    const Topology topo = topologyOf(layer.mesh);
    EXPECT_EQ(topo.euler, 1);  // a disk
    EXPECT_EQ(topo.nonManifoldEdges, 0u);
    EXPECT_EQ(topo.misorientedEdges, 0u);
    ASSERT_GT(topo.boundaryVertices.size(), 100u);
    double maxRim = 0.0;
    for (int v : topo.boundaryVertices) {
      maxRim = std::max(maxRim, model.distance(layer.mesh.vertices[v]));
    }
    EXPECT_LT(maxRim, 1e-6);
    for (std::size_t t = 0; t < layer.mesh.triangleCount(); ++t) {
      EXPECT_GT(layer.mesh.areaNormal(t).z(), 0.0);  // normals towards increasing distance
    }
    EXPECT_NEAR(layer.area, pi * kR * kR, 0.01 * pi * kR * kR);
    expectPolygonArea(layer.area, polygonArea());
    EXPECT_EQ(layer.components, 1u);
    EXPECT_EQ(layer.thicknessToPrevious.samples, layer.mesh.vertexCount());
    EXPECT_NEAR(layer.thicknessToPrevious.min, h, 1e-4);
    EXPECT_NEAR(layer.thicknessToPrevious.mean, h, 1e-4);
    EXPECT_NEAR(layer.thicknessToPrevious.max, h, 1e-3);
  }
}

TEST(LayerExtraction, CylinderLayersArePlanesClippedToTheModel) {
  const HandCase c = makeCylinderCase();
  const TriMesh model = testing::makeCylinder(Vec3(0, 0, kZ0), kR, kH, kSegments);
  LayerOptions options;
  options.layerThickness = 1.0;
  options.thicknessSamples = 0;  // every vertex
  const LayersResult result =
      extractLayers(c.field, c.grid, model, makeSquare(kZ0, 2 * kR), options);
  expectCylinderLayers(result, kZ0, 1.0, 9);  // top inside centre: d = 9.875
  EXPECT_GT(result.stats.extendedCells, 0u);
  EXPECT_EQ(result.stats.nearestFallbacks, 0u);
  EXPECT_GT(result.stats.rimVertices, 0u);
  EXPECT_GT(result.stats.exactDistanceQueries, 0u);
}

TEST(LayerExtraction, LevelsExactlyOnCellCentresStayWatertight) {
  // makeCase puts centres at z = z0 − 2L + (m + 0.5)L; with d = z − (z0 − 1.5L) every value is
  // m·L exactly (all numbers dyadic), so each level passes through a whole plane of centres.
  const double z0 = 0.5, shift = z0 - 1.5 * kL;
  const HandCase c = makeCase(
      Vec3(-kR, -kR, z0), Vec3(kR, kR, z0 + kH), kL,
      [&](const Vec3& p) { return p.head<2>().norm() < kR && p.z() > z0 && p.z() < z0 + kH; },
      [&](const Vec3& p) { return p.z() - shift; });
  bool exactHit = false;
  for (float d : c.field.distance) exactHit = exactHit || d == 1.0f;
  ASSERT_TRUE(exactHit);
  const TriMesh model = testing::makeCylinder(Vec3(0, 0, z0), kR, kH, kSegments);
  LayerOptions options;
  options.layerThickness = 1.0;
  const LayersResult result =
      extractLayers(c.field, c.grid, model, makeSquare(shift, 2 * kR), options);
  ASSERT_EQ(result.surfaces.size(), 10u);  // top inside centre: d = 10.25
  for (const LayerSurface& layer : result.surfaces) {
    SCOPED_TRACE("layer " + std::to_string(layer.index));
    for (const Vec3& v : layer.mesh.vertices) ASSERT_NEAR(v.z(), shift + layer.level, 1e-5);
    const Topology topo = topologyOf(layer.mesh);
    EXPECT_EQ(topo.euler, 1);
    EXPECT_EQ(topo.nonManifoldEdges, 0u);
    EXPECT_EQ(topo.misorientedEdges, 0u);
    EXPECT_EQ(layer.components, 1u);
    expectPolygonArea(layer.area, polygonArea());
  }
}

TEST(LayerExtraction, UnclippedLayersExtendBeyondTheSolidOnTheSamePlanes) {
  const HandCase c = makeCylinderCase();
  LayerOptions options;
  options.layerThickness = 1.0;
  options.clipToSolid = false;
  const LayersResult result =
      extractLayers(c.field, c.grid, TriMesh{}, makeSquare(kZ0, 2 * kR), options);
  ASSERT_EQ(result.surfaces.size(), 9u);
  for (const LayerSurface& layer : result.surfaces) {
    double maxRadius = 0.0, maxDeviation = 0.0;
    for (const Vec3& v : layer.mesh.vertices) {
      maxRadius = std::max(maxRadius, v.head<2>().norm());
      maxDeviation = std::max(maxDeviation, std::abs(v.z() - (kZ0 + layer.level)));
    }
    EXPECT_LT(maxDeviation, 1e-5);  // the linear field is extended exactly
    EXPECT_GT(maxRadius, kR + 0.9 * kL);
    EXPECT_LT(maxRadius, kR + 3.0 * kL);
    EXPECT_GT(layer.area, pi * kR * kR * 1.05);
    EXPECT_EQ(layer.components, 1u);
  }
}

TEST(LayerExtraction, TiltedLinearFieldExtendedExactly) {
  const Vec3 n = Vec3(0.3, -0.5, 0.8).normalized(), x0(-4.2, 0.1, -3.9);
  const Vec3 centre(0.2, -0.1, 0.05);
  const HandCase c = makeCase(
      centre - Vec3::Constant(4), centre + Vec3::Constant(4), 0.2,
      [&](const Vec3& p) { return (p - centre).norm() < 4.0; },
      [&](const Vec3& p) { return n.dot(p - x0); });
  LayerOptions options;
  options.simplification.enabled = false;  // exactness of the extension, not of simplifying
  options.layerThickness = 0.7;
  options.clipToSolid = false;
  options.thicknessSamples = 100;
  const LayersResult result = extractLayers(c.field, c.grid, TriMesh{}, TriMesh{}, options);
  ASSERT_GT(result.surfaces.size(), 10u);
  EXPECT_EQ(result.stats.partialFits, 0u);
  EXPECT_EQ(result.stats.nearestFallbacks, 0u);
  std::size_t beyond = 0;
  for (const LayerSurface& layer : result.surfaces) {
    for (const Vec3& v : layer.mesh.vertices) {
      ASSERT_NEAR(n.dot(v - x0), layer.level, 2e-5);
      beyond += (v - centre).norm() > 4.0 + 0.5 * 0.2 ? 1 : 0;
    }
  }
  EXPECT_GT(beyond, 0u);  // vertices in the extension band lie on the planes too
  // Layer 1 has no start surface to measure against; later layers measure h (planes).
  EXPECT_EQ(result.surfaces[0].thicknessToPrevious.samples, 0u);
  const ThicknessStats& t5 = result.surfaces[5].thicknessToPrevious;
  EXPECT_LE(t5.samples, 100u);  // strided sample of the vertices
  EXPECT_GE(t5.samples, 50u);
  EXPECT_NEAR(t5.min, 0.7, 1e-4);  // (the unclipped rims end unevenly, so max is larger)
}

TEST(LayerExtraction, OneCellThickPlateUsesInPlaneGradient) {
  // A plate one cell thick: the samples around an outside cell are coplanar, so the fit keeps only
  // the in-plane gradient; d = x − x0 is then still extended exactly.
  const double L = 0.25, x0 = -3.0;
  const HandCase c = makeCase(
      Vec3(-3, -2, -0.5 * L), Vec3(3, 2, 0.5 * L), L,
      [&](const Vec3& p) {
        return std::abs(p.z()) < 0.5 * L && std::abs(p.x()) < 3 && std::abs(p.y()) < 2;
      },
      [&](const Vec3& p) { return p.x() - x0; });
  LayerOptions options;
  options.layerThickness = 1.0;
  options.clipToSolid = false;
  const LayersResult result = extractLayers(c.field, c.grid, TriMesh{}, TriMesh{}, options);
  EXPECT_GT(result.stats.partialFits, 0u);
  ASSERT_EQ(result.surfaces.size(), 5u);
  for (const LayerSurface& layer : result.surfaces) {
    ASSERT_FALSE(layer.mesh.empty());
    for (const Vec3& v : layer.mesh.vertices) ASSERT_NEAR(v.x(), x0 + layer.level, 1e-5);
  }
}

TEST(LayerExtraction, TwoPillarsGiveTwoComponents) {
  const Vec3 a(-3, 0, 0), b(3, 0, 0);
  const double r = 2.0;
  const HandCase c = makeCase(
      Vec3(-5, -2, 0), Vec3(5, 2, 4), 0.25,
      [&](const Vec3& p) {
        return p.z() > 0 && p.z() < 4 &&
               ((p - a).head<2>().norm() < r || (p - b).head<2>().norm() < r);
      },
      [](const Vec3& p) { return p.z(); });
  TriMesh model = testing::makeCylinder(a, r, 4.0, 48);
  appendMesh(model, testing::makeCylinder(b, r, 4.0, 48));
  LayerOptions options;
  options.layerThickness = 1.0;
  options.thicknessSamples = -1;  // not measured
  const LayersResult result = extractLayers(c.field, c.grid, model, makeSquare(0, 6), options);
  ASSERT_EQ(result.surfaces.size(), 3u);
  for (const LayerSurface& layer : result.surfaces) {
    EXPECT_EQ(layer.thicknessToPrevious.samples, 0u);
    EXPECT_EQ(layer.components, 2u);
    expectPolygonArea(layer.area, 2 * 0.5 * 48 * r * r * std::sin(2 * pi / 48));
  }
}

// ---- thick spherical shell: d = |x − c| − R1 ------------------------------------------------

constexpr double kR1 = 3.0, kR2 = 8.0;
const Vec3 kCentre(0.1, -0.2, 0.3);

HandCase makeShellCase(double L) {
  return makeCase(
      kCentre - Vec3::Constant(kR2), kCentre + Vec3::Constant(kR2), L,
      [](const Vec3& p) {
        const double r = (p - kCentre).norm();
        return r > kR1 && r < kR2;
      },
      [](const Vec3& p) { return (p - kCentre).norm() - kR1; });
}

TEST(LayerExtraction, ShellLayersAreClosedSpheres) {
  const double L = 0.25, h = 1.0;
  const HandCase c = makeShellCase(L);
  const TriMesh model = testing::makeSphericalShell(kCentre, kR1, kR2, 4);
  const TriMesh source = testing::makeSphere(kCentre, kR1, 4);
  LayerOptions options;
  options.layerThickness = h;
  options.thicknessSamples = 3000;         // strided runs of vertices: ~4 µs–25 µs per sample
  options.simplification.enabled = false;  // samples and deviation of the full surfaces
  const LayersResult result = extractLayers(c.field, c.grid, model, source, options);
  ASSERT_EQ(result.surfaces.size(), 4u);  // radii 4..7; the top centre is below R2
  for (const LayerSurface& layer : result.surfaces) {
    SCOPED_TRACE("layer " + std::to_string(layer.index));
    const double radius = kR1 + layer.level;
    double maxDeviation = 0.0;
    for (const Vec3& v : layer.mesh.vertices) {
      maxDeviation = std::max(maxDeviation, std::abs((v - kCentre).norm() - radius));
    }
    EXPECT_LT(maxDeviation, 0.05 * L);
    const Topology topo = topologyOf(layer.mesh);
    EXPECT_EQ(topo.euler, 2);
    EXPECT_EQ(topo.boundaryEdges, 0u);  // watertight
    EXPECT_EQ(topo.nonManifoldEdges, 0u);
    EXPECT_EQ(topo.misorientedEdges, 0u);
    EXPECT_NEAR(signedVolume(layer.mesh), 4.0 / 3.0 * pi * std::pow(radius, 3),
                0.01 * 4.0 / 3.0 * pi * std::pow(radius, 3));  // positive: normals outward
    EXPECT_NEAR(layer.area, 4 * pi * radius * radius, 0.01 * 4 * pi * radius * radius);
    EXPECT_EQ(layer.components, 1u);
    EXPECT_LE(layer.thicknessToPrevious.samples, 3000u);
    EXPECT_GE(layer.thicknessToPrevious.samples, 2900u);
    EXPECT_NEAR(layer.thicknessToPrevious.min, h, 0.1 * L);
    EXPECT_NEAR(layer.thicknessToPrevious.mean, h, 0.05 * L);
    EXPECT_NEAR(layer.thicknessToPrevious.max, h, 0.1 * L);
  }
  EXPECT_EQ(result.stats.rimVertices, 0u);  // nothing to clip
}

// ---- eq. 13 voxel sets ------------------------------------------------------------------------

TEST(LayerExtraction, VoxelSetsMatchEquation13) {
  const double L = 0.5, h = 0.3;  // h < L: a voxel may belong to two sets
  const HandCase c = makeShellCase(L);
  LayerOptions options;
  options.layerThickness = h;
  options.clipToSolid = false;
  options.thicknessSamples = 64;  // not under test here
  const LayersResult result = extractLayers(c.field, c.grid, TriMesh{}, TriMesh{}, options);
  double maxD = 0.0;
  for (float d : c.field.distance)
    if (d < kInfF) maxD = std::max(maxD, static_cast<double>(d));
  const auto count = result.voxelSets.size();
  ASSERT_EQ(result.surfaces.size(), count);
  EXPECT_LE(static_cast<double>(count) * h, maxD);
  EXPECT_GT(static_cast<double>(count + 1) * h, maxD);
  std::vector<std::vector<std::size_t>> expected(count);
  for (std::size_t n = 0; n < c.field.distance.size(); ++n) {
    const float value = c.field.distance[n];
    if (!(value < kInfF)) continue;
    const double t = value;
    for (std::size_t i = 1; i <= count; ++i) {
      if (i * h - L / 2 <= t && t <= i * h + L / 2) expected[i - 1].push_back(n);
    }
  }
  std::size_t inTwo = 0;
  std::map<std::size_t, int> membership;
  for (std::size_t i = 0; i < count; ++i) {
    EXPECT_EQ(result.voxelSets[i].index, static_cast<int>(i + 1));
    EXPECT_DOUBLE_EQ(result.voxelSets[i].level, (i + 1) * h);
    EXPECT_EQ(result.voxelSets[i].cells, expected[i]) << "set " << i + 1;
    for (std::size_t n : result.voxelSets[i].cells) inTwo += ++membership[n] == 2 ? 1 : 0;
  }
  EXPECT_GT(inTwo, 0u);
}

// ---- bad input, cancellation, determinism ------------------------------------------------------

TEST(LayerExtraction, RejectsBadLayerThickness) {
  const HandCase c = makeCylinderCase(kZ0, 0.5);
  const TriMesh model = testing::makeCylinder(Vec3(0, 0, kZ0), kR, kH, kSegments);
  for (double h : {0.0, -1.5, std::numeric_limits<double>::quiet_NaN(), kInf}) {
    LayerOptions options;
    options.layerThickness = h;
    try {
      extractLayers(c.field, c.grid, model, TriMesh{}, options);
      ADD_FAILURE() << "no exception for h = " << h;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("layer thickness must be positive"), std::string::npos)
          << e.what();
    }
  }
}

TEST(LayerExtraction, RejectsTooManyLayers) {
  const HandCase c = makeCylinderCase(kZ0, 0.5);
  const TriMesh model = testing::makeCylinder(Vec3(0, 0, kZ0), kR, kH, kSegments);
  LayerOptions options;
  options.layerThickness = 1.0;
  options.maxLayers = 5;
  try {
    extractLayers(c.field, c.grid, model, TriMesh{}, options);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("gives 9 layers"), std::string::npos) << what;
    EXPECT_NE(what.find("increase the layer thickness"), std::string::npos) << what;
  }
}

TEST(LayerExtraction, RejectsMismatchedOrEmptyInputs) {
  HandCase c = makeCylinderCase(kZ0, 0.5);
  const TriMesh model = testing::makeCylinder(Vec3(0, 0, kZ0), kR, kH, kSegments);
  EXPECT_THROW(extractLayers(c.field, c.grid, TriMesh{}, TriMesh{}), InvalidInput);  // no model
  DistanceField shifted = c.field;
  shifted.geometry.dims.x() += 1;
  EXPECT_THROW(extractLayers(shifted, c.grid, model, TriMesh{}), InvalidInput);
  DistanceField unreached = c.field;
  std::fill(unreached.distance.begin(), unreached.distance.end(), kInfF);
  EXPECT_THROW(extractLayers(unreached, c.grid, model, TriMesh{}), InvalidInput);
  DistanceField withNan = c.field;
  withNan.distance[withNan.distance.size() / 2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(extractLayers(withNan, c.grid, model, TriMesh{}), InvalidInput);
  // Thinner than one layer: no layers, no error.
  LayerOptions thick;
  thick.layerThickness = 50.0;
  const LayersResult none = extractLayers(c.field, c.grid, model, TriMesh{}, thick);
  EXPECT_TRUE(none.surfaces.empty());
  EXPECT_TRUE(none.voxelSets.empty());
}

TEST(LayerExtraction, ReportsProgressAndCancels) {
  const HandCase c = makeCylinderCase(kZ0, 0.5);
  const TriMesh model = testing::makeCylinder(Vec3(0, 0, kZ0), kR, kH, kSegments);
  std::vector<double> fractions;
  const Progress watch([&](double f, std::string_view) {
    fractions.push_back(f);
    return true;
  });
  extractLayers(c.field, c.grid, model, TriMesh{}, {}, watch);
  ASSERT_GT(fractions.size(), 5u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);

  for (std::size_t stopAt : {std::size_t{1}, fractions.size() / 2, fractions.size() - 1}) {
    std::size_t calls = 0;
    const Progress cancel([&](double, std::string_view) { return ++calls < stopAt; });
    EXPECT_THROW(extractLayers(c.field, c.grid, model, TriMesh{}, {}, cancel), Cancelled)
        << "stop at call " << stopAt;
  }
}

TEST(LayerExtraction, DeterministicAcrossThreadCounts) {
  const HandCase c = makeShellCase(0.4);
  const TriMesh model = testing::makeSphericalShell(kCentre, kR1, kR2, 3);
  LayerOptions options;
  options.layerThickness = 0.9;
  options.thicknessSamples = 500;
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const LayersResult one = extractLayers(c.field, c.grid, model, TriMesh{}, options);
  omp_set_num_threads(std::max(2, threads));
  const LayersResult many = extractLayers(c.field, c.grid, model, TriMesh{}, options);
  omp_set_num_threads(threads);
  ASSERT_EQ(one.surfaces.size(), many.surfaces.size());
  for (std::size_t i = 0; i < one.surfaces.size(); ++i) {
    EXPECT_EQ(one.surfaces[i].mesh.vertices, many.surfaces[i].mesh.vertices);
    EXPECT_EQ(one.surfaces[i].mesh.triangles, many.surfaces[i].mesh.triangles);
    EXPECT_EQ(one.surfaces[i].area, many.surfaces[i].area);
    EXPECT_EQ(one.voxelSets[i].cells, many.voxelSets[i].cells);
  }
}

}  // namespace
}  // namespace curvedslicer

// ---- streaming (streamLayers and LayerSink) ----

namespace curvedslicer {
namespace {

/// Records everything a sink receives and the order of the calls.
class RecordingSink final : public LayerSink {
 public:
  int beginCalls = 0;
  int layerCount = -1;
  std::vector<std::size_t> announcedSizes;
  std::vector<LayerSurface> surfaces;
  std::vector<VoxelLayerSet> sets;
  std::vector<std::vector<float>> setDistances;  // distance[n] at each set's cells
  std::string calls;                             // 'b', 's' (surface), 'v' (voxel set)
  int throwAtSurface = 0;                        // 1-based surface index that throws IoError

  void begin(int count, const std::vector<std::size_t>& sizes, const GridGeometry&) override {
    ++beginCalls;
    layerCount = count;
    announcedSizes = sizes;
    calls += 'b';
  }
  void acceptSurface(LayerSurface&& surface) override {
    if (surface.index == throwAtSurface) throw IoError("disk full: test; free some space");
    calls += 's';
    surfaces.push_back(std::move(surface));
  }
  void acceptVoxelSet(VoxelLayerSet&& set, const std::vector<float>& distance) override {
    calls += 'v';
    std::vector<float> d;
    for (std::size_t n : set.cells) d.push_back(distance[n]);
    setDistances.push_back(std::move(d));
    sets.push_back(std::move(set));
  }
};

void expectSameLayers(const LayersResult& expected, const RecordingSink& sink,
                      const LayersResult& streamed) {
  ASSERT_EQ(sink.surfaces.size(), expected.surfaces.size());
  ASSERT_EQ(sink.sets.size(), expected.voxelSets.size());
  ASSERT_EQ(streamed.summaries.size(), expected.surfaces.size());
  for (std::size_t i = 0; i < expected.surfaces.size(); ++i) {
    const LayerSurface& a = expected.surfaces[i];
    const LayerSurface& b = sink.surfaces[i];
    EXPECT_EQ(a.index, b.index);
    EXPECT_EQ(a.level, b.level);
    EXPECT_EQ(a.mesh.vertices, b.mesh.vertices) << "layer " << a.index;
    EXPECT_EQ(a.mesh.triangles, b.mesh.triangles) << "layer " << a.index;
    EXPECT_EQ(a.area, b.area);
    EXPECT_EQ(a.components, b.components);
    EXPECT_EQ(a.thicknessToPrevious.samples, b.thicknessToPrevious.samples);
    EXPECT_EQ(a.thicknessToPrevious.min, b.thicknessToPrevious.min);
    EXPECT_EQ(a.thicknessToPrevious.mean, b.thicknessToPrevious.mean);
    EXPECT_EQ(a.thicknessToPrevious.max, b.thicknessToPrevious.max);
    EXPECT_EQ(expected.voxelSets[i].index, sink.sets[i].index);
    EXPECT_EQ(expected.voxelSets[i].cells, sink.sets[i].cells) << "set " << i + 1;
    const LayerSummary& s = streamed.summaries[i];
    EXPECT_EQ(s.index, a.index);
    EXPECT_EQ(s.vertices, a.mesh.vertexCount());
    EXPECT_EQ(s.triangles, a.mesh.triangleCount());
    EXPECT_EQ(s.area, a.area);
    EXPECT_EQ(s.voxelSetSize, expected.voxelSets[i].cells.size());
  }
  EXPECT_EQ(streamed.stats.extendedCells, expected.stats.extendedCells);
  EXPECT_EQ(streamed.stats.exactDistanceQueries, expected.stats.exactDistanceQueries);
  EXPECT_EQ(streamed.stats.rimVertices, expected.stats.rimVertices);
}

TEST(LayerStreaming, SameLayersInAnyBatchingAsInMemory) {
  const HandCase c = makeShellCase(0.4);
  const TriMesh model = testing::makeSphericalShell(kCentre, kR1, kR2, 3);
  const TriMesh source = testing::makeSphere(kCentre, kR1, 3);  // the start surface
  LayerOptions options;
  options.layerThickness = 0.9;
  options.thicknessSamples = 300;
  const LayersResult expected = extractLayers(c.field, c.grid, model, source, options);
  ASSERT_GT(expected.surfaces.size(), 4u);
  EXPECT_EQ(expected.batches, 1u) << "the default budget fits this small case in one batch";
  ASSERT_EQ(expected.summaries.size(), expected.surfaces.size());

  std::size_t previousBatches = 0;
  for (std::size_t budget : {std::size_t{100000}, std::size_t{3000}, std::size_t{1}}) {
    LayerOptions o = options;
    o.batchCrossings = budget;
    DistanceField field = c.field;
    RecordingSink sink;
    const LayersResult streamed = streamLayers(std::move(field), c.grid, model, source, sink, o);
    SCOPED_TRACE("batch budget " + std::to_string(budget));
    EXPECT_TRUE(field.distance.empty()) << "the field is consumed";
    EXPECT_TRUE(streamed.surfaces.empty());
    EXPECT_TRUE(streamed.voxelSets.empty());
    EXPECT_EQ(sink.beginCalls, 1);
    EXPECT_EQ(sink.layerCount, static_cast<int>(expected.surfaces.size()));
    for (std::size_t i = 0; i < expected.voxelSets.size(); ++i) {
      EXPECT_EQ(sink.announcedSizes.at(i), expected.voxelSets[i].cells.size());
    }
    expectSameLayers(expected, sink, streamed);
    // Distances handed with the sets are the field's.
    for (std::size_t i = 0; i < sink.sets.size(); ++i) {
      for (std::size_t q = 0; q < sink.sets[i].cells.size(); ++q) {
        ASSERT_EQ(sink.setDistances[i][q], c.field.distance[sink.sets[i].cells[q]]);
      }
    }
    // begin, then per batch its surfaces before its sets; indices increase.
    EXPECT_EQ(sink.calls.front(), 'b');
    EXPECT_GE(streamed.batches, previousBatches);
    previousBatches = streamed.batches;
    if (budget == 1) {
      EXPECT_EQ(streamed.batches, expected.surfaces.size()) << "one level per batch";
      std::string alternating = "b";
      for (std::size_t i = 0; i < expected.surfaces.size(); ++i) alternating += "sv";
      EXPECT_EQ(sink.calls, alternating);
    }
  }
  EXPECT_GT(previousBatches, 1u);
}

TEST(LayerStreaming, UnclippedLayersMatchToo) {
  const HandCase c = makeShellCase(0.5);
  LayerOptions options;
  options.layerThickness = 1.1;
  options.clipToSolid = false;
  options.thicknessSamples = 0;
  const LayersResult expected = extractLayers(c.field, c.grid, TriMesh{}, TriMesh{}, options);
  options.batchCrossings = 2000;
  DistanceField field = c.field;
  RecordingSink sink;
  const LayersResult streamed =
      streamLayers(std::move(field), c.grid, TriMesh{}, TriMesh{}, sink, options);
  EXPECT_GT(streamed.batches, 1u);
  expectSameLayers(expected, sink, streamed);
}

// The automatic batch size (LayerOptions::batchCrossings, kCellsPerBatchCrossing) counts crossed
// cubes; a layer parallel to a grid face — the large thin-walled part's layers, which broke the
// old cells / 64 batches' memory — gives 8 triangles per crossed cube (a quad from each of the
// two Kuhn tetrahedra cut 2|2, a triangle from each of the other four), not the bunny's 4–5.
TEST(LayerStreaming, FlatLayersGiveEightTrianglesPerCrossedCube) {
  const double L = 0.5;
  // Cell centres at z = −0.75 + 0.5k; d = z + 0.35 puts the levels 2, 4, 6, 8 between them.
  const HandCase c = makeCase(
      Vec3::Zero(), Vec3::Constant(8.0), L, [](const Vec3&) { return true; },
      [](const Vec3& p) { return p.z() + 0.35; });
  LayerOptions options;
  options.layerThickness = 2.0;
  options.clipToSolid = false;
  options.thicknessSamples = -1;
  options.batchCrossings = 1;  // one level per batch: largestBatchCrossings is a level's count
  options.simplification.enabled = false;  // the marching tetrahedra's own triangles
  DistanceField field = c.field;
  RecordingSink sink;
  const LayersResult result =
      streamLayers(std::move(field), c.grid, TriMesh{}, TriMesh{}, sink, options);
  ASSERT_EQ(sink.surfaces.size(), 4u);
  EXPECT_EQ(result.batches, 4u);
  EXPECT_EQ(result.largestBatchCrossings, 19u * 19u);  // the dual grid's cubes in one z slab
  for (const LayerSurface& layer : sink.surfaces) {
    EXPECT_EQ(layer.mesh.triangles.size(), 8u * result.largestBatchCrossings) << layer.index;
  }
}

TEST(LayerStreaming, SinkErrorsAndCancellationStopTheExtraction) {
  const HandCase c = makeShellCase(0.5);
  const TriMesh model = testing::makeSphericalShell(kCentre, kR1, kR2, 3);
  LayerOptions options;
  options.layerThickness = 0.9;
  options.batchCrossings = 1;
  {
    RecordingSink sink;
    sink.throwAtSurface = 3;
    DistanceField field = c.field;
    EXPECT_THROW(streamLayers(std::move(field), c.grid, model, TriMesh{}, sink, options), IoError);
    EXPECT_EQ(sink.surfaces.size(), 2u);
  }
  {
    RecordingSink sink;
    DistanceField field = c.field;
    std::size_t calls = 0;
    const Progress cancel([&](double, std::string_view) { return ++calls < 40; });
    EXPECT_THROW(streamLayers(std::move(field), c.grid, model, TriMesh{}, sink, options, cancel),
                 Cancelled);
    EXPECT_LT(sink.surfaces.size(), 9u) << "cancelled before the end";
  }
  {  // Bad input is rejected before the sink hears anything.
    RecordingSink sink;
    DistanceField field = c.field;
    LayerOptions bad = options;
    bad.layerThickness = -1.0;
    EXPECT_THROW(streamLayers(std::move(field), c.grid, model, TriMesh{}, sink, bad), InvalidInput);
    EXPECT_EQ(sink.beginCalls, 0);
  }
}

TEST(LayerStreaming, ProgressNeverGoesBackwardsAcrossBatches) {
  const HandCase c = makeShellCase(0.5);
  const TriMesh model = testing::makeSphericalShell(kCentre, kR1, kR2, 3);
  LayerOptions options;
  options.layerThickness = 0.9;
  options.batchCrossings = 500;
  std::vector<double> fractions;
  const Progress watch([&](double f, std::string_view) {
    fractions.push_back(f);
    return true;
  });
  RecordingSink sink;
  DistanceField field = c.field;
  const LayersResult streamed =
      streamLayers(std::move(field), c.grid, model, TriMesh{}, sink, options, watch);
  EXPECT_GT(streamed.batches, 2u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
}

}  // namespace
}  // namespace curvedslicer
