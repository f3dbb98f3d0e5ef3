// Smoothing B-spline fit and resampling of raw paths.
#include "curvedslicer/paths/path_fit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "common/raw_paths.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

/// A raw circle polyline (chords of a circle of radius r) with a small deterministic zigzag.
Polyline rawCircle(double r, int n, double zigzag) {
  Polyline p;
  p.closed = true;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    const double rr = r + (i % 2 ? zigzag : -zigzag);
    p.points.emplace_back(rr * std::cos(a), rr * std::sin(a), 0.1 * std::sin(3 * a));
  }
  return p;
}

/// Dense samples of a fitted spline over u in [0, 1) as a closed polyline: `samples` uniform
/// parameters and every knot (so the polyline has the corners, where the spline is only C0).
Polyline sampleClosedSpline(const BSplineCurve& spline, int samples) {
  std::vector<double> u;
  for (int i = 0; i < samples; ++i) u.push_back(double(i) / samples);
  if (!spline.closed) {
    for (const double k : spline.knots) {
      if (k < 1.0) u.push_back(k);
    }
  }
  std::sort(u.begin(), u.end());
  u.erase(std::unique(u.begin(), u.end()), u.end());
  Polyline dense;
  dense.closed = true;
  for (const double x : u) dense.points.push_back(spline.evaluate(x));
  return dense;
}

/// Largest distance from the segments between consecutive resampled points to the spline,
/// measured independently of fitPath's own bookkeeping.
double measureChordError(const PathFitResult& fit) {
  // Dense spline samples as a reference polyline.
  Polyline dense;
  dense.closed = fit.spline.closed;
  const int n = 20000;
  for (int i = 0; i < (dense.closed ? n : n + 1); ++i)
    dense.points.push_back(fit.spline.evaluate(double(i) / n));
  return computeOneSidedHausdorff(dense, fit.points, 1);
}

TEST(PathFit, ClosedCircleStaysClosedWithinTolerance) {
  const Polyline raw = rawCircle(20.0, 300, 0.01);
  const PathFitResult fit = fitPath(raw);
  EXPECT_TRUE(fit.spline.closed);
  EXPECT_TRUE(fit.points.closed);
  EXPECT_LE(fit.fitDeviation, 0.05);
  // Independent check both ways against the raw line.
  Polyline dense;
  dense.closed = true;
  for (int i = 0; i < 5000; ++i) dense.points.push_back(fit.spline.evaluate(i / 5000.0));
  EXPECT_LE(computeOneSidedHausdorff(raw, dense, 1), 0.05 + 1e-3);
  EXPECT_LE(computeOneSidedHausdorff(dense, raw, 1), 0.05 + 1e-3);
  // C² closure: the spline at 0 and at 1 coincide, and so do the derivatives.
  EXPECT_LT((fit.spline.evaluate(0.0) - fit.spline.evaluate(1.0)).norm(), 1e-12);
  EXPECT_LT((fit.spline.derivative(0.0) - fit.spline.derivative(1.0 - 1e-12)).norm(), 1e-6);
  // Resampled at most 2 mm apart (closing segment included), chord error within tolerance.
  for (std::size_t i = 0; i < fit.points.segmentCount(); ++i) {
    EXPECT_LE((fit.points.segmentEnd(i) - fit.points.segmentStart(i)).norm(), 2.0 + 1e-9);
  }
  EXPECT_LE(fit.chordError, 0.05);
  EXPECT_LE(measureChordError(fit), 0.05 + 1e-4);
  // The zigzag is smoothed out: points lie on the radius-20 circle (± the z wave).
  for (const Vec3& p : fit.points.points) EXPECT_NEAR(std::hypot(p.x(), p.y()), 20.0, 0.02);
}

