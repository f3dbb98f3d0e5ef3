// Bead widening (paths/bead_widening.hpp): two straight beads facing each other across a
// strip narrower than a fill bead each grow into it on their facing side only, by half the
// strip; growth stops at the extension limit and the widest bead; slivers and short stretches
// are left; bad input is named. Through the planner: a
// thin wall whose width holds one ring of beads on each side and a strip narrower than s/2 in
// the middle (the turbine blades' case) is covered to within 1.5 % at fixed width.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "common/shapes.hpp"
#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/bead_widening.hpp"
#include "curvedslicer/paths/planner.hpp"

namespace curvedslicer {
namespace {

using testing::kS;

struct TwoBeads {
  TriMesh mesh;
  Polyline a, b;
  std::vector<Vec3> normalsA, normalsB;
};

/// A flat wall [0, width] × [0, 60] and two straight beads along y, s/2 in from each long edge.
TwoBeads makeWall(double width) {
  TwoBeads w;
  w.mesh = testing::makeFlatGrid(0.0, width, 0.0, 60.0, 0.0, static_cast<int>(width / 0.25), 240);
  for (int i = 0; i <= 60; ++i) {
    w.a.points.emplace_back(0.5 * kS, i, 0.0);
    w.b.points.emplace_back(width - 0.5 * kS, i, 0.0);
  }
  w.normalsA.assign(w.a.points.size(), Vec3(0, 0, 1));
  w.normalsB = w.normalsA;
  return w;
}

TEST(BeadWidening, FacingBeadsEachTakeHalfOfANarrowStrip) {
  // 8.6 mm wall: the beads cover 0–3.7 and 4.9–8.6; the strip between is 1.2 mm. Bead a runs
  // +y with normal +z, so its right side (+x) faces the strip; bead b's left side (−x) does.
  const TwoBeads w = makeWall(8.6);
  BeadWideningOptions o;
  o.beadSpacing = kS;
  const BeadWidening out =
      computeBeadWidening(w.mesh, {{&w.a, &w.normalsA, {}}, {&w.b, &w.normalsB, {}}}, {}, o);
  ASSERT_EQ(out.right.size(), 2u);
  ASSERT_EQ(out.right[0].size(), w.a.points.size());
  ASSERT_EQ(out.left[1].size(), w.b.points.size());
  const double margin = 0.5 * kS / 16.0;
  for (std::size_t i = 0; i < w.a.points.size(); ++i) {
    EXPECT_GE(out.right[0][i], 0.6 - 1e-9) << i;
    EXPECT_LE(out.right[0][i], 0.6 + margin + 1e-9) << i;
    EXPECT_EQ(out.left[0][i], 0.0) << i;
    EXPECT_GE(out.left[1][i], 0.6 - 1e-9) << i;
    EXPECT_LE(out.left[1][i], 0.6 + margin + 1e-9) << i;
    EXPECT_EQ(out.right[1][i], 0.0) << i;
  }
  EXPECT_EQ(out.widenedPoints, 2 * w.a.points.size());
  EXPECT_LE(out.largestWidth, kS + 0.6 + margin + 1e-9);
}

TEST(BeadWidening, GrowthStopsAtTheExtensionAndTheWidestBead) {
  // 9.4 mm wall: the strip is 2.0 mm wide. With 0.6 mm per side each bead takes only 0.6 of
  // its 1.0 mm half (the rest is narrowed, not closed); with 1.2 mm it takes the whole half;
  // the widest bead caps the growth.
  const TwoBeads w = makeWall(9.4);
  const std::vector<WidenableBead> both = {{&w.a, &w.normalsA, {}}, {&w.b, &w.normalsB, {}}};
  BeadWideningOptions o;
  o.beadSpacing = kS;
  o.maxExtension = 0.6;
  o.maxWidth = 2.0 * kS;
  const double margin = 0.5 * kS / 16.0;
  const BeadWidening part = computeBeadWidening(w.mesh, both, {}, o);
  ASSERT_EQ(part.right[0].size(), w.a.points.size());
  for (const double e : part.right[0]) {
    EXPECT_GE(e, 0.6 - 0.5 * margin);
    EXPECT_LE(e, 0.6 + margin + 1e-9);
  }
  o.maxExtension = 1.2;
  const BeadWidening taken = computeBeadWidening(w.mesh, both, {}, o);
  for (std::size_t i = 0; i < w.a.points.size(); ++i) {
    EXPECT_GE(taken.right[0][i], 1.0 - 1e-9) << i;
    EXPECT_LE(taken.right[0][i], 1.0 + margin + 1e-9) << i;
    EXPECT_EQ(taken.left[0][i], 0.0) << i;
  }
  o.maxWidth = kS + 0.2;
  const BeadWidening capped = computeBeadWidening(w.mesh, both, {}, o);
  for (std::size_t i = 0; i < w.a.points.size(); ++i) {
    EXPECT_NEAR(capped.left[0][i] + capped.right[0][i], 0.2, 1e-9) << i;
  }
  EXPECT_LE(capped.largestWidth, kS + 0.2 + 1e-9);
}

TEST(BeadWidening, SliversAndShortStretchesAreLeft) {
  // 7.6 mm wall: a 0.2 mm sliver (< s/10) between the beads stays; an 8.6 mm wall whose beads
  // are only 3 mm long (< s) keeps them as they are.
  const TwoBeads sliver = makeWall(7.6);
  EXPECT_EQ(computeBeadWidening(
                sliver.mesh, {{&sliver.a, &sliver.normalsA, {}}, {&sliver.b, &sliver.normalsB, {}}})
                .widenedPoints,
            0u);
  TwoBeads w = makeWall(8.6);
  w.a.points.resize(4);
  w.b.points.resize(4);
  w.normalsA.resize(4);
  w.normalsB.resize(4);
  EXPECT_EQ(
      computeBeadWidening(w.mesh, {{&w.a, &w.normalsA, {}}, {&w.b, &w.normalsB, {}}}).widenedPoints,
      0u);
}

TEST(BeadWidening, CoveredLayerIsLeftAlone) {
  // 7.4 mm wall: the two beads meet on the middle line; nothing to widen.
  const TwoBeads w = makeWall(7.4);
  const BeadWidening out =
      computeBeadWidening(w.mesh, {{&w.a, &w.normalsA, {}}, {&w.b, &w.normalsB, {}}});
  EXPECT_EQ(out.widenedPoints, 0u);
}

TEST(BeadWidening, RejectsBadInputNamingIt) {
  const TwoBeads w = makeWall(8.6);
  const std::vector<Vec3> tooFew(3, Vec3(0, 0, 1));
  EXPECT_THROW(computeBeadWidening(w.mesh, {{&w.a, &tooFew, {}}}), InvalidInput);
  BeadWideningOptions o;
  o.beadSpacing = 0.0;
  EXPECT_THROW(computeBeadWidening(w.mesh, {}, {}, o), InvalidInput);
  o.beadSpacing = kS;
  o.maxWidth = std::nan("");
  EXPECT_THROW(computeBeadWidening(w.mesh, {}, {}, o), InvalidInput);
}

TEST(BeadWidening, ThinWallsAreCoveredByThePlanner) {
  // Walls 7.8–9.0 mm wide hold one ring on each side and leave a strip 0.4–1.6 mm wide, under
  // the gap fill's minimum s/2: without widening it stays void (5.4 % of the layer at 7.8 mm, 16 %
  // at 9 mm; measured 0.01–0.02 % with it).
  for (double width = 7.8; width <= 9.01; width += 0.4) {
    LayerSurface layer;
    layer.index = 1;
    layer.mesh = testing::makeFlatGrid(0.0, 60.0, 0.0, width, 0.0, 120,
                                       static_cast<int>(std::lround(width / 0.5)));
    PlannerOptions options;
    options.narrowStrips = NarrowStripMode::Overlap;
    const PlanResult result = planLayers({layer}, TriMesh{}, options);
    ASSERT_EQ(result.plan.layers.size(), 1u);
    const LayerCoverage& c = result.plan.layers[0].coverage;
    EXPECT_LE(c.voidShare, 0.015) << "width " << width;
    EXPECT_LE(c.overlapShare, 0.10) << "width " << width;
    options.fillGaps = false;
    const PlanResult off = planLayers({layer}, TriMesh{}, options);
    EXPECT_GT(off.plan.layers[0].coverage.voidShare, c.voidShare) << "width " << width;
  }
}

}  // namespace
}  // namespace curvedslicer
