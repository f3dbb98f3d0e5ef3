// Connected insets (paths/connected_insets.hpp): concentric rings on a plane become one path whose
// ring parts are the rings' own points and whose links are short, on the surface and clear of the
// other paths; a level gap, a blocking path or a long step-over keeps rings apart; bad input; the
// planner with the option on and off (same beads, fewer arc starts, seams still staggered).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <tuple>
#include <vector>

#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/connected_insets.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "paths/joined_paths.hpp"
#include "paths/revolution_meshes.hpp"

namespace curvedslicer {
namespace {

using testing::kS;

/// A ring of radius r about (cx, cy) in the plane z = 0, `n` points, starting at angle `a0`.
PlanPath makeCircle(double r, int n, double a0 = 0.0, double cx = 0.0, double cy = 0.0) {
  PlanPath path;
  path.closed = true;
  for (int i = 0; i < n; ++i) {
    const double a = a0 + 2.0 * std::numbers::pi * i / n;
    PathPoint p;
    p.position = Vec3(cx + r * std::cos(a), cy + r * std::sin(a), 0.0);
    path.points.push_back(p);
  }
  path.length = 2.0 * std::numbers::pi * r;
  return path;
}

PlanPath makeSegment(const Vec3& a, const Vec3& b) {
  PlanPath path;
  for (const Vec3& p : {a, b}) {
    PathPoint q;
    q.position = p;
    path.points.push_back(q);
  }
  return path;
}

/// The plane z = 0: projection drops z, normal +z.
SurfacePoint projectOntoPlane(const Vec3& p) {
  return {Vec3(p.x(), p.y(), 0.0), Vec3::UnitZ()};
}

std::set<std::tuple<double, double, double>> pointSet(const std::vector<Vec3>& points) {
  std::set<std::tuple<double, double, double>> out;
  for (const Vec3& p : points) out.emplace(p.x(), p.y(), p.z());
  return out;
}

TEST(ConnectedInsets, ConcentricRingsBecomeOnePathWithShortLinks) {
  // Rings at 1.85, 5.55, 9.25 mm inward from a circle of radius 30 (levels 0, 1, 2).
  std::vector<PlanPath> paths = {makeCircle(30 - 1.85, 180), makeCircle(30 - 5.55, 150, 0.3),
                                 makeCircle(30 - 9.25, 120, 0.1)};
  const std::vector<PlanPath> rings = paths;
  const ConnectedInsetResult r = connectInsets(paths, {0, 1, 2}, projectOntoPlane);
  EXPECT_EQ(r.arcStartsBefore, 3u);
  EXPECT_EQ(r.arcStartsAfter, 1u);
  EXPECT_EQ(r.links, 2u);
  EXPECT_EQ(r.seams.size(), 3u);
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_FALSE(paths[0].closed);
  // The seam stays the outer ring's.
  EXPECT_EQ(paths[0].points.front().position, rings[0].points.front().position);
  const testing::SplitBeads split = testing::splitLayerBeads(paths);
  ASSERT_EQ(split.rings, 3u);
  ASSERT_EQ(split.links.size(), 2u);
  for (std::size_t k = 0; k < 3; ++k) {
    std::vector<Vec3> original;
    for (const PathPoint& p : rings[k].points) original.push_back(p.position);
    EXPECT_EQ(pointSet(split.beads[k].points), pointSet(original)) << "ring " << k;
    EXPECT_EQ(split.beads[k].points.size(), original.size());
  }
  double arc = 0.0;
  for (const Polyline& b : split.beads) arc += b.length();
  for (const testing::LinkPart& link : split.links) {
    const double length = link.line.length();
    arc += length;
    EXPECT_LE(length, 1.5 * kS);
    EXPECT_NEAR(length, kS, 0.2);  // across the strip, not along it
    for (const Vec3& p : link.line.points) EXPECT_EQ(p.z(), 0.0);
    EXPECT_GE(link.line.points.size(), 3u);  // at most pointSpacing (2 mm) apart
  }
  EXPECT_NEAR(paths[0].length, arc, 1e-9);
}

TEST(ConnectedInsets, OnlyConsecutiveLevelsJoin) {
  std::vector<PlanPath> paths = {makeCircle(28, 120), makeCircle(24.3, 100)};
  connectInsets(paths, {0, 2}, projectOntoPlane);
  EXPECT_EQ(paths.size(), 2u);
  std::vector<PlanPath> open = {makeCircle(28, 120), makeSegment(Vec3(0, 0, 0), Vec3(5, 0, 0))};
  connectInsets(open, {0, 1}, projectOntoPlane);  // an open path is never a ring part
  EXPECT_EQ(open.size(), 2u);
  std::vector<PlanPath> unmarked = {makeCircle(28, 120), makeCircle(24.3, 100)};
  connectInsets(unmarked, {0, -1}, projectOntoPlane);
  EXPECT_EQ(unmarked.size(), 2u);
}

TEST(ConnectedInsets, BlockedOrLongStepOverKeepsRingsApart) {
  // A short bead across the strip at the seam (angle 0): the link would cross it.
  std::vector<PlanPath> blocked = {makeCircle(28, 120), makeCircle(24.3, 100),
                                   makeSegment(Vec3(25.5, -2, 0), Vec3(25.5, 2, 0))};
  const ConnectedInsetResult r = connectInsets(blocked, {0, 1, -1}, projectOntoPlane);
  EXPECT_EQ(r.links, 0u);
  EXPECT_GE(r.rejectedLinks, 1u);
  EXPECT_EQ(blocked.size(), 3u);
  // Rings 2·s apart: the step-over would be longer than 1.5·s.
  std::vector<PlanPath> wide = {makeCircle(28, 120), makeCircle(28 - 2 * kS, 100)};
  EXPECT_EQ(connectInsets(wide, {0, 1}, projectOntoPlane).links, 0u);
  ConnectedInsetOptions longer;
  longer.maxLinkLength = 2.5 * kS;
  EXPECT_EQ(connectInsets(wide, {0, 1}, projectOntoPlane, longer).links, 1u);
  // A surface that is not under the chord (a gap deeper than s/4): no link.
  std::vector<PlanPath> gap = {makeCircle(28, 120), makeCircle(24.3, 100)};
  const SurfaceProjection away = [](const Vec3& p) {
    return SurfacePoint{Vec3(p.x(), p.y(), -2.0), Vec3::UnitZ()};
  };
  EXPECT_EQ(connectInsets(gap, {0, 1}, away).links, 0u);
}

TEST(ConnectedInsets, SplitJoinedPathFindsRingPartsAndLinks) {
  std::vector<PlanPath> paths = {makeCircle(28, 60), makeCircle(24.3, 50, 0.05)};
  connectInsets(paths, {0, 1}, projectOntoPlane);
  ASSERT_EQ(paths.size(), 1u);
  const std::vector<JoinedPathPart> parts = splitJoinedPath(paths[0]);
  ASSERT_EQ(parts.size(), 3u);
  EXPECT_TRUE(parts[0].ring);
  EXPECT_EQ(parts[0].first, 0u);
  EXPECT_EQ(parts[0].last, 60u);  // 60 points and the first again
  EXPECT_FALSE(parts[1].ring);    // the link shares its ends with the rings
  EXPECT_EQ(parts[1].first, 60u);
  EXPECT_EQ(parts[2].first, parts[1].last);
  EXPECT_TRUE(parts[2].ring);
  EXPECT_EQ(parts[2].last - parts[2].first, 50u);
  EXPECT_EQ(parts[2].last + 1, paths[0].points.size());
  // A closed ring: one ring part; an open piece: one non-ring part.
  const std::vector<JoinedPathPart> ring = splitJoinedPath(makeCircle(10, 20));
  ASSERT_EQ(ring.size(), 1u);
  EXPECT_TRUE(ring[0].ring);
  EXPECT_EQ(ring[0].last, 19u);
  const std::vector<JoinedPathPart> open =
      splitJoinedPath(makeSegment(Vec3(0, 0, 0), Vec3(5, 0, 0)));
  ASSERT_EQ(open.size(), 1u);
  EXPECT_FALSE(open[0].ring);
  EXPECT_EQ(open[0].last, 1u);
}

TEST(ConnectedInsets, BadInput) {
  std::vector<PlanPath> paths = {makeCircle(28, 120)};
  EXPECT_THROW(connectInsets(paths, {0, 1}, projectOntoPlane), InvalidInput);
  ConnectedInsetOptions bad;
  bad.beadSpacing = 0.0;
  EXPECT_THROW(connectInsets(paths, {0}, projectOntoPlane, bad), InvalidInput);
  bad.beadSpacing = kS;
  bad.pointSpacing = -1.0;
  EXPECT_THROW(connectInsets(paths, {0}, projectOntoPlane, bad), InvalidInput);
}

TEST(ConnectedInsets, PlannerJoinsTheSameBeadsAndStaggersSeams) {
  // An annulus (r 8 … 31, flat) in five layers: rings from the rim inward and from the hole
  // outward. With the option on, the same beads (point for point) in fewer paths, the links
  // on the layer and clear of other beads, each arc start 2·s from the previous layer's starts.
  std::vector<LayerSurface> layers;
  for (int k = 1; k <= 5; ++k) {
    testing::Profile annulus;
    annulus.radius = [](double t) { return 8.0 + 23.0 * t; };
    annulus.height = [k](double) { return 1.5 * k; };
    annulus.rings = 46;
    LayerSurface layer;
    layer.index = k;
    layer.level = 1.5 * k;
    layer.mesh = testing::makeRevolutionMesh(annulus, 0.5);
    layers.push_back(std::move(layer));
  }
  PlannerOptions off;
  off.connectInsets = false;
  const PlanResult separate = planLayers(layers, {}, off);
  const PlanResult joined = planLayers(layers, {}, PlannerOptions{});
  EXPECT_EQ(separate.stats.insetLinks, 0u);
  EXPECT_GT(joined.stats.insetLinks, 0u);
  std::size_t before = 0, after = 0;
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const std::vector<PlanPath>& a = separate.plan.layers[l].paths;
    const std::vector<PlanPath>& b = joined.plan.layers[l].paths;
    before += a.size();
    after += b.size();
    const testing::SplitBeads split = testing::splitLayerBeads(b);
    ASSERT_EQ(split.beads.size(), a.size()) << "layer " << l;
    // Ring parts are rings of the unjoined plan (seams may differ: compare point sets).
    std::set<std::tuple<double, double, double>> all, allJoined;
    for (const PlanPath& p : a) {
      for (const PathPoint& q : p.points)
        all.emplace(q.position.x(), q.position.y(), q.position.z());
    }
    for (const Polyline& p : split.beads) {
      for (const Vec3& q : p.points) allJoined.emplace(q.x(), q.y(), q.z());
    }
    EXPECT_EQ(all, allJoined) << "layer " << l;
    for (const testing::LinkPart& link : split.links) {
      EXPECT_LE(link.line.length(), 1.5 * kS + 1e-9);
      for (const Vec3& q : link.line.points) {
        EXPECT_NEAR(q.z(), 1.5 * (l + 1), off.fitTolerance);
        const double r = std::hypot(q.x(), q.y());
        EXPECT_GE(r, 8.0 + 0.5 * kS - off.fitTolerance);
        EXPECT_LE(r, 31.0 - 0.5 * kS + off.fitTolerance);
        for (std::size_t i = 0; i < split.beads.size(); ++i) {
          if (i == link.before || i == link.after) continue;
          EXPECT_GE(closestPointOnPolyline(split.beads[i], q).distance, 0.5 * kS);
        }
      }
    }
    if (l == 0) continue;
    const testing::SplitBeads previous = testing::splitLayerBeads(joined.plan.layers[l - 1].paths);
    for (const PlanPath& p : b) {
      for (const Polyline& prev : previous.beads) {
        EXPECT_GE((p.points.front().position - prev.points.front()).norm(), 2.0 * kS)
            << "layer " << l;
      }
    }
  }
  // 23 mm wide: 6 rings per layer (3 from each side), joined into two paths (the innermost
  // rings of the two sides are of one level).
  EXPECT_EQ(before, 30u);
  EXPECT_LE(after, 10u);
  EXPECT_EQ(joined.stats.seamsTooClose, 0u);
  // Deterministic.
  const PlanResult again = planLayers(layers, {}, PlannerOptions{});
  for (std::size_t l = 0; l < layers.size(); ++l) {
    ASSERT_EQ(again.plan.layers[l].paths.size(), joined.plan.layers[l].paths.size());
    for (std::size_t i = 0; i < joined.plan.layers[l].paths.size(); ++i) {
      const auto& x = joined.plan.layers[l].paths[i].points;
      const auto& y = again.plan.layers[l].paths[i].points;
      ASSERT_EQ(x.size(), y.size());
      for (std::size_t j = 0; j < x.size(); ++j) EXPECT_EQ(x[j].position, y[j].position);
    }
  }
}

}  // namespace
}  // namespace curvedslicer