TEST(PathFit, OpenCurveKeepsItsEndPoints) {
  Polyline raw;
  for (int i = 0; i <= 200; ++i) {
    const double x = 0.25 * i;
    raw.points.emplace_back(x, 3.0 * std::sin(x / 6.0), 0.0);
  }
  PathFitOptions options;
  options.tolerance = 0.02;
  options.pointSpacing = 1.5;
  options.chordTolerance = 0.01;
  const PathFitResult fit = fitPath(raw, options);
  EXPECT_FALSE(fit.points.closed);
  EXPECT_EQ(fit.points.points.front(), raw.points.front());
  EXPECT_EQ(fit.points.points.back(), raw.points.back());
  EXPECT_LE(fit.fitDeviation, 0.02);
  EXPECT_LE(fit.chordError, 0.01);
  EXPECT_LE(measureChordError(fit), 0.01 + 1e-4);
  for (std::size_t i = 0; i < fit.points.segmentCount(); ++i) {
    EXPECT_LE((fit.points.segmentEnd(i) - fit.points.segmentStart(i)).norm(), 1.5 + 1e-9);
  }
  // Derivative agrees with a finite difference.
  const double u = 0.37, h = 1e-6;
  const Vec3 fd = (fit.spline.evaluate(u + h) - fit.spline.evaluate(u - h)) / (2 * h);
  EXPECT_LT((fd - fit.spline.derivative(u)).norm(), 1e-4 * fd.norm());
}

TEST(PathFit, SharpCornerIsKeptExactly) {
  // An L-shaped raw path: split at the corner, two straight pieces that one round each fits; the
  // corner is a point of the path. Without corner detection the single spline needs more rounds.
  Polyline raw;
  for (int i = 0; i <= 40; ++i) raw.points.emplace_back(0.25 * i, 0.0, 0.0);
  for (int i = 1; i <= 40; ++i) raw.points.emplace_back(10.0, 0.25 * i, 0.0);
  const PathFitResult fit = fitPath(raw);
  EXPECT_LE(fit.fitDeviation, 0.05);
  EXPECT_EQ(fit.fitRounds, 2);
  ASSERT_EQ(fit.corners.size(), 1u);
  EXPECT_EQ(fit.points.points[fit.corners[0]], Vec3(10.0, 0.0, 0.0));
  EXPECT_EQ(fit.points.points.front(), raw.points.front());
  EXPECT_EQ(fit.points.points.back(), raw.points.back());
  EXPECT_LT((fit.spline.evaluate(0.5) - Vec3(10.0, 0.0, 0.0)).norm(), 1e-12);
  PathFitOptions noCorners;
  noCorners.cornerAngle = 180.0;
  const PathFitResult single = fitPath(raw, noCorners);
  EXPECT_TRUE(single.corners.empty());
  EXPECT_LE(single.fitDeviation, 0.05);
  EXPECT_GT(single.fitRounds, 1);
  EXPECT_GT(single.spline.controlPoints.size(), 4 * fit.spline.controlPoints.size());
}

TEST(PathFit, RingWithCornersKeepsThemWithinTolerance) {
  // A 245 mm iso-line-like ring, 0.1 mm raw spacing, four 53° corners: each corner is a point of
  // the path, the fit is within the tolerance both ways everywhere (independent measure), and
  // the four smooth pieces need one round each (one uniform spline ends with > 4× the control
  // points).
  std::vector<Vec3> corners;
  const Polyline raw = testing::makeBulgedSquareRing(60.0, 5.0, 0.1, 0.0, corners);
  const PathFitResult fit = fitPath(raw);
  EXPECT_TRUE(fit.points.closed);
  EXPECT_FALSE(fit.spline.closed);
  ASSERT_EQ(fit.corners.size(), 4u);
  for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(fit.points.points[fit.corners[c]], corners[c]);
  EXPECT_LE(fit.fitRounds, 4 * 2);
  PathFitOptions noCorners;
  noCorners.cornerAngle = 180.0;
  const PathFitResult single = fitPath(raw, noCorners);
  EXPECT_TRUE(single.corners.empty());
  EXPECT_GT(single.fitRounds, fit.fitRounds / 4);
  EXPECT_GT(single.spline.controlPoints.size(), 4 * fit.spline.controlPoints.size());
  EXPECT_LE(fit.fitDeviation, 0.05);
  const Polyline dense = sampleClosedSpline(fit.spline, 4000);
  EXPECT_LT((fit.spline.evaluate(0.0) - fit.spline.evaluate(1.0)).norm(), 1e-12);
  const double rawToSpline = computeOneSidedHausdorff(raw, dense, 0);
  const double splineToRaw = computeOneSidedHausdorff(dense, raw, 0);
  EXPECT_LE(rawToSpline, 0.05 + 1e-3);
  EXPECT_LE(splineToRaw, 0.05 + 1e-3);
  EXPECT_NEAR(fit.fitDeviation, std::max(rawToSpline, splineToRaw), 2e-3);
  // Resampled path: spacing, chord error (independent) and no self-intersection.
  for (std::size_t i = 0; i < fit.points.segmentCount(); ++i) {
    EXPECT_LE((fit.points.segmentEnd(i) - fit.points.segmentStart(i)).norm(), 2.0 + 1e-9);
  }
  EXPECT_LE(fit.chordError, 0.05);
  EXPECT_LE(computeOneSidedHausdorff(dense, fit.points, 0), 0.05 + 1e-3);
  EXPECT_LE(computeOneSidedHausdorff(fit.points, raw, 4), 0.05 + 0.05 + 1e-9);
  EXPECT_FALSE(hasSelfIntersection(fit.points, 1e-6));
  // Same corners starting the ring elsewhere (rotation of the raw vertices).
  Polyline rotated = raw;
  std::rotate(rotated.points.begin(), rotated.points.begin() + 377, rotated.points.end());
  const PathFitResult again = fitPath(rotated);
  ASSERT_EQ(again.corners.size(), 4u);
  EXPECT_EQ(again.points.points[again.corners[0]], corners[1]);
  EXPECT_LE(again.fitDeviation, 0.05);
}

