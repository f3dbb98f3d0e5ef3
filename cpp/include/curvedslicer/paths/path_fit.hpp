// Path fitting (paper §3.1: "piecewise polynomial is used to fit path curves"): a smoothing cubic
// B-spline within a tolerance of a raw iso-line, resampled at a robot point spacing with bounded
// chord error.
//
// Method: the raw points are parameterised by chord length. A cubic B-spline with uniform knots
// (clamped with fixed end points for open curves, periodic for closed ones, so closed curves stay
// closed and C²) is fitted by penalised least squares, minimising Σ|C(u_i) − p_i|² +
// λ·Σ|Δ²P_j|² (second differences of the control points, λ = `smoothing` × the data scale). The
// number of control points starts at length / (8·pointSpacing) + 4 and grows by half until the
// fit is within `tolerance` both ways (every raw vertex to the spline, every spline sample to the
// raw polyline); at the raw point count the penalty is dropped (interpolation). The spline is then
// resampled at equal arc length with at most `pointSpacing` between points, and every interval
// whose chord leaves the spline by more than `chordTolerance` is halved until none does.
// The deviation of a round is exact for the spline's dense samples (16 per span, ≥ 4 per raw
// point): every distance is first bounded by the few segments around its parameter; only the
// distances that could raise the running maximum are measured exactly (brute force for the first
// few, then through a uniform hash grid of the segments).
// Preconditions: ≥ 2 raw points (closed: ≥ 3), finite. Cost: O(n + k) per fit round for n raw
// points and k control points when the fit is close (sparse banded normal equations, local
// deviation bounds), O(log(n / k₀)) rounds; n grows 16× at most when the raw line is densified.
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
};

/// A cubic B-spline curve, part frame, mm. Open: clamped knot vector (passes through the first and
/// last control points), parameter u in [0, 1]. Closed: periodic with uniform knots, u in [0, 1)
/// wrapping around.
struct BSplineCurve {
  static constexpr int kDegree = 3;
  bool closed = false;
  std::vector<Vec3> controlPoints;
  /// Open: full clamped knot vector (controlPoints + 4 entries, 0…0, …, 1…1). Closed: the
  /// controlPoints + 1 breakpoints 0, 1/k, …, 1 of the periodic uniform spline.
  std::vector<double> knots;

  /// Point at parameter u (open: clamped to [0, 1]; closed: taken modulo 1).
  Vec3 evaluate(double u) const;
  /// First derivative dC/du at u.
  Vec3 derivative(double u) const;
  bool empty() const { return controlPoints.empty(); }
};

struct PathFitResult {
  BSplineCurve spline;
  /// The resampled path: open paths start and end at the raw path's end points; closed paths
  /// are closed (first point not repeated).
  Polyline points;
  double fitDeviation = 0.0;  ///< mm, measured two-sided distance between spline and raw line
  double chordError = 0.0;    ///< mm, largest measured distance of the spline from its chords
  int fitRounds = 0;          ///< control-point counts tried
};

/// Fits and resamples one raw path (see the file comment). If interpolating every raw point still
/// misses the tolerance (corners sharper than the raw sampling can follow), the raw segments are
/// sampled 4× more densely, at most twice; `fitDeviation` reports what was achieved (it exceeds
/// the tolerance only if even that fails — callers that must guarantee it check the field).
/// @throws InvalidInput for non-positive or non-finite tolerance or spacing, negative smoothing,
///         too few distinct points (open < 2, closed < 3) or non-finite points; NumericalFailure
///         for a singular or non-finite fit (repeated points the cleaning did not catch).
PathFitResult fitPath(const Polyline& raw, const PathFitOptions& options = {});

/// Resamples a polyline at equal arc length with at most `spacing` (mm) between points; keeps the
/// end points of open polylines and the closed flag. @throws InvalidInput for spacing ≤ 0.
Polyline resamplePolyline(const Polyline& polyline, double spacing);

}  // namespace curvedslicer
