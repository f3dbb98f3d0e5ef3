// Path fitting (paper §3.1: "piecewise polynomial is used to fit path curves"): a smoothing cubic
// B-spline within a tolerance of a raw iso-line, resampled at a robot point spacing with bounded
// chord error.
//
// Method: raw vertices closer than tolerance / 50 to the previous kept vertex are merged (they stay
// in the raw line the deviation is measured against). The line is then split at its corners: kept
// vertices where the chords to the points 4 × tolerance of arc length before and after turn by more
// than `cornerAngle`, the sharpest such vertex within that arc on either side. Each piece between
// corners (and an open line's end points) is fitted as an open clamped spline whose end points are
// the corner vertices, so the path keeps every corner exactly (C0 there, like the raw line); a
// closed line without corners is one periodic spline (closed and C²). A piece is a cubic B-spline
// with uniform knots, parameterised by chord length, fitted by penalised least squares, minimising
// Σ|C(u_i) − p_i|² + λ·Σ|Δ²P_j|² (second differences of the control points, λ = `smoothing` × the
// data scale). The number of control points starts at length / (8·pointSpacing) + 4 and grows by
// the ratio deviation / tolerance (at least by half, at most 4×) until the fit is within
// `tolerance` both ways (every raw vertex to the spline, every spline sample to the raw polyline);
// at the fitted point count the penalty is dropped (interpolation). A piece with fewer than 4 kept
// points, or that not even the densified interpolation fits within the tolerance, is kept as the
// polyline of its kept vertices. Every piece is measured against its own part of the raw line,
// which together make up the raw line, so the largest piece deviation bounds the path's two-sided
// deviation. Each piece is then resampled at equal arc length with at most `pointSpacing` between
// points, and every interval whose chord leaves the spline by more than `chordTolerance` is halved
// until none does; the pieces share their corner points.
//
// The deviation of a round is exact for the spline's dense samples (16 per span, ≥ 4 per raw
// point): every distance is first bounded by the few segments around its parameter; only the
// distances that could raise the running maximum are measured exactly (brute force for the first
// few, then through a uniform hash grid of the segments).
//
// Why corners: with uniform knots, following one corner within the tolerance needs a knot spacing
// of about a millimetre that the whole piece then gets; split there, a smooth piece needs few
// rounds.
//
// Preconditions: ≥ 2 raw points (closed: ≥ 3), finite. Cost: O(n) for the corners and O(n + k) per
// fit round for n raw points and k control points when the fit is close (sparse banded normal
// equations, local deviation bounds), O(log(n / k₀)) rounds per piece; n grows 16× at most when a
// piece is densified.
#pragma once

#include <vector>

#include "curvedslicer/core/types.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

struct PathFitOptions {
  double tolerance = 0.05;      ///< mm, largest distance between spline and raw iso-line (> 0)
  double pointSpacing = 2.0;    ///< mm, largest distance between resampled points (> 0)
  double chordTolerance = 0.0;  ///< mm, largest chord error; ≤ 0 means = `tolerance`
  /// Weight of the control-point second-difference penalty relative to the data term (≥ 0);
  /// keeps the spline from wiggling between raw points. 0 is a plain least-squares fit.
  double smoothing = 1e-4;
  /// Degrees: a turn larger than this over 4 × `tolerance` of arc length on each side of a raw
  /// vertex is a corner the path keeps exactly (> 0; ≥ 180 finds none, every line is one spline).
  double cornerAngle = 30.0;
};

/// A cubic B-spline curve, part frame, mm. Open: clamped knot vector (passes through the first and
/// last control points), parameter u in [0, 1]; interior knots may repeat up to 3 times (C0
/// there). Closed: periodic with uniform knots, u in [0, 1) wrapping around.
struct BSplineCurve {
  static constexpr int kDegree = 3;
  bool closed = false;
  std::vector<Vec3> controlPoints;
  /// Open: full clamped knot vector (controlPoints + 4 entries, 0…0, …, 1…1, non-decreasing).
  /// Closed: the controlPoints + 1 breakpoints 0, 1/k, …, 1 of the periodic uniform spline.
  std::vector<double> knots;

  /// Point at parameter u (open: clamped to [0, 1]; closed: taken modulo 1).
  Vec3 evaluate(double u) const;
  /// First derivative dC/du at u.
  Vec3 derivative(double u) const;
  bool empty() const { return controlPoints.empty(); }
};

struct PathFitResult {
  /// The fitted curve of the whole path. A closed path without corners: periodic (closed = true).
  /// Otherwise clamped (closed = false), the pieces joined with knots of multiplicity 3 at the
  /// corners, each piece's parameter range proportional to its raw length; for a closed path it
  /// starts and ends at its first corner (evaluate(0) = evaluate(1)).
  BSplineCurve spline;
  /// The resampled path: open paths start and end at the raw path's end points; closed paths
  /// are closed (first point not repeated).
  Polyline points;
  double fitDeviation = 0.0;  ///< mm, measured two-sided distance between spline and raw line
  double chordError = 0.0;    ///< mm, largest measured distance of the spline from its chords
  int fitRounds = 0;          ///< control-point counts tried, summed over the pieces
  /// Indices into `points.points` of the corners (raw vertices kept exactly, C0 there), ascending.
  /// A closed path with corners starts at its first corner (index 0).
  std::vector<std::size_t> corners;
};

/// Fits and resamples one raw path (see the file comment). If interpolating every kept point of a
/// piece still misses the tolerance (turns sharper than the raw sampling can follow), its raw
/// segments are sampled 4× more densely, at most twice, and if that fails too the piece is kept as
/// a polyline of its kept vertices (within tolerance / 25 of the raw line). `fitDeviation` is the
/// measured two-sided deviation.
/// @throws InvalidInput for non-positive or non-finite tolerance, spacing or corner angle, negative
///         smoothing,
///         too few distinct points (open < 2, closed < 3) or non-finite points; NumericalFailure
///         for a singular or non-finite fit (repeated points the cleaning did not catch).
PathFitResult fitPath(const Polyline& raw, const PathFitOptions& options = {});

/// Resamples a polyline at equal arc length with at most `spacing` (mm) between points; keeps the
/// end points of open polylines and the closed flag. @throws InvalidInput for spacing ≤ 0.
Polyline resamplePolyline(const Polyline& polyline, double spacing);

}  // namespace curvedslicer
