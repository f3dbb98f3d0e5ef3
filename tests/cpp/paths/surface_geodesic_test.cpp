// GDTC on analytic surfaces: equidistant iso-line paths on a cylinder, a spherical cap, a cone and
// a plane, curve insertion, the paper method's error, bad input.
#include "curvedslicer/paths/surface_geodesic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <numbers>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/iso_lines.hpp"
#include "curvedslicer/paths/path_fit.hpp"
#include "curvedslicer/paths/surface_curves.hpp"
#include "paths/revolution_meshes.hpp"

namespace curvedslicer {
namespace {

using testing::makeRectangleMesh;
using testing::makeRevolutionMesh;
using testing::Profile;

using ScalarOf = std::function<double(const Vec3&)>;

struct CaseStats {
  double spacingError = 0.0;        // largest |spacing − s| / s between neighbouring raw paths
  double fitSpacingError = 0.0;     // the same for the fitted, resampled paths
  double rawSurfaceDistance = 0.0;  // mm, largest distance of a raw path point from the surface
  double fitSurfaceDistance = 0.0;  // mm, the same for fitted points
  double fitDeviation = 0.0;        // mm, largest spline–raw deviation
  int paths = 0;
  int levels = 0;
};

/// Extracts the iso-lines at `values`, fits them, and measures them against the analytic distance
/// `trueDistance` and the analytic surface distance `surfaceDistance`.
CaseStats measurePaths(const SurfaceGeodesicResult& field, const std::vector<double>& values,
                       const ScalarOf& trueDistance, const ScalarOf& surfaceDistance, double s) {
  CaseStats stats;
  std::vector<std::pair<double, double>> rawRange, fitRange;  // per level: min, max true distance
  for (const double value : values) {
    const std::vector<Polyline> lines = extractIsoLines(field.mesh, field.distance, value);
    if (lines.empty()) continue;
    ++stats.levels;
    double lo = kInf, hi = -kInf, flo = kInf, fhi = -kInf;
    for (const Polyline& line : lines) {
      ++stats.paths;
      for (const Vec3& p : line.points) {
        lo = std::min(lo, trueDistance(p));
        hi = std::max(hi, trueDistance(p));
        stats.rawSurfaceDistance = std::max(stats.rawSurfaceDistance, surfaceDistance(p));
      }
      if (line.points.size() < (line.closed ? 3u : 2u)) continue;
      const PathFitResult fit = fitPath(line);
      stats.fitDeviation = std::max(stats.fitDeviation, fit.fitDeviation);
      for (const Vec3& p : fit.points.points) {
        flo = std::min(flo, trueDistance(p));
        fhi = std::max(fhi, trueDistance(p));
        stats.fitSurfaceDistance = std::max(stats.fitSurfaceDistance, surfaceDistance(p));
      }
    }
    rawRange.emplace_back(lo, hi);
    fitRange.emplace_back(flo, fhi);
  }
  auto spacingError = [s](const std::vector<std::pair<double, double>>& range) {
    double worst = 0.0;
    for (std::size_t k = 0; k + 1 < range.size(); ++k) {
      const double smallest = range[k + 1].first - range[k].second;
      const double largest = range[k + 1].second - range[k].first;
      worst = std::max({worst, std::abs(smallest - s) / s, std::abs(largest - s) / s});
    }
    return worst;
  };
  stats.spacingError = spacingError(rawRange);
  stats.fitSpacingError = spacingError(fitRange);
  return stats;
}

/// The boundary loop whose points all satisfy `select`.
std::vector<Polyline> boundaryWhere(const TriMesh& mesh,
                                    const std::function<bool(const Vec3&)>& select) {
  std::vector<Polyline> chosen;
  for (const Polyline& loop : extractBoundaryLoops(mesh)) {
    if (select(loop.points.front())) chosen.push_back(loop);
  }
  return chosen;
}

struct AnalyticCase {
  const char* name;
  TriMesh mesh;
  std::vector<Polyline> curve;
  IsoValueStart start;
  ScalarOf trueDistance;
  ScalarOf surfaceDistance;
  double maxDistance;
};

constexpr double kSpacing = 3.7;

AnalyticCase cylinderCase() {
  const double R = 20.0, H = 30.0;
  Profile profile{[R](double) { return R; }, [](double t) { return t; }, 0.0, H, 50};
  AnalyticCase c{"cylinder",
                 makeRevolutionMesh(profile, 0.6),
                 {},
                 IsoValueStart::Boundary,
                 [](const Vec3& p) { return p.z(); },
                 [R](const Vec3& p) { return std::abs(std::hypot(p.x(), p.y()) - R); },
                 H};
  c.curve = boundaryWhere(c.mesh, [](const Vec3& p) { return p.z() < 1e-9; });
  return c;
}

AnalyticCase sphericalCapCase() {
  // Polar angle 0.95 rad: the innermost path (at 20.35 mm) keeps a geodesic radius of 3.4 mm.
  // Paths tighter than ~2.5 edge lengths around the pole are less accurate (see METHODS.md).
  const double R = 25.0, theta = 0.95;
  Profile profile{[R](double t) { return R * std::sin(t); },
                  [R](double t) { return R * std::cos(t); }, 0.0, theta, 40};
  AnalyticCase c{"spherical cap",
                 makeRevolutionMesh(profile, 0.6),
                 {},
                 IsoValueStart::Boundary,
                 [R, theta](const Vec3& p) {
                   return R * (theta - std::atan2(std::hypot(p.x(), p.y()), p.z()));
                 },
                 [R](const Vec3& p) { return std::abs(p.norm() - R); },
                 R * theta};
  c.curve = extractBoundaryLoops(c.mesh);
  return c;
}

AnalyticCase coneCase() {
  // Frustum side: r = 20 − z/2 for z in [0, 24]; slant factor √(1 + ¼).
  const double k = std::sqrt(1.25);
  Profile profile{[](double z) { return 20.0 - 0.5 * z; }, [](double z) { return z; }, 0.0, 24.0,
                  36};
  AnalyticCase c{
      "cone",
      makeRevolutionMesh(profile, 0.6),
      {},
      IsoValueStart::Boundary,
      [k](const Vec3& p) { return p.z() * k; },
      [k](const Vec3& p) { return std::abs(std::hypot(p.x(), p.y()) - 20.0 + 0.5 * p.z()) / k; },
      24.0 * k};
  c.curve = boundaryWhere(c.mesh, [](const Vec3& p) { return p.z() < 1e-9; });
  return c;
}

AnalyticCase planeCase() {
  // The line x = 13.3 (not through vertices), from a plane section; paths on both sides.
  AnalyticCase c{"plane",
                 makeRectangleMesh(0.0, 40.0, 0.0, 30.0, 50, 40),
                 {},
                 IsoValueStart::InteriorCurve,
                 [](const Vec3& p) { return std::abs(p.x() - 13.3); },
                 [](const Vec3& p) { return std::abs(p.z()); },
                 26.7};
  c.curve = computePlaneSection(c.mesh, Vec3(13.3, 0, 0), Vec3(1, 0, 0));
  return c;
}

void checkAccurate(const AnalyticCase& c) {
  SCOPED_TRACE(c.name);
  ASSERT_FALSE(c.curve.empty());
  const SurfaceGeodesicResult field = computeSurfaceGeodesic(c.mesh, c.curve);
  EXPECT_EQ(field.unreachedVertices, 0u);
  std::vector<double> values = computeIsoValues(kSpacing, c.maxDistance, c.start);
  if (c.start == IsoValueStart::InteriorCurve) values.erase(values.begin());  // k = 0 is the curve
  ASSERT_GE(values.size(), 3u);
  const CaseStats stats = measurePaths(field, values, c.trueDistance, c.surfaceDistance, kSpacing);
  std::cout << "[accurate] " << c.name << ": " << stats.levels << " levels, " << stats.paths
            << " paths, spacing error raw " << 100 * stats.spacingError << " %, fitted "
            << 100 * stats.fitSpacingError << " %, surface distance raw "
            << stats.rawSurfaceDistance << " mm, fitted " << stats.fitSurfaceDistance
            << " mm, unfoldings " << field.unfoldings << ", " << field.seconds << " s\n";
  EXPECT_GE(stats.levels, static_cast<int>(values.size()) - 1);
  EXPECT_LT(stats.spacingError, 0.01);
  EXPECT_LT(stats.fitSpacingError, 0.01);
  EXPECT_LT(stats.rawSurfaceDistance, 0.05);
  EXPECT_LT(stats.fitSurfaceDistance, 0.05);
  EXPECT_LE(stats.fitDeviation, 0.05);
}

TEST(SurfaceGeodesic, CylinderFromBottomCircle) {
  checkAccurate(cylinderCase());
}
TEST(SurfaceGeodesic, SphericalCapFromRim) {
  checkAccurate(sphericalCapCase());
}
TEST(SurfaceGeodesic, ConeFromBase) {
  checkAccurate(coneCase());
}
TEST(SurfaceGeodesic, PlaneFromLine) {
  const AnalyticCase c = planeCase();
  ASSERT_EQ(c.curve.size(), 1u);
  checkAccurate(c);
  // Paths lie on both sides of the line: two per level.
  const SurfaceGeodesicResult field = computeSurfaceGeodesic(c.mesh, c.curve);
  EXPECT_EQ(extractIsoLines(field.mesh, field.distance, kSpacing).size(), 2u);
}

TEST(SurfaceGeodesic, PaperMethodSpacingErrorIsReported) {
  SurfaceGeodesicOptions options;
  options.method = SurfaceGeodesicMethod::Paper;
  for (const AnalyticCase& c : {cylinderCase(), sphericalCapCase(), coneCase(), planeCase()}) {
    const SurfaceGeodesicResult field = computeSurfaceGeodesic(c.mesh, c.curve, options);
    std::vector<double> values = computeIsoValues(kSpacing, c.maxDistance, c.start);
    if (c.start == IsoValueStart::InteriorCurve) values.erase(values.begin());
    const CaseStats stats =
        measurePaths(field, values, c.trueDistance, c.surfaceDistance, kSpacing);
    std::cout << "[paper] " << c.name << ": search radius " << field.searchRadius
              << " mm, spacing error raw " << 100 * stats.spacingError << " %, fitted "
              << 100 * stats.fitSpacingError << " %\n";
    // Loose bound of its own: a stencil Dijkstra overestimates by up to a few percent.
    EXPECT_LT(stats.spacingError, 0.15) << c.name;
    EXPECT_LT(stats.rawSurfaceDistance, 0.05) << c.name;
  }
}

TEST(SurfaceGeodesic, ObliqueCurveIsInsertedNotSnapped) {
  // The line y = 0.37·x + 4 sampled every 2.9 mm: neither points nor segments follow the mesh.
  const TriMesh mesh = makeRectangleMesh(0.0, 40.0, 0.0, 30.0, 50, 40);
  Polyline line;
  for (double x = 0.0; x <= 40.0 + 1e-9; x += 40.0 / 14)
    line.points.emplace_back(x, 0.37 * x + 4, 0);
  const Vec3 n = Vec3(-0.37, 1, 0).normalized();
  const SurfaceGeodesicResult field = computeSurfaceGeodesic(mesh, {line});
  EXPECT_GT(field.insertedVertices, 50u);
  double onLine = 0.0, worst = 0.0;
  for (const std::int32_t v : field.curveVertices) {
    onLine = std::max(onLine, std::abs(n.dot(field.mesh.vertices[v] - Vec3(0, 4, 0))));
    EXPECT_EQ(field.distance[v], 0.0);
  }
  // The plane is convex: the geodesic distance is the Euclidean distance to the segment. The
  // front is straight except around the curve's end points (on the boundary), where it turns
  // into circles; fast marching is exact on the straight part and first-order next to the bend.
  std::size_t inexact = 0;
  for (std::size_t v = 0; v < field.mesh.vertexCount(); ++v) {
    const double error =
        std::abs(field.distance[v] - closestPointOnPolyline(line, field.mesh.vertices[v]).distance);
    worst = std::max(worst, error);
    if (error > 1e-6) ++inexact;
  }
  std::cout << "oblique line: largest error " << worst << " mm, " << inexact << " of "
            << field.mesh.vertexCount() << " vertices off by more than 1e-6 mm\n";
  EXPECT_LT(onLine, 1e-9);
  EXPECT_LT(worst, 0.1 * 0.8) << "within a tenth of the edge length";
  EXPECT_LT(inexact, field.mesh.vertexCount() / 10) << "exact where the front is straight";
  EXPECT_EQ(field.mesh.vertexCount(), mesh.vertexCount() + field.insertedVertices);
}

TEST(SurfaceGeodesic, CurveOffTheSurfaceIsRejected) {
  const TriMesh mesh = makeRectangleMesh(0.0, 10.0, 0.0, 10.0, 10, 10);
  Polyline line{{Vec3(1, 1, 0), Vec3(5, 5, 0.3)}, false};
  try {
    computeSurfaceGeodesic(mesh, {line});
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("0.3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not on the layer surface"), std::string::npos);
  }
  SurfaceGeodesicOptions loose;
  loose.curveTolerance = 0.5;
  EXPECT_NO_THROW(computeSurfaceGeodesic(mesh, {line}, loose));
}

TEST(SurfaceGeodesic, BadInputIsRejected) {
  const TriMesh mesh = makeRectangleMesh(0.0, 10.0, 0.0, 10.0, 4, 4);
  const Polyline line{{Vec3(1, 1, 0), Vec3(5, 5, 0)}, false};
  EXPECT_THROW(computeSurfaceGeodesic(TriMesh{}, {line}), InvalidInput);
  EXPECT_THROW(computeSurfaceGeodesic(mesh, {}), InvalidInput);
  SurfaceGeodesicOptions bad;
  bad.curveTolerance = -1.0;
  EXPECT_THROW(computeSurfaceGeodesic(mesh, {line}, bad), InvalidInput);
  bad = {};
  bad.maxDistance = 0.0;
  EXPECT_THROW(computeSurfaceGeodesic(mesh, {line}, bad), InvalidInput);
  EXPECT_THROW(computeSurfaceGeodesicFromVertices(mesh, {}), InvalidInput);
  EXPECT_THROW(computeSurfaceGeodesicFromVertices(mesh, {1000}), InvalidInput);
  EXPECT_THROW(computeSurfaceGeodesicFromVertices(mesh, {0, 1}, {0.0}), InvalidInput);
}

TEST(SurfaceGeodesic, MethodNamesRoundTrip) {
  for (SurfaceGeodesicMethod m : {SurfaceGeodesicMethod::Accurate, SurfaceGeodesicMethod::Paper}) {
    EXPECT_EQ(parseSurfaceGeodesicMethod(toString(m)), m);
  }
  EXPECT_EQ(toString(SurfaceGeodesicOptions{}.method), "accurate");
  try {
    parseSurfaceGeodesicMethod("exact");
    ADD_FAILURE();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()),
              "unknown surface geodesic method: 'exact'; choose accurate or paper");
  }
}

