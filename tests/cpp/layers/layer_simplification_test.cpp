// simplifyLayerSurface (layers/layer_simplification.hpp) and its use in extractLayers: the
// simplified surface stays within the tolerance of the full one (checked by a second computation:
// distances of the simplified vertices and of points sampled on its triangles to the full
// surface, with the project's triangle hierarchy), the rim stays where it was (on the part
// surface), orientation, the option off, bad input and determinism.
#include "curvedslicer/layers/layer_simplification.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "common/shapes.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/layers/layer_extraction.hpp"

namespace curvedslicer {
namespace {

/// Height field z = f(x, y) over [0, size]² on an n × n grid of squares, each split into two
/// triangles (normals +z).
template <class F>
TriMesh makeHeightField(double size, int n, F f) {
  TriMesh m;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = size * i / n, y = size * j / n;
      m.vertices.emplace_back(x, y, f(x, y));
    }
  }
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      m.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return m;
}

/// Largest distance from `simplified` to `full`: every vertex and a barycentric grid of
/// (k+1)(k+2)/2 points on every triangle.
double largestDistance(const TriMesh& simplified, const TriMesh& full, int k = 8) {
  const TriangleBvh reference(full);
  double worst = 0.0;
  for (const Vec3& v : simplified.vertices) worst = std::max(worst, reference.distance(v));
  for (std::size_t t = 0; t < simplified.triangleCount(); ++t) {
    const Vec3 &a = simplified.corner(t, 0), &b = simplified.corner(t, 1),
               &c = simplified.corner(t, 2);
    for (int i = 0; i <= k; ++i) {
      for (int j = 0; i + j <= k; ++j) {
        const double u = static_cast<double>(i) / k, v = static_cast<double>(j) / k;
        worst = std::max(worst, reference.distance(a + u * (b - a) + v * (c - a)));
      }
    }
  }
  return worst;
}

/// Boundary edges (used by one triangle), as sorted position pairs.
std::set<std::pair<std::vector<double>, std::vector<double>>> borderEdges(const TriMesh& m) {
  std::map<std::pair<int, int>, int> uses;
  for (const Vec3i& t : m.triangles) {
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
  }
  std::set<std::pair<std::vector<double>, std::vector<double>>> edges;
  auto key = [&m](int v) {
    const Vec3& p = m.vertices[static_cast<std::size_t>(v)];
    return std::vector<double>{p.x(), p.y(), p.z()};
  };
  for (const auto& [edge, count] : uses) {
    if (count == 1) edges.insert(std::minmax(key(edge.first), key(edge.second)));
  }
  return edges;
}

TEST(LayerSimplification, CurvedSurfaceStaysWithinTheTolerance) {
  const TriMesh full = makeHeightField(20.0, 80, [](double x, double y) {
    return 1.5 * std::sin(0.3 * x) * std::cos(0.25 * y) + 0.02 * x;
  });
  for (double tolerance : {0.01, 0.05}) {
    SCOPED_TRACE("tolerance " + std::to_string(tolerance));
    const SimplifiedSurface s = simplifyLayerSurface(full, tolerance);
    EXPECT_FALSE(s.keptFull);
    EXPECT_EQ(s.trianglesBefore, full.triangleCount());
    EXPECT_EQ(s.trianglesAfter, s.mesh.triangleCount());
    EXPECT_LT(s.trianglesAfter, full.triangleCount() / 2);  // 12,800 → well below half
    EXPECT_LE(largestDistance(s.mesh, full), tolerance);
    EXPECT_EQ(borderEdges(s.mesh), borderEdges(full));  // rim unchanged, edge for edge
    for (std::size_t t = 0; t < s.mesh.triangleCount(); ++t) {
      EXPECT_GT(s.mesh.areaNormal(t).z(), 0.0) << "triangle " << t;  // orientation kept
    }
    EXPECT_NEAR(surfaceArea(s.mesh), surfaceArea(full), 0.01 * surfaceArea(full));
  }
  // A looser tolerance removes more.
  EXPECT_LT(simplifyLayerSurface(full, 0.05).trianglesAfter,
            simplifyLayerSurface(full, 0.01).trianglesAfter);
}

TEST(LayerSimplification, FlatSurfaceCollapsesToItsRim) {
  const TriMesh full = makeHeightField(10.0, 40, [](double, double) { return 2.0; });
  const SimplifiedSurface s = simplifyLayerSurface(full, 1e-3);
  // Of 1,681 vertices the 160 on the rim stay; nearly all interior ones go.
  EXPECT_GE(s.verticesAfter, 160u);
  EXPECT_LT(s.verticesAfter, 200u);
  EXPECT_LT(s.trianglesAfter, 240u);  // from 3,200
  for (std::size_t t = 0; t < s.mesh.triangleCount(); ++t) {
    EXPECT_GT(s.mesh.areaNormal(t).z(), 0.0) << "triangle " << t;  // no slivers, none flipped
  }
  EXPECT_NEAR(surfaceArea(s.mesh), 100.0, 1e-9);
  for (const Vec3& v : s.mesh.vertices) EXPECT_NEAR(v.z(), 2.0, 1e-12);
  EXPECT_EQ(borderEdges(s.mesh), borderEdges(full));
}