TEST(PathFit, MicroSegmentsAreHarmless) {
  // The same ring with a 0.5 µm segment every tenth raw point: merged before fitting, so the fit
  // takes the same rounds, stays within the tolerance of every raw vertex, and the path has no
  // sub-micrometre segment.
  std::vector<Vec3> corners;
  const Polyline clean = testing::makeBulgedSquareRing(60.0, 5.0, 0.1, 0.0, corners);
  const Polyline raw = testing::makeBulgedSquareRing(60.0, 5.0, 0.1, 5e-4, corners);
  ASSERT_GT(raw.points.size(), clean.points.size() + 200);
  const PathFitResult reference = fitPath(clean);
  const PathFitResult fit = fitPath(raw);
  EXPECT_EQ(fit.fitRounds, reference.fitRounds);
  EXPECT_LE(fit.fitDeviation, 0.05);
  ASSERT_EQ(fit.corners.size(), 4u);
  for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(fit.points.points[fit.corners[c]], corners[c]);
  const Polyline dense = sampleClosedSpline(fit.spline, 4000);
  EXPECT_LE(computeOneSidedHausdorff(raw, dense, 0), 0.05 + 1e-3);
  double shortest = kInf;
  for (std::size_t i = 0; i < fit.points.segmentCount(); ++i)
    shortest = std::min(shortest, (fit.points.segmentEnd(i) - fit.points.segmentStart(i)).norm());
  EXPECT_GT(shortest, 1e-3);
  // An open line made only of micro-segments at one end still keeps its exact end points.
  Polyline open;
  for (int i = 0; i <= 100; ++i) open.points.emplace_back(0.2 * i, 0.01 * i * i * 0.04, 0.0);
  open.points.emplace_back(20.0 + 1e-4, 4.0, 0.0);
  const PathFitResult openFit = fitPath(open);
  EXPECT_EQ(openFit.points.points.front(), open.points.front());
  EXPECT_EQ(openFit.points.points.back(), open.points.back());
  EXPECT_LE(openFit.fitDeviation, 0.05);
}

TEST(PathFit, FollowsNoiseLargerThanTheTolerance) {
  // A ±0.08 mm zigzag cannot be smoothed away within 0.05 mm. By default it turns by more than
  // the corner angle at every other raw point, so the path keeps those points; without corners
  // the single spline has to interpolate and then densify. Either way the deviation it reports
  // must match an independent two-sided measurement.
  const Polyline raw = rawCircle(4.0, 200, 0.08);
  for (const double cornerAngle : {30.0, 180.0}) {
    PathFitOptions options;
    options.cornerAngle = cornerAngle;
    const PathFitResult fit = fitPath(raw, options);
    EXPECT_TRUE(fit.points.closed);
    EXPECT_LE(fit.fitDeviation, 0.05);
    if (cornerAngle < 180.0) {
      EXPECT_FALSE(fit.corners.empty());
    } else {
      EXPECT_TRUE(fit.corners.empty());
      EXPECT_GT(fit.fitRounds, 1);
    }
    const Polyline dense =
        sampleClosedSpline(fit.spline, 16 * static_cast<int>(fit.spline.controlPoints.size()));
    const double rawToSpline = computeOneSidedHausdorff(raw, dense, 0);
    const double splineToRaw = computeOneSidedHausdorff(dense, raw, 0);
    EXPECT_LE(rawToSpline, 0.05 + 1e-3);
    EXPECT_LE(splineToRaw, 0.05 + 1e-3);
    EXPECT_NEAR(fit.fitDeviation, std::max(rawToSpline, splineToRaw), 2e-3);
  }
}

