// Contour-parallel paths from a layer's boundary (issue 3 acceptance): a rectangular layer and a
// layer with a hole. No self-intersection, neighbouring paths never closer than 0.95·s, the strip
// between the outermost path and the boundary at most s/2 + fit tolerance, fits within tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "curvedslicer/paths/iso_lines.hpp"
#include "curvedslicer/paths/path_fit.hpp"
#include "curvedslicer/paths/surface_curves.hpp"
#include "curvedslicer/paths/surface_geodesic.hpp"
#include "paths/revolution_meshes.hpp"

namespace curvedslicer {
namespace {

using testing::makeRectangleMesh;
using testing::makeRevolutionMesh;
using testing::Profile;

struct Level {
  double value;
  std::vector<Polyline> raw, fitted;
};

void checkContourParallel(const TriMesh& layer, double s, const std::string& name) {
  SCOPED_TRACE(name);
  const PathFitOptions fitOptions;  // 0.05 mm, 2 mm
  const std::vector<Polyline> boundary = extractBoundaryLoops(layer);
  ASSERT_FALSE(boundary.empty());
  const SurfaceGeodesicResult field = computeSurfaceGeodesic(layer, boundary);
  double maxDistance = 0.0;
  for (const double d : field.distance) maxDistance = std::max(maxDistance, d);
  std::vector<Level> levels;
  for (const double value : computeIsoValues(s, maxDistance, IsoValueStart::Boundary)) {
    Level level{value, extractIsoLines(field.mesh, field.distance, value), {}};
    for (const Polyline& raw : level.raw) {
      const PathFitResult fit = fitPath(raw, fitOptions);
      EXPECT_LE(fit.fitDeviation, fitOptions.tolerance);
      EXPECT_LE(fit.chordError, fitOptions.tolerance);
      // Independent check: resampled path within fit + chord tolerance of the raw iso-line.
      EXPECT_LE(computeOneSidedHausdorff(fit.points, raw, 4),
                fitOptions.tolerance + fitOptions.tolerance + 1e-9);
      EXPECT_EQ(fit.points.closed, raw.closed);
      level.fitted.push_back(fit.points);
    }
    if (!level.fitted.empty()) levels.push_back(std::move(level));
  }
  ASSERT_GE(levels.size(), 3u);
  int paths = 0;
  double closest = kInf, widestStrip = 0.0, narrowestStrip = kInf;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    for (std::size_t i = 0; i < levels[k].fitted.size(); ++i) {
      const Polyline& path = levels[k].fitted[i];
      ++paths;
      EXPECT_FALSE(hasSelfIntersection(path, 1e-6)) << "level " << k << " path " << i;
      // Same level, other paths.
      for (std::size_t j = i + 1; j < levels[k].fitted.size(); ++j) {
        closest = std::min(closest, computePolylineDistance(path, levels[k].fitted[j]));
      }
      // Next level.
      if (k + 1 < levels.size()) {
        for (const Polyline& next : levels[k + 1].fitted) {
          closest = std::min(closest, computePolylineDistance(path, next));
        }
      }
    }
  }
  // Strip: every point of the outermost paths to the nearest boundary.
  for (const Polyline& path : levels[0].fitted) {
    for (const Vec3& p : path.points) {
      double d = kInf;
      for (const Polyline& b : boundary) d = std::min(d, closestPointOnPolyline(b, p).distance);
      widestStrip = std::max(widestStrip, d);
      narrowestStrip = std::min(narrowestStrip, d);
    }
  }
  std::cout << name << ": " << levels.size() << " levels, " << paths
            << " paths, closest neighbours " << closest << " mm (s = " << s << "), strip "
            << narrowestStrip << " .. " << widestStrip << " mm\n";
  EXPECT_GE(closest, 0.95 * s);
  EXPECT_LE(widestStrip, s / 2 + fitOptions.tolerance);
  EXPECT_GE(narrowestStrip, s / 2 - fitOptions.tolerance);
}

TEST(ContourPaths, RectangularLayer) {
  checkContourParallel(makeRectangleMesh(0, 60, 0, 40, 120, 80), 3.7, "rectangle 60 x 40");
}

TEST(ContourPaths, LayerWithHole) {
  // A round plate with a concentric hole, 6 bead spacings wide: the paths from the rim and from
  // the hole meet at the middle.
  const double s = 3.7, ri = 8.0, ro = ri + 6 * s;
  Profile annulus{[](double t) { return t; }, [](double) { return 0.0; }, ri, ro,
                  static_cast<int>(std::lround((ro - ri) / 0.5))};
  checkContourParallel(makeRevolutionMesh(annulus, 0.5), s, "plate with a hole");
}

}  // namespace
}  // namespace curvedslicer