TEST(LayerSimplification, FlatSurfaceKeepsEdgesWithinTheLengthLimit) {
  // 40 mm square, 0.5 mm grid: without a limit it collapses to its rim (edges up to ~40 mm
  // long); with a 1.5 mm limit no edge is longer, and it still loses most triangles.
  const TriMesh full = makeHeightField(40.0, 80, [](double, double) { return 2.0; });
  const double limit = 1.5;
  const SimplifiedSurface s = simplifyLayerSurface(full, 1e-3, limit);
  double longest = 0.0;
  for (const Vec3i& f : s.mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      longest = std::max(longest, (s.mesh.vertices[static_cast<std::size_t>(f[k])] -
                                   s.mesh.vertices[static_cast<std::size_t>(f[(k + 1) % 3])])
                                      .norm());
    }
  }
  EXPECT_LE(longest, limit);
  EXPECT_LT(s.trianglesAfter, full.triangleCount() / 2);
  EXPECT_NEAR(surfaceArea(s.mesh), 1600.0, 1e-9);
  EXPECT_EQ(borderEdges(s.mesh), borderEdges(full));
  const SimplifiedSurface unlimited = simplifyLayerSurface(full, 1e-3);
  EXPECT_LT(unlimited.trianglesAfter, s.trianglesAfter);
}

TEST(LayerSimplification, TouchingFansAreWeldedAgainAndKeptInPlace) {
  // Two flat squares of 8 × 8 cells meeting at one corner: vertex (10, 10) is non-manifold.
  TriMesh full = makeHeightField(10.0, 8, [](double, double) { return 0.0; });
  TriMesh second = full;
  for (Vec3& v : second.vertices) v += Vec3(10.0, 10.0, 0.0);
  appendMesh(full, second);
  // Weld the shared corner: the last vertex of the first square is the first of the second.
  const int shared = 80, duplicate = 81;
  for (Vec3i& t : full.triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] == duplicate) t[k] = shared;
      if (t[k] > duplicate) --t[k];
    }
  }
  full.vertices.erase(full.vertices.begin() + duplicate);
  const SimplifiedSurface s = simplifyLayerSurface(full, 1e-3);
  EXPECT_FALSE(s.keptFull);
  EXPECT_LT(s.trianglesAfter, full.triangleCount() / 2);
  const auto corners = std::count_if(s.mesh.vertices.begin(), s.mesh.vertices.end(),
                                     [](const Vec3& v) { return v == Vec3(10.0, 10.0, 0.0); });
  EXPECT_EQ(corners, 1);  // one vertex again, not two copies
  EXPECT_NEAR(surfaceArea(s.mesh), 200.0, 1e-9);
}

TEST(LayerSimplification, EdgeOfThreeTrianglesIsLeftAlone) {
  TriMesh fin;
  fin.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0), Vec3(0.5, 0, 1)};
  fin.triangles = {Vec3i(0, 1, 2), Vec3i(1, 0, 3), Vec3i(0, 1, 4)};
  const SimplifiedSurface s = simplifyLayerSurface(fin, 0.1);
  EXPECT_TRUE(s.keptFull);
  EXPECT_EQ(s.mesh.triangles, fin.triangles);
  EXPECT_EQ(s.mesh.vertices, fin.vertices);
}

TEST(LayerSimplification, RejectsBadTolerances) {
  const TriMesh full = makeHeightField(1.0, 2, [](double, double) { return 0.0; });
  for (double bad : {0.0, -0.1, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()}) {
    EXPECT_THROW(simplifyLayerSurface(full, bad), InvalidInput) << bad;
  }
  LayerSimplificationOptions options;
  EXPECT_DOUBLE_EQ(resolveLayerTolerance(options, 0.5), 0.025);  // 0.05·L
  options.tolerance = 0.1;
  EXPECT_DOUBLE_EQ(resolveLayerTolerance(options, 0.5), 0.1);
  options.tolerance = -1.0;
  EXPECT_THROW(resolveLayerTolerance(options, 0.5), InvalidInput);
  options.tolerance = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(resolveLayerTolerance(options, 0.5), InvalidInput);
}

TEST(LayerSimplification, EmptySurfaceStaysEmpty) {
  const SimplifiedSurface s = simplifyLayerSurface(TriMesh{}, 0.1);
  EXPECT_TRUE(s.mesh.empty());
  EXPECT_FALSE(s.keptFull);
}

