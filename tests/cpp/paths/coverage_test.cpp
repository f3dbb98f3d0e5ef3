// Layer coverage (paths/coverage.hpp) against closed forms on a flat plate: a square ring (void =
// inner square + the rounded outer corners), two parallel beads (overlap = strip + lens), a
// hairpin turn of one path (overlap where the legs are more than a bead width apart along the
// path), a right-angle turn (no overlap), a spot deposit (a disc), the closing segment of a ring,
// per-point widths, the void patches, determinism and bad input.
//
// Sampling error: a sample stands for its sub-triangle, so an area bounded by a curve of length P
// is measured within P·h/2 (h the sample spacing) in the worst case; the tests use h = 0.05 mm and
// allow P·h/4 (the boundaries cross the sample lattice at general angles, so errors average out).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/coverage.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;
constexpr double kSpacing = 0.05;  // mm, sample spacing of the tests

/// The plate [x0, x1] × [y0, y1] at z = 0, two triangles.
TriMesh makePlate(double x0, double y0, double x1, double y1) {
  TriMesh m;
  m.vertices = {Vec3(x0, y0, 0), Vec3(x1, y0, 0), Vec3(x1, y1, 0), Vec3(x0, y1, 0)};
  m.triangles = {Vec3i(0, 1, 2), Vec3i(0, 2, 3)};
  return m;
}

PlanPath makePath(const std::vector<Vec3>& points, bool closed, double width = 0.0) {
  PlanPath p;
  p.closed = closed;
  for (const Vec3& q : points) {
    PathPoint pp;
    pp.position = q;
    pp.width = width;
    p.points.push_back(pp);
  }
  return p;
}

/// A square ring of side `side` centred at (cx, cy), corners only.
PlanPath makeSquareRing(double cx, double cy, double side, bool closed = true) {
  const double h = 0.5 * side;
  return makePath({Vec3(cx - h, cy - h, 0), Vec3(cx + h, cy - h, 0), Vec3(cx + h, cy + h, 0),
                   Vec3(cx - h, cy + h, 0)},
                  closed);
}

/// Area of the lens of two discs of radius r whose centres are d apart.
double lensArea(double r, double d) {
  return 2.0 * r * r * std::acos(d / (2.0 * r)) - 0.5 * d * std::sqrt(4.0 * r * r - d * d);
}

CoverageOptions fine() {
  CoverageOptions o;
  o.sampleSpacing = kSpacing;
  return o;
}

