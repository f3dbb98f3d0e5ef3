// Corner fill (paths/corner_fill.hpp) on flat layers with closed forms: a rhombus whose outer
// ring covers everything but its four corner wedges, (w/2)²·(cot(θ/2) − (π − θ)/2) each, and
// after the dip only the two obtuse ones, with the bead's edge w/2·(1 − sin(θ/2)) past the
// boundary at the acute ones; a triangle
// with a 40° corner where the bound stops the dip; rounded rings that stay; the planner with the
// option on and off; bad input.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/corner_fill.hpp"
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/paths/planner.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;
using testing::kS;
constexpr double kH = 0.5 * kS;    // half a bead
constexpr double kSpacing = 0.05;  // coverage sample spacing, mm

/// Wedge void a round bead leaves in a corner of angle θ (radians) at half-width h.
double wedgeVoid(double theta, double h) {
  return h * h * (1.0 / std::tan(0.5 * theta) - 0.5 * (kPi - theta));
}

/// A convex polygon (counter-clockwise, z = 0) and its signed distance (positive inside).
struct ConvexPolygon {
  std::vector<Vec3> corners;

  double edgeDistance(const Vec3& p) const {
    double d = kInf;
    for (std::size_t i = 0; i < corners.size(); ++i) {
      const Vec3& a = corners[i];
      const Vec3& b = corners[(i + 1) % corners.size()];
      const Vec3 t = (b - a).normalized();
      const Vec3 inward(-t.y(), t.x(), 0.0);
      d = std::min(d, (p - a).dot(inward));
    }
    return d;
  }
  double angleAt(std::size_t i) const {
    const std::size_t n = corners.size();
    const Vec3 u = (corners[(i + n - 1) % n] - corners[i]).normalized();
    const Vec3 v = (corners[(i + 1) % n] - corners[i]).normalized();
    return std::acos(u.dot(v));
  }
  /// The polygon inset by h: each corner moved along its bisector by h / sin(θ/2).
  std::vector<Vec3> inset(double h) const {
    std::vector<Vec3> out;
    const std::size_t n = corners.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 u = (corners[(i + n - 1) % n] - corners[i]).normalized();
      const Vec3 v = (corners[(i + 1) % n] - corners[i]).normalized();
      out.push_back(corners[i] + (u + v).normalized() * (h / std::sin(0.5 * angleAt(i))));
    }
    return out;
  }
  /// A fan of triangles (coverage needs no connectivity).
  TriMesh mesh() const {
    TriMesh m;
    m.vertices = corners;
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
      m.triangles.push_back(Vec3i(0, static_cast<int>(i), static_cast<int>(i + 1)));
    }
    return m;
  }
  EdgeSampler sampler() const {
    return [this](const Vec3& p) {
      return EdgeSample{Vec3(p.x(), p.y(), 0.0), Vec3::UnitZ(), edgeDistance(p)};
    };
  }
};

/// A closed ring through `corners` with every side cut into pieces of at most `step` mm.
Polyline makeRing(const std::vector<Vec3>& corners, double step) {
  Polyline ring;
  ring.closed = true;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Vec3& a = corners[i];
    const Vec3& b = corners[(i + 1) % corners.size()];
    const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
    for (int k = 0; k < pieces; ++k) ring.points.push_back(a + (b - a) * (double(k) / pieces));
  }
  return ring;
}

ConvexPolygon makeRhombus(double side, double acuteDegrees) {
  const double a = acuteDegrees * kPi / 180.0;
  const Vec3 e1(side, 0, 0), e2(side * std::cos(a), side * std::sin(a), 0);
  return {{Vec3::Zero(), e1, e1 + e2, e2}};
}

double voidArea(const ConvexPolygon& poly, const Polyline& ring) {
  PlanPath path;
  path.closed = ring.closed;
  for (const Vec3& p : ring.points) {
    PathPoint q;
    q.position = p;
    path.points.push_back(q);
  }
  CoverageOptions o;
  o.sampleSpacing = kSpacing;
  const LayerCoverage c = computeLayerCoverage(poly.mesh(), {path}, kS, o);
  return c.voidShare * c.area;
}