TEST(PathFit, UnevenSamplingDeviationMatchesIndependentMeasure) {
  // Raw points bunched at one end of each side of a square (segments from 4e-4 mm to 1 mm): the
  // reported deviation must be the two-sided distance measured independently, with the corners
  // kept (four straight pieces) and as one spline.
  Polyline raw;
  raw.closed = true;
  const Vec3 corners[4] = {Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(10, 10, 0), Vec3(0, 10, 0)};
  for (int c = 0; c < 4; ++c) {
    for (int i = 0; i < 30; ++i) {
      const double t = std::pow(i / 30.0, 3.0);
      raw.points.push_back(corners[c] + (corners[(c + 1) % 4] - corners[c]) * t);
    }
  }
  for (const double cornerAngle : {30.0, 180.0}) {
    PathFitOptions options;
    options.cornerAngle = cornerAngle;
    const PathFitResult fit = fitPath(raw, options);
    EXPECT_EQ(fit.corners.size(), cornerAngle < 180.0 ? 4u : 0u);
    const Polyline dense =
        sampleClosedSpline(fit.spline, 16 * static_cast<int>(fit.spline.controlPoints.size()));
    const double measured =
        std::max(computeOneSidedHausdorff(raw, dense, 0), computeOneSidedHausdorff(dense, raw, 0));
    EXPECT_LE(fit.fitDeviation, 0.05);
    EXPECT_NEAR(fit.fitDeviation, measured, 2e-3);
  }
}

TEST(PathFit, ResamplePolyline) {
  const Polyline square{{Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(4, 4, 0), Vec3(0, 4, 0)}, true};
  const Polyline r = resamplePolyline(square, 1.5);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.points.size(), 11u);  // ceil(16 / 1.5) = 11 segments
  for (const Vec3& p : r.points) EXPECT_LT(closestPointOnPolyline(square, p).distance, 1e-12);
  for (std::size_t i = 0; i < r.segmentCount(); ++i) {
    EXPECT_LE((r.segmentEnd(i) - r.segmentStart(i)).norm(), 1.5 + 1e-12);
  }
  EXPECT_THROW(resamplePolyline(square, 0.0), InvalidInput);
}

TEST(PathFit, BadInput) {
  const Polyline raw = rawCircle(5.0, 50, 0.0);
  PathFitOptions bad;
  bad.tolerance = 0.0;
  EXPECT_THROW(fitPath(raw, bad), InvalidInput);
  bad = {};
  bad.pointSpacing = -2.0;
  EXPECT_THROW(fitPath(raw, bad), InvalidInput);
  bad = {};
  bad.smoothing = -1.0;
  EXPECT_THROW(fitPath(raw, bad), InvalidInput);
  bad = {};
  bad.cornerAngle = 0.0;
  EXPECT_THROW(fitPath(raw, bad), InvalidInput);
  EXPECT_THROW(fitPath(Polyline{{Vec3::Zero()}, false}), InvalidInput);
  EXPECT_THROW(fitPath(Polyline{{Vec3::Zero(), Vec3::UnitX()}, true}), InvalidInput);
  EXPECT_THROW(fitPath(Polyline{{Vec3::Zero(), Vec3::Zero()}, false}), InvalidInput);
}

TEST(PathFit, Deterministic) {
  const Polyline raw = rawCircle(8.0, 120, 0.02);
  const PathFitResult a = fitPath(raw), b = fitPath(raw);
  EXPECT_EQ(a.points.points, b.points.points);
  std::vector<Vec3> corners;
  const Polyline ring = testing::makeBulgedSquareRing(40.0, 3.0, 0.1, 5e-4, corners);
  const PathFitResult c = fitPath(ring), d = fitPath(ring);
  EXPECT_EQ(c.points.points, d.points.points);
  EXPECT_EQ(c.corners, d.corners);
}

}  // namespace
}  // namespace curvedslicer
