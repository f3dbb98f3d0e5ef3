// Smoothing B-spline fit and resampling of raw paths.
#include "curvedslicer/paths/path_fit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

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

TEST(PathFit, SharpCornerNeedsMoreControlPoints) {
  // An L-shaped raw path: the fit must still follow the corner within the tolerance.
  Polyline raw;
  for (int i = 0; i <= 40; ++i) raw.points.emplace_back(0.25 * i, 0.0, 0.0);
  for (int i = 1; i <= 40; ++i) raw.points.emplace_back(10.0, 0.25 * i, 0.0);
  const PathFitResult fit = fitPath(raw);
  EXPECT_LE(fit.fitDeviation, 0.05);
  EXPECT_GT(fit.fitRounds, 1);
}

TEST(PathFit, FollowsNoiseLargerThanTheTolerance) {
  // A ±0.08 mm zigzag cannot be smoothed away within 0.05 mm: the fit has to interpolate and then
  // densify, and the deviation it reports must match an independent two-sided measurement.
  const Polyline raw = rawCircle(4.0, 200, 0.08);
  const PathFitResult fit = fitPath(raw);
  EXPECT_TRUE(fit.points.closed);
  EXPECT_LE(fit.fitDeviation, 0.05);
  EXPECT_GT(fit.fitRounds, 1);
  Polyline dense;
  dense.closed = true;
  const int samples = 16 * static_cast<int>(fit.spline.controlPoints.size());
  for (int i = 0; i < samples; ++i)
    dense.points.push_back(fit.spline.evaluate(double(i) / samples));
  const double rawToSpline = computeOneSidedHausdorff(raw, dense, 0);
  const double splineToRaw = computeOneSidedHausdorff(dense, raw, 0);
  EXPECT_LE(rawToSpline, 0.05 + 1e-3);
  EXPECT_LE(splineToRaw, 0.05 + 1e-3);
  EXPECT_NEAR(fit.fitDeviation, std::max(rawToSpline, splineToRaw), 2e-3);
}

TEST(PathFit, UnevenSamplingDeviationMatchesIndependentMeasure) {
  // Raw points bunched at one end of each side of a square (segments from 4e-4 mm to 1 mm): the
  // reported deviation must be the two-sided distance measured independently.
  Polyline raw;
  raw.closed = true;
  const Vec3 corners[4] = {Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(10, 10, 0), Vec3(0, 10, 0)};
  for (int c = 0; c < 4; ++c) {
    for (int i = 0; i < 30; ++i) {
      const double t = std::pow(i / 30.0, 3.0);
      raw.points.push_back(corners[c] + (corners[(c + 1) % 4] - corners[c]) * t);
    }
  }
  const PathFitResult fit = fitPath(raw);
  Polyline dense;
  dense.closed = true;
  const int samples = 16 * static_cast<int>(fit.spline.controlPoints.size());
  for (int i = 0; i < samples; ++i)
    dense.points.push_back(fit.spline.evaluate(double(i) / samples));
  const double measured =
      std::max(computeOneSidedHausdorff(raw, dense, 0), computeOneSidedHausdorff(dense, raw, 0));
  EXPECT_LE(fit.fitDeviation, 0.05);
  EXPECT_NEAR(fit.fitDeviation, measured, 2e-3);
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
  EXPECT_THROW(fitPath(Polyline{{Vec3::Zero()}, false}), InvalidInput);
  EXPECT_THROW(fitPath(Polyline{{Vec3::Zero(), Vec3::UnitX()}, true}), InvalidInput);
  EXPECT_THROW(fitPath(Polyline{{Vec3::Zero(), Vec3::Zero()}, false}), InvalidInput);
}

TEST(PathFit, Deterministic) {
  const Polyline raw = rawCircle(8.0, 120, 0.02);
  const PathFitResult a = fitPath(raw), b = fitPath(raw);
  EXPECT_EQ(a.points.points, b.points.points);
}

}  // namespace
}  // namespace curvedslicer
