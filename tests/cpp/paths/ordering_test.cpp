// Ordering within a layer: travel, open-path alternation, seam staggering between layers, bad
// input and determinism.
#include <cmath>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/ordering.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;

Polyline makeCircle(const Vec3& c, double r, int n, double phase = 0.0) {
  Polyline p;
  p.closed = true;
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2.0 * kPi * i / n;
    p.points.push_back(c + Vec3(r * std::cos(a), r * std::sin(a), 0.0));
  }
  return p;
}

Polyline makeLine(const Vec3& a, const Vec3& b, int n) {
  Polyline p;
  for (int i = 0; i < n; ++i) p.points.push_back(a + (b - a) * (static_cast<double>(i) / (n - 1)));
  return p;
}

TEST(Ordering, ParallelOpenPathsAlternateDirection) {
  // Six parallel lines 3 mm apart, given shuffled and all pointing the same way.
  std::vector<Polyline> lines;
  for (int k : {3, 0, 5, 1, 4, 2}) {
    lines.push_back(makeLine(Vec3(0, 3.0 * k, 0), Vec3(40, 3.0 * k, 0), 21));
  }
  const LayerOrder order = orderLayerPaths(lines, Vec3(0, -1, 0), {});
  ASSERT_EQ(order.paths.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(lines[order.paths[k].source].points[0].y(), 3.0 * k);  // bottom to top
    EXPECT_EQ(order.paths[k].reversed, k % 2 == 1);                  // boustrophedon
  }
  EXPECT_NEAR(order.travel, 1.0 + 5 * 3.0, 1e-9);
  EXPECT_EQ(order.end, Vec3(0, 15, 0));
}

TEST(Ordering, TwoOptRemovesCrossingTravel) {
  // Greedy from the origin visits the near cluster, then a far one, then comes back; 2-opt
  // must not make it worse and the result is a valid permutation.
  std::vector<Polyline> lines;
  for (double x : {0.0, 50.0, 2.0, 52.0, 4.0}) {
    lines.push_back(makeLine(Vec3(x, 0, 0), Vec3(x, 10, 0), 5));
  }
  OrderingOptions greedyOnly;
  greedyOnly.improvementPasses = 0;
  const LayerOrder greedy = orderLayerPaths(lines, Vec3(-1, 0, 0), {}, greedyOnly);
  const LayerOrder improved = orderLayerPaths(lines, Vec3(-1, 0, 0), {});
  EXPECT_LE(improved.travel, greedy.travel + 1e-9);
  std::vector<bool> seen(lines.size(), false);
  for (const OrderedPath& o : improved.paths) seen[o.source] = true;
  for (bool s : seen) EXPECT_TRUE(s);
}

TEST(Ordering, SeamsOfConsecutiveLayersAreApart) {
  // Ten layers of three concentric rings, 1.5 mm apart in z; s = 3.7 mm, separation 2·s.
  const double s = 3.7;
  OrderingOptions options;
  options.seamSeparation = 2.0 * s;
  std::vector<Vec3> previousSeams;
  std::optional<Vec3> torch;
  for (int layer = 0; layer < 10; ++layer) {
    std::vector<Polyline> rings;
    for (int k = 0; k < 3; ++k) {
      rings.push_back(makeCircle(Vec3(0, 0, 1.5 * layer), 30.0 - k * s, 120, 0.01 * layer));
    }
    const LayerOrder order = orderLayerPaths(rings, torch, previousSeams, options);
    EXPECT_EQ(order.seamsTooClose, 0u);
    for (const Vec3& seam : order.seams) {
      for (const Vec3& prev : previousSeams) EXPECT_GE((seam - prev).norm(), 2.0 * s);
    }
    // Closed rings stay closed and keep their direction: the seam is one of the ring's points.
    for (std::size_t i = 0; i < order.paths.size(); ++i) {
      const OrderedPath& o = order.paths[i];
      EXPECT_FALSE(o.reversed);
      EXPECT_EQ(order.seams[i], rings[o.source].points[o.seam]);
    }
    previousSeams = order.seams;
    torch = order.end;
  }
}

TEST(Ordering, ShortRingReportsSeamTooClose) {
  // A ring of radius 2 cannot keep 7.4 mm from a seam at its centre height.
  const std::vector<Polyline> rings = {makeCircle(Vec3::Zero(), 2.0, 24)};
  OrderingOptions options;
  options.seamSeparation = 7.4;
  const LayerOrder order = orderLayerPaths(rings, std::nullopt, {Vec3(2.0, 0, 0)}, options);
  EXPECT_EQ(order.seamsTooClose, 1u);
  EXPECT_TRUE(order.paths[0].seamTooClose);
  // The farthest point from the old seam is taken: the opposite side.
  EXPECT_NEAR(order.seams[0].x(), -2.0, 1e-12);
}

TEST(Ordering, ApplyOrderRotatesAndReverses) {
  const std::vector<int> v = {0, 1, 2, 3};
  OrderedPath o;
  o.seam = 2;
  EXPECT_EQ(applyOrder(v, true, o), (std::vector<int>{2, 3, 0, 1}));
  o.reversed = true;
  EXPECT_EQ(applyOrder(v, false, o), (std::vector<int>{3, 2, 1, 0}));
}

TEST(Ordering, RejectsPathWithTooFewPoints) {
  Polyline ring = makeCircle(Vec3::Zero(), 5.0, 2);
  try {
    orderLayerPaths({ring}, std::nullopt, {});
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("path 0 has 2 point(s): a closed path needs 3"),
              std::string::npos)
        << e.what();
  }
}

TEST(Ordering, EmptyLayerKeepsTorch) {
  const LayerOrder order = orderLayerPaths({}, Vec3(1, 2, 3), {});
  EXPECT_TRUE(order.paths.empty());
  EXPECT_EQ(order.end, Vec3(1, 2, 3));
}

TEST(Ordering, IsDeterministic) {
  std::vector<Polyline> paths;
  for (int k = 0; k < 8; ++k) {
    paths.push_back(makeCircle(Vec3(10.0 * (k % 3), 7.0 * (k / 3), 0), 2.0 + k % 2, 30));
    paths.push_back(makeLine(Vec3(k, 40, 0), Vec3(k, 50, 0), 6));
  }
  const LayerOrder a = orderLayerPaths(paths, Vec3::Zero(), {Vec3(1, 1, 0)}, {4.0, 4});
  const LayerOrder b = orderLayerPaths(paths, Vec3::Zero(), {Vec3(1, 1, 0)}, {4.0, 4});
  ASSERT_EQ(a.paths.size(), b.paths.size());
  for (std::size_t i = 0; i < a.paths.size(); ++i) {
    EXPECT_EQ(a.paths[i].source, b.paths[i].source);
    EXPECT_EQ(a.paths[i].seam, b.paths[i].seam);
    EXPECT_EQ(a.paths[i].reversed, b.paths[i].reversed);
  }
  EXPECT_EQ(a.travel, b.travel);
}

}  // namespace
}  // namespace curvedslicer