TEST(CornerFill, RhombusCornersCoveredWithinBound) {
  // Side 7 mm, 70°: inradius 3.29 mm < w, so the ring at w/2 covers all but the corner wedges.
  const ConvexPolygon rhombus = makeRhombus(7.0, 70.0);
  Polyline ring = makeRing(rhombus.inset(kH), 0.5);
  std::vector<Vec3> normals(ring.points.size(), Vec3::UnitZ());
  std::vector<double> widths;
  const double wedges = 2.0 * wedgeVoid(70.0 * kPi / 180.0, kH) +
                        2.0 * wedgeVoid(110.0 * kPi / 180.0, kH);  // 3.36 mm² at 70°
  // Sampling error: the wedges' outline (two tangent lengths and an arc each) × spacing / 4.
  double outline = 0.0;
  for (const double deg : {70.0, 110.0, 70.0, 110.0}) {
    const double th = deg * kPi / 180.0;
    outline += 2.0 * kH / std::tan(0.5 * th) + kH * (kPi - th);
  }
  EXPECT_NEAR(voidArea(rhombus, ring), wedges, outline * kSpacing / 4.0);

  CornerFillOptions o;
  o.beadSpacing = kS;
  const CornerFillResult r = fillRingCorners({{&ring, &normals, &widths}}, rhombus.sampler(), o);
  EXPECT_EQ(r.corners, 2u);  // the two acute ones; the 110° corners keep their wedges
  EXPECT_EQ(normals.size(), ring.points.size());
  // The acute corners need the most: the bead reaches the tip, its edge h·(1 − sin 35°) out.
  const double over = kH * (1.0 - std::sin(35.0 * kPi / 180.0));
  EXPECT_NEAR(r.largestOverdeposit, over, 1e-9);
  EXPECT_LE(r.largestOverdeposit, 0.25 * kS);
  EXPECT_NEAR(r.largestDip, kH / std::sin(35.0 * kPi / 180.0) - kH, 1e-9);
  for (const Vec3& p : ring.points) EXPECT_GE(rhombus.edgeDistance(p), kH - over - 1e-9);
  const double obtuse = 2.0 * wedgeVoid(110.0 * kPi / 180.0, kH);
  EXPECT_NEAR(voidArea(rhombus, ring), obtuse, outline * kSpacing / 4.0);  // acute wedges gone
}

TEST(CornerFill, BoundStopsTheDipInASharpCorner) {
  // A triangle with a 40° corner: covering its tip would put the edge h·(1 − sin 20°) = 1.22 mm
  // out, more than the bound s/4 = 0.925 mm; the dip stops at the bound and leaves a smaller void.
  const double a = 40.0 * kPi / 180.0;
  // Isosceles, 14 mm legs: corners of 40°, 70°, 70°; inradius 3.35 mm < w (no void inside).
  const ConvexPolygon triangle{
      {Vec3::Zero(), Vec3(14.0, 0, 0), Vec3(14.0 * std::cos(a), 14.0 * std::sin(a), 0)}};
  Polyline ring = makeRing(triangle.inset(kH), 0.5);
  std::vector<Vec3> normals(ring.points.size(), Vec3::UnitZ());
  const double before = voidArea(triangle, ring);
  CornerFillOptions o;
  o.beadSpacing = kS;
  const CornerFillResult r = fillRingCorners({{&ring, &normals, nullptr}}, triangle.sampler(), o);
  EXPECT_EQ(r.corners, 3u);
  EXPECT_NEAR(r.largestOverdeposit, 0.25 * kS, 1e-9);
  EXPECT_NEAR(r.largestDip, 0.25 * kS / std::sin(0.5 * a), 1e-9);
  for (const Vec3& p : ring.points) EXPECT_GE(triangle.edgeDistance(p), kH - 0.25 * kS - 1e-9);
  const double after = voidArea(triangle, ring);
  EXPECT_LT(after,
            before - wedgeVoid(triangle.angleAt(1), kH) - wedgeVoid(triangle.angleAt(2), kH));
  EXPECT_GT(after, 0.1);  // the 40° tip beyond the bound stays
}