TEST(Coverage, SquareRingLeavesInnerSquareAndRoundedCornersVoid) {
  // Plate 40 × 40, s = 4, one ring at s/2 from the edge: it covers the band [0, 4] from the edge
  // except the four outer corners, where its edge is a quarter circle of radius 2.
  const TriMesh plate = makePlate(0, 0, 40, 40);
  const LayerCoverage c = computeLayerCoverage(plate, {makeSquareRing(20, 20, 36)}, 4.0, fine());
  const double r = 2.0;
  const double corners = 4.0 * r * r * (1.0 - kPi / 4.0);
  const double expectedVoid = 32.0 * 32.0 + corners;
  const double perimeter = 4.0 * 32.0 + 2.0 * kPi * r;
  EXPECT_TRUE(c.measured);
  EXPECT_NEAR(c.area, 1600.0, 1e-6);  // a sum of 2.6 million sample areas
  EXPECT_NEAR(c.voidShare * c.area, expectedVoid, perimeter * kSpacing / 4.0);
  EXPECT_NEAR(c.overlapShare * c.area, 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(c.beadWidth, 4.0);
  EXPECT_EQ(c.arcStarts, 1u);
  // Five patches: the inner square and the four corners, the square first.
  ASSERT_EQ(c.voids.size(), 5u);
  EXPECT_NEAR(c.voids[0].area, 1024.0, 4.0 * 32.0 * kSpacing / 4.0);
  EXPECT_NEAR((c.voids[0].centre - Vec3(20, 20, 0)).norm(), 0.0, kSpacing);
  EXPECT_NEAR(c.voids[0].size, 32.0 * std::sqrt(2.0), 2.0 * kSpacing);
  for (std::size_t k = 1; k < 5; ++k) {
    EXPECT_NEAR(c.voids[k].area, corners / 4.0, 2.0 * r * kSpacing);
  }
}

TEST(Coverage, ClosingSegmentOfARingCounts) {
  const TriMesh plate = makePlate(0, 0, 40, 40);
  const LayerCoverage closed =
      computeLayerCoverage(plate, {makeSquareRing(20, 20, 36, true)}, 4.0, fine());
  const LayerCoverage open =
      computeLayerCoverage(plate, {makeSquareRing(20, 20, 36, false)}, 4.0, fine());
  // The open ring misses its last side x = 2, y ∈ [2, 38]: of the band [0, 4] × [2, 38] the
  // neighbouring sides and the end discs still cover 4 + π at each end.
  const double missing = 36.0 * 4.0 - 2.0 * (4.0 + kPi);
  EXPECT_NEAR((open.voidShare - closed.voidShare) * 1600.0, missing, 36.0 * 2.0 * kSpacing / 4.0);
}

TEST(Coverage, TwoParallelBeadsOverlapInAStripAndTwoHalfLenses) {
  // Beads of width 4 along x over [0, 30], 3 mm apart: overlap = 30 × 1 strip + one full lens
  // (half at each end).
  const TriMesh plate = makePlate(-10, -10, 40, 15);
  const LayerCoverage c = computeLayerCoverage(plate,
                                               {makePath({Vec3(0, 0, 0), Vec3(30, 0, 0)}, false),
                                                makePath({Vec3(0, 3, 0), Vec3(30, 3, 0)}, false)},
                                               4.0, fine());
  const double overlap = 30.0 + lensArea(2.0, 3.0);
  const double stadium = 30.0 * 4.0 + kPi * 4.0;
  const double perimeter = 2.0 * 30.0 + 2.0 * kPi * 2.0;
  EXPECT_NEAR(c.overlapShare * c.area, overlap, perimeter * kSpacing / 4.0);
  EXPECT_NEAR(c.voidShare * c.area, c.area - (2.0 * stadium - overlap),
              2.0 * (60.0 + 4.0 * kPi) * kSpacing / 4.0);
  EXPECT_EQ(c.arcStarts, 2u);
}

TEST(Coverage, HairpinOverlapsWhereItsLegsAreMoreThanABeadApartAlongThePath) {
  // One path: (0,0) → (20,0) → (20,2.5) → (0,2.5), width 4. A point of the band y ∈ [0.5, 2] at x
  // is covered by leg 1 at arc x and leg 2 at arc 42.5 − x: overlap while 42.5 − 2x > 4, i.e.
  // x < 19.25; for x < 0 the two end discs overlap in half a lens (arcs 0 and 42.5).
  const TriMesh plate = makePlate(-10, -10, 30, 15);
  const PlanPath hairpin =
      makePath({Vec3(0, 0, 0), Vec3(20, 0, 0), Vec3(20, 2.5, 0), Vec3(0, 2.5, 0)}, false);
  const LayerCoverage c = computeLayerCoverage(plate, {hairpin}, 4.0, fine());
  const double overlap = 19.25 * 1.5 + 0.5 * lensArea(2.0, 2.5);
  EXPECT_NEAR(c.overlapShare * c.area, overlap, (2.0 * 19.25 + 2.0 * 1.5 + kPi) * kSpacing / 4.0);
  EXPECT_EQ(c.arcStarts, 1u);
}

TEST(Coverage, RightAngleTurnDoesNotOverlapItself) {
  // Inside the corner the two legs' hits are at most one bead width apart along the path.
  const TriMesh plate = makePlate(-10, -10, 30, 30);
  const LayerCoverage c = computeLayerCoverage(
      plate, {makePath({Vec3(0, 0, 0), Vec3(20, 0, 0), Vec3(20, 20, 0)}, false)}, 4.0, fine());
  EXPECT_NEAR(c.overlapShare * c.area, 0.0, 0.01);
  // Covered: two 20 × 4 rectangles, the outer quarter disc at the corner less the inner 2 × 2
  // square counted twice, the two end half discs.
  const double covered = 2.0 * 80.0 - 4.0 + kPi * 4.0 / 4.0 + kPi * 4.0;
  EXPECT_NEAR((1.0 - c.voidShare) * c.area, covered, (80.0 + 3.0 * kPi) * kSpacing / 4.0);
}

TEST(Coverage, SpotCoversADiscOfItsWidth) {
  const TriMesh plate = makePlate(0, 0, 20, 20);
  PlanPath spot = makePath({Vec3(10, 10, 0)}, false, 3.0);
  spot.dwell = 1.5;
  const LayerCoverage c = computeLayerCoverage(plate, {spot}, 4.0, fine());
  EXPECT_NEAR((1.0 - c.voidShare) * c.area, kPi * 1.5 * 1.5, 2.0 * kPi * 1.5 * kSpacing / 4.0);
  ASSERT_EQ(c.voids.size(), 1u);  // the plate around the disc is one patch
}

TEST(Coverage, PerPointWidthIsInterpolatedAlongTheSegment) {
  // Width 2 at x = 0 to 6 at x = 30: a trapezoid of area 30 · 4 plus the end half discs.
  const TriMesh plate = makePlate(-10, -10, 40, 10);
  PlanPath bead = makePath({Vec3(0, 0, 0), Vec3(30, 0, 0)}, false);
  bead.points[0].width = 2.0;
  bead.points[1].width = 6.0;
  const LayerCoverage c = computeLayerCoverage(plate, {bead}, 3.7, fine());
  // A point (x, y) with x ∈ [0, 30] is covered when |y| ≤ w(x)/2 = 1 + x/15 (the trapezoid);
  // beyond the ends, by the end discs of radius 1 and 3.
  const double covered = 30.0 * 4.0 + 0.5 * kPi * 1.0 + 0.5 * kPi * 9.0;
  EXPECT_NEAR((1.0 - c.voidShare) * c.area, covered, (60.0 + 4.0 * kPi) * kSpacing / 4.0);
}

TEST(Coverage, NoPathsLeaveTheWholeLayerVoid) {
  const LayerCoverage c = computeLayerCoverage(makePlate(0, 0, 10, 10), {}, 3.7);
  EXPECT_TRUE(c.measured);
  EXPECT_DOUBLE_EQ(c.voidShare, 1.0);
  EXPECT_EQ(c.arcStarts, 0u);
  ASSERT_EQ(c.voids.size(), 1u);
  EXPECT_NEAR(c.voids[0].area, 100.0, 1e-6);
}

TEST(Coverage, ListsAtMostMaxVoidsLargestFirst) {
  CoverageOptions o = fine();
  o.maxVoids = 2;
  const LayerCoverage c =
      computeLayerCoverage(makePlate(0, 0, 40, 40), {makeSquareRing(20, 20, 36)}, 4.0, o);
  ASSERT_EQ(c.voids.size(), 2u);
  EXPECT_GT(c.voids[0].area, c.voids[1].area);
}

TEST(Coverage, IsDeterministic) {
  const TriMesh plate = makePlate(0, 0, 40, 40);
  const std::vector<PlanPath> paths = {makeSquareRing(20, 20, 36), makeSquareRing(20, 20, 28)};
  const LayerCoverage a = computeLayerCoverage(plate, paths, 4.0);
  const LayerCoverage b = computeLayerCoverage(plate, paths, 4.0);
  EXPECT_EQ(a.voidShare, b.voidShare);
  EXPECT_EQ(a.overlapShare, b.overlapShare);
  ASSERT_EQ(a.voids.size(), b.voids.size());
  for (std::size_t k = 0; k < a.voids.size(); ++k) EXPECT_EQ(a.voids[k].area, b.voids[k].area);
}

TEST(Coverage, DoesNotDependOnTheThreadCount) {
  const TriMesh plate = makePlate(0, 0, 40, 40);
  const std::vector<PlanPath> paths = {makeSquareRing(20, 20, 36), makeSquareRing(20, 20, 29)};
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const LayerCoverage one = computeLayerCoverage(plate, paths, 4.0, fine());
  omp_set_num_threads(3);
  const LayerCoverage three = computeLayerCoverage(plate, paths, 4.0, fine());
  omp_set_num_threads(threads);
  EXPECT_EQ(one.area, three.area);
  EXPECT_EQ(one.voidShare, three.voidShare);
  EXPECT_EQ(one.overlapShare, three.overlapShare);
  EXPECT_GT(one.overlapShare, 0.0);  // the rings are 3.5 mm apart: 0.5 mm of overlap
  ASSERT_EQ(one.voids.size(), three.voids.size());
  for (std::size_t k = 0; k < one.voids.size(); ++k) {
    EXPECT_EQ(one.voids[k].centre, three.voids[k].centre);
  }
}

TEST(Coverage, ThreadsOptionDoesNotChangeTheResult) {
  const TriMesh plate = makePlate(0, 0, 40, 40);
  const std::vector<PlanPath> paths = {makeSquareRing(20, 20, 36), makeSquareRing(20, 20, 29)};
  CoverageOptions o = fine();
  o.threads = 1;
  const LayerCoverage one = computeLayerCoverage(plate, paths, 4.0, o);
  o.threads = 3;
  const LayerCoverage three = computeLayerCoverage(plate, paths, 4.0, o);
  EXPECT_EQ(one.area, three.area);
  EXPECT_EQ(one.voidShare, three.voidShare);
  EXPECT_EQ(one.overlapShare, three.overlapShare);
  EXPECT_GT(one.overlapShare, 0.0);
  ASSERT_EQ(one.voids.size(), three.voids.size());
  for (std::size_t k = 0; k < one.voids.size(); ++k) {
    EXPECT_EQ(one.voids[k].centre, three.voids[k].centre);
  }
}

TEST(Coverage, RejectsBadInput) {
  const TriMesh plate = makePlate(0, 0, 10, 10);
  EXPECT_THROW(computeLayerCoverage(plate, {}, 0.0), InvalidInput);
  EXPECT_THROW(computeLayerCoverage(plate, {}, std::nan("")), InvalidInput);
  CoverageOptions o;
  o.sampleSpacing = 0.0;
  EXPECT_THROW(computeLayerCoverage(plate, {}, 3.7, o), InvalidInput);
  CoverageOptions negative;
  negative.threads = -1;
  EXPECT_THROW(computeLayerCoverage(plate, {}, 3.7, negative), InvalidInput);
  EXPECT_THROW(
      computeLayerCoverage(plate, {makePath({Vec3(1, 1, 0), Vec3(5, 1, 0)}, false, -1.0)}, 3.7),
      InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
