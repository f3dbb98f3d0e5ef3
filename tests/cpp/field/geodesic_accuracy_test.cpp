// Accuracy of the geodesic field against closed forms (ACCURACY.md), in units of the voxel size L,
// on grids with at least 128 cells along the longest side.
#include <gtest/gtest.h>

#include <cstdio>

#include "common/analytic_cases.hpp"
#include "curvedslicer/field/geodesic_field.hpp"

namespace curvedslicer {
namespace {

using testing::AnalyticCase;
using testing::FieldError;

FieldError run(const AnalyticCase& c, GeodesicMethod method, GeodesicResult* result = nullptr) {
  GeodesicOptions options;
  options.method = method;
  GeodesicResult local;
  GeodesicResult& r = result ? *result : local;
  r = computeGeodesicField(c.grid, c.model, c.source, options);
  const FieldError e = testing::measureFieldError(c, r.field);
  std::printf(
      "[ %-9s ] %-16s cells %dx%dx%d, %zu voxels: mean %.4f L, max %.4f L (at %.2f %.2f "
      "%.2f), max overestimate %.4f L, LOS failures %zu, edge pivots %zu\n",
      std::string(toString(method)).c_str(), c.name.c_str(), c.grid.geometry.dims.x(),
      c.grid.geometry.dims.y(), c.grid.geometry.dims.z(), e.voxels, e.mean, e.max, e.worst.x(),
      e.worst.y(), e.worst.z(), e.maxOver, r.lineOfSightFailures, r.edgePivots);
  EXPECT_EQ(e.unreached, 0u) << c.name;
  EXPECT_GE(c.grid.geometry.dims.maxCoeff(), 128) << c.name;
  return e;
}

TEST(GeodesicAccuracy, TiltedSlab) {
  const auto c = testing::makeTiltedSlabCase();
  const FieldError e = run(c, GeodesicMethod::AnyAngle);
  EXPECT_LE(e.mean, 0.02);
  EXPECT_LE(e.max, 0.25);
}

TEST(GeodesicAccuracy, SphericalShell) {
  const auto c = testing::makeSphericalShellCase();
  const FieldError e = run(c, GeodesicMethod::AnyAngle);
  EXPECT_LE(e.mean, 0.02);
  EXPECT_LE(e.max, 0.25);
}

TEST(GeodesicAccuracy, LShapeAroundReentrantEdge) {
  const auto c = testing::makeLShapeCase();
  const FieldError e = run(c, GeodesicMethod::AnyAngle);
  EXPECT_LE(e.mean, 0.05);
  EXPECT_LE(e.max, 0.4);
}

TEST(GeodesicAccuracy, UBendFromEndFace) {
  const auto c = testing::makeUBendCase();
  const FieldError e = run(c, GeodesicMethod::AnyAngle);
  EXPECT_LE(e.mean, 0.35);
  EXPECT_LE(e.max, 1.2);
}

// Not an issue tolerance: a regression guard. Shortest paths bend only at the two reflex edges,
// where the pivots sit exactly, so the field is exact up to rounding; what it guards:
//  - the line-of-sight inheritance (docs/METHODS.md), which verifies most cells of a model with
//    few reflex edges without a segment test: a cell wrongly taken as seeing the end face behind
//    a shadow would be off by many L;
//  - the neighbour-centre fallback of a repair: on this grid the segment between two cell
//    centres next to the reflex edge at (W, W) cuts its corner, which once made the whole base
//    and upper arm up to 0.27 L too short.
TEST(GeodesicAccuracy, UChannelAroundTwoReentrantEdges) {
  const auto c = testing::makeUChannelCase();
  GeodesicResult r;
  const FieldError e = run(c, GeodesicMethod::AnyAngle, &r);
  EXPECT_LE(e.mean, 0.01);
  EXPECT_LE(e.max, 0.05);
  // Few reflex edges: the segment tests are a small fraction of the voxels.
  EXPECT_LT(r.lineOfSightTests, e.voxels / 10);
}

// The paper's method is printed on the same cases and held only to its own bound: the search
// sphere's worst angular gap overestimates by up to 2.9 %, plus about one voxel.
TEST(GeodesicAccuracy, PaperMethodWithinItsOwnBound) {
  for (const auto& c : {testing::makeTiltedSlabCase(), testing::makeSphericalShellCase(),
                        testing::makeLShapeCase(), testing::makeUBendCase()}) {
    const FieldError e = run(c, GeodesicMethod::Paper);
    EXPECT_LE(e.maxRelativeOver, 0.029) << c.name;
  }
}

}  // namespace
}  // namespace curvedslicer