TEST(LayerSimplification, Deterministic) {
  const TriMesh full = makeHeightField(
      10.0, 40, [](double x, double y) { return 0.3 * std::sin(x) + 0.2 * std::cos(0.7 * y); });
  const SimplifiedSurface a = simplifyLayerSurface(full, 0.02);
  const SimplifiedSurface b = simplifyLayerSurface(full, 0.02);
  EXPECT_EQ(a.mesh.vertices, b.mesh.vertices);
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
}

// ---- in extractLayers: spherical layers clipped by a cylinder --------------------------------

struct ClippedCase {
  VoxelGrid grid;
  DistanceField field;
  TriMesh model;
};

/// Cylinder r = 5, z in [0.3, 10.3] (64 facets), field = distance from a point below it, so the
/// layers are spherical caps whose rims lie on the cylinder's side.
ClippedCase makeClippedCase(double L) {
  ClippedCase c;
  const double r = 5.0, z0 = 0.3, height = 10.0;
  const Vec3 source(0.2, -0.1, -6.0);
  c.model = testing::makeCylinder(Vec3(0, 0, z0), r, height, 64);
  GridGeometry& g = c.grid.geometry;
  g.voxelSize = L;
  g.corner = Vec3(-r, -r, z0) - Vec3::Constant(2 * L);
  g.dims =
      Vec3i(static_cast<int>(std::ceil(2 * r / L)) + 4, static_cast<int>(std::ceil(2 * r / L)) + 4,
            static_cast<int>(std::ceil(height / L)) + 4);
  c.grid.inside.assign(g.cellCount(), 0);
  c.field.geometry = g;
  c.field.distance.assign(g.cellCount(), kInfF);
  for (std::size_t n = 0; n < g.cellCount(); ++n) {
    const Vec3 p = g.centerInPart(n);
    if (p.head<2>().norm() >= r || p.z() <= z0 || p.z() >= z0 + height) continue;
    c.grid.inside[n] = 1;
    ++c.grid.insideCount;
    c.field.distance[n] = static_cast<float>((p - source).norm() - 6.0);
  }
  return c;
}

TEST(LayerSimplification, LayersStayWithinTheToleranceAndRimsOnThePart) {
  const double L = 0.25;
  const ClippedCase c = makeClippedCase(L);
  LayerOptions options;
  options.layerThickness = 2.0;
  options.thicknessSamples = -1;
  options.simplification.enabled = true;
  LayerOptions full = options;
  full.simplification.enabled = false;
  const LayersResult simplified = extractLayers(c.field, c.grid, c.model, TriMesh{}, options);
  const LayersResult reference = extractLayers(c.field, c.grid, c.model, TriMesh{}, full);
  ASSERT_EQ(simplified.surfaces.size(), reference.surfaces.size());
  ASSERT_GE(simplified.surfaces.size(), 3u);
  const double tolerance = 0.05 * L;  // the default
  EXPECT_DOUBLE_EQ(simplified.stats.simplificationTolerance, tolerance);
  EXPECT_EQ(simplified.stats.layersKeptFull, 0u);
  EXPECT_EQ(simplified.stats.fullResolutionTriangles, reference.stats.simplifiedTriangles);
  EXPECT_LT(simplified.stats.simplifiedTriangles, simplified.stats.fullResolutionTriangles / 3);
  EXPECT_EQ(reference.stats.simplificationTolerance, 0.0);
  EXPECT_EQ(reference.stats.fullResolutionTriangles, reference.stats.simplifiedTriangles);
  const TriangleBvh part(c.model);
  for (std::size_t i = 0; i < simplified.surfaces.size(); ++i) {
    const LayerSurface& s = simplified.surfaces[i];
    const LayerSurface& f = reference.surfaces[i];
    SCOPED_TRACE("layer " + std::to_string(s.index));
    EXPECT_EQ(simplified.summaries[i].fullResolutionTriangles, f.mesh.triangleCount());
    EXPECT_EQ(simplified.summaries[i].triangles, s.mesh.triangleCount());
    EXPECT_LE(largestDistance(s.mesh, f.mesh, 4), tolerance);
    // The rim: the same edges as the full layer's, every vertex on the part surface.
    const auto rim = borderEdges(s.mesh);
    EXPECT_EQ(rim, borderEdges(f.mesh));
    ASSERT_GT(rim.size(), 100u);
    for (const auto& [a, b] : rim) {
      EXPECT_LT(part.distance(Vec3(a[0], a[1], a[2])), 1e-6 * L);
      EXPECT_LT(part.distance(Vec3(b[0], b[1], b[2])), 1e-6 * L);
    }
    EXPECT_NEAR(s.area, f.area, 0.002 * f.area);
    EXPECT_EQ(s.components, f.components);
  }
}

}  // namespace
}  // namespace curvedslicer