TEST(SurfaceGeodesic, FromVerticesAndMaxDistance) {
  const TriMesh mesh = makeRectangleMesh(0.0, 10.0, 0.0, 10.0, 10, 10);
  SurfaceGeodesicOptions options;
  options.maxDistance = 3.0;
  const SurfaceGeodesicResult field = computeSurfaceGeodesicFromVertices(mesh, {0}, {}, options);
  std::size_t reached = 0;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const double d = field.distance[v];
    if (std::isfinite(d)) {
      ++reached;
      EXPECT_LE(d, 3.0);
      EXPECT_NEAR(d, mesh.vertices[v].norm(), 0.15 * mesh.vertices[v].norm() + 1e-12);
    }
  }
  EXPECT_GT(reached, 5u);
  EXPECT_EQ(field.unreachedVertices, mesh.vertexCount() - reached);
}

TEST(SurfaceGeodesic, CancellationAndDeterminism) {
  const AnalyticCase c = sphericalCapCase();
  int calls = 0;
  Progress cancel([&](double, std::string_view) { return ++calls < 3; });
  EXPECT_THROW(computeSurfaceGeodesic(c.mesh, c.curve, {}, cancel), Cancelled);
  const SurfaceGeodesicResult a = computeSurfaceGeodesic(c.mesh, c.curve);
  const SurfaceGeodesicResult b = computeSurfaceGeodesic(c.mesh, c.curve);
  EXPECT_EQ(a.distance, b.distance);
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
}

}  // namespace
}  // namespace curvedslicer