TEST(CornerFill, SmoothRingAndConcaveTurnsStay) {
  // A circle (no corner within s/4) stays; an L-shaped ring's inner (concave) corner stays.
  Polyline circle;
  circle.closed = true;
  for (int k = 0; k < 64; ++k) {
    circle.points.push_back(
        Vec3(10 * std::cos(2 * kPi * k / 64), 10 * std::sin(2 * kPi * k / 64), 0));
  }
  std::vector<Vec3> normals(circle.points.size(), Vec3::UnitZ());
  const EdgeSampler disc = [](const Vec3& p) {
    return EdgeSample{p, Vec3::UnitZ(), 10.0 + kH - p.norm()};
  };
  const Polyline copy = circle;
  EXPECT_EQ(fillRingCorners({{&circle, &normals, nullptr}}, disc).corners, 0u);
  EXPECT_EQ(circle.points, copy.points);
  // A turn whose outside leads away from the edge (the edge lies on its inside, as around a
  // reflex corner of the part): moving the point out would not bring it nearer the edge.
  Polyline bend;
  bend.points = {Vec3(-5, 0, 0), Vec3(0, 0, 0), Vec3(-3, 5, 0)};  // a 59° corner
  std::vector<Vec3> bendNormals(3, Vec3::UnitZ());
  const Vec3 outside = (Vec3(1, 0, 0) - Vec3(-3, 5, 0).normalized()).normalized();
  const EdgeSampler inside = [&](const Vec3& p) {
    return EdgeSample{p, Vec3::UnitZ(), kH + p.dot(outside)};
  };
  EXPECT_EQ(fillRingCorners({{&bend, &bendNormals, nullptr}}, inside).corners, 0u);
  EXPECT_EQ(bend.points.size(), 3u);
}

TEST(CornerFill, RejectsBadInput) {
  Polyline ring = makeRing(makeRhombus(7.0, 70.0).inset(kH), 0.5);
  std::vector<Vec3> normals(ring.points.size(), Vec3::UnitZ());
  const EdgeSampler flat = [](const Vec3& p) { return EdgeSample{p, Vec3::UnitZ(), kH}; };
  CornerFillOptions o;
  o.beadSpacing = 0.0;
  EXPECT_THROW(fillRingCorners({{&ring, &normals, nullptr}}, flat, o), InvalidInput);
  o = {};
  o.maxCornerAngle = 180.0;
  EXPECT_THROW(fillRingCorners({{&ring, &normals, nullptr}}, flat, o), InvalidInput);
  std::vector<Vec3> fewNormals(2, Vec3::UnitZ());
  EXPECT_THROW(fillRingCorners({{&ring, &fewNormals, nullptr}}, flat), InvalidInput);
  PlannerOptions p;
  p.cornerOverdeposit = std::nan("");
  EXPECT_THROW(validatePlannerOptions(p), InvalidInput);
}

/// A triangle subdivided into n² congruent triangles (indexed, z = height).
TriMesh makeTriangleLayer(const Vec3& a, const Vec3& b, const Vec3& c, int n, double height) {
  TriMesh m;
  auto index = [n](int i, int j) { return j * (n + 1) - j * (j - 1) / 2 + i; };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i + j <= n; ++i) {
      Vec3 p = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
      p.z() = height;
      m.vertices.push_back(p);
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i + j < n; ++i) {
      m.triangles.push_back(Vec3i(index(i, j), index(i + 1, j), index(i, j + 1)));
      if (i + j + 1 < n) {
        m.triangles.push_back(Vec3i(index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)));
      }
    }
  }
  return m;
}

TEST(CornerFill, PlannerDipsOuterRingIntoTriangleCorners) {
  // A 60° triangle of side 40 mm: three corners of 60°, each leaving 2.97 mm² with a plain ring;
  // 60° needs the bead's edge h·(1 − sin 30°) = s/4 out: just within the default bound.
  const double side = 40.0;
  const Vec3 a(0, 0, 0), b(side, 0, 0), c(0.5 * side, 0.5 * std::sqrt(3.0) * side, 0);
  LayerSurface layer;
  layer.index = 1;
  layer.level = 1.5;
  layer.mesh = makeTriangleLayer(a, b, c, 80, 1.5);
  PlannerOptions o;
  o.beadSpacing = kS;
  o.threads = 1;
  o.cornerFill = false;
  const PlanResult plain = planLayers({layer}, TriMesh{}, o);
  o.cornerFill = true;
  const PlanResult filled = planLayers({layer}, TriMesh{}, o);
  const LayerCoverage& before = plain.plan.layers[0].coverage;
  const LayerCoverage& after = filled.plan.layers[0].coverage;
  const double corners = 3.0 * wedgeVoid(kPi / 3.0, kH);
  EXPECT_LT(after.voidShare * after.area, before.voidShare * before.area - 0.8 * corners);
  // No point of the filled plan puts its bead's edge more than s/4 past the boundary.
  const ConvexPolygon tri{{a, b, c}};
  for (const PlanPath& path : filled.plan.layers[0].paths) {
    for (const PathPoint& p : path.points) {
      const double h = p.width > 0.0 ? 0.5 * p.width : kH;
      EXPECT_GE(tri.edgeDistance(p.position), h - 0.25 * kS - 0.01);
    }
  }
}

}  // namespace
}  // namespace curvedslicer
