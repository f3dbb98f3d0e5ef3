// Polyline measurements (see curvedslicer/paths/polyline.hpp).
#include "curvedslicer/paths/polyline.hpp"

#include <algorithm>
#include <cmath>

namespace curvedslicer {

namespace {

/// Closest point parameter t in [0, 1] on segment ab to p.
double closestSegmentParameter(const Vec3& a, const Vec3& b, const Vec3& p) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return 0.0;
  return std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
}

/// Smallest distance between segments p0p1 and q0q1 (Ericson, RTCD §5.1.9).
double segmentSegmentDistance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 1e-300 && e <= 1e-300) return r.norm();
  if (a <= 1e-300) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 1e-300) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

}  // namespace

std::size_t Polyline::segmentCount() const {
  if (points.size() < 2) return 0;
  if (closed) return points.size() >= 3 ? points.size() : 1;
  return points.size() - 1;
}

double Polyline::length() const {
  double total = 0.0;
  for (std::size_t i = 0; i < segmentCount(); ++i)
    total += (segmentEnd(i) - segmentStart(i)).norm();
  return total;
}

PolylinePoint closestPointOnPolyline(const Polyline& polyline, const Vec3& p) {
  PolylinePoint best;
  if (polyline.points.empty()) return best;
  if (polyline.points.size() == 1) {
    best.point = polyline.points[0];
    best.distance = (p - best.point).norm();
    return best;
  }
  for (std::size_t i = 0; i < polyline.segmentCount(); ++i) {
    const Vec3& a = polyline.segmentStart(i);
    const Vec3& b = polyline.segmentEnd(i);
    const double t = closestSegmentParameter(a, b, p);
    const Vec3 q = a + t * (b - a);
    const double d = (p - q).norm();
    if (d < best.distance) {
      best.point = q;
      best.segment = i;
      best.parameter = t;
      best.distance = d;
    }
  }
  return best;
}

std::vector<double> computeCumulativeLengths(const Polyline& polyline) {
  std::vector<double> s;
  if (polyline.points.empty()) return s;
  s.reserve(polyline.points.size() + 1);
  s.push_back(0.0);
  for (std::size_t i = 0; i < polyline.segmentCount(); ++i) {
    s.push_back(s.back() + (polyline.segmentEnd(i) - polyline.segmentStart(i)).norm());
  }
  return s;
}

Vec3 evaluatePolylineAt(const Polyline& polyline, double s) {
  if (polyline.points.empty()) return Vec3::Zero();
  const std::vector<double> cum = computeCumulativeLengths(polyline);
  const double total = cum.back();
  if (total <= 0.0) return polyline.points.front();
  if (polyline.closed) {
    s = std::fmod(s, total);
    if (s < 0.0) s += total;
  } else {
    s = std::clamp(s, 0.0, total);
  }
  const auto it = std::upper_bound(cum.begin(), cum.end(), s);
  const std::size_t i =
      std::min<std::size_t>(std::max<std::ptrdiff_t>(it - cum.begin() - 1, 0), cum.size() - 2);
  const double len = cum[i + 1] - cum[i];
  const double t = len > 0.0 ? (s - cum[i]) / len : 0.0;
  return polyline.segmentStart(i) + t * (polyline.segmentEnd(i) - polyline.segmentStart(i));
}

double computePolylineDistance(const Polyline& a, const Polyline& b) {
  if (a.points.empty() || b.points.empty()) return kInf;
  if (a.segmentCount() == 0) return closestPointOnPolyline(b, a.points[0]).distance;
  if (b.segmentCount() == 0) return closestPointOnPolyline(a, b.points[0]).distance;
  double best = kInf;
  for (std::size_t i = 0; i < a.segmentCount(); ++i) {
    for (std::size_t j = 0; j < b.segmentCount(); ++j) {
      best = std::min(best, segmentSegmentDistance(a.segmentStart(i), a.segmentEnd(i),
                                                   b.segmentStart(j), b.segmentEnd(j)));
    }
  }
  return best;
}

double computeOneSidedHausdorff(const Polyline& a, const Polyline& b, int samplesPerSegment) {
  if (a.points.empty()) return 0.0;
  if (b.points.empty()) return kInf;
  const int n = std::max(samplesPerSegment, 1);
  double worst = 0.0;
  for (const Vec3& p : a.points) worst = std::max(worst, closestPointOnPolyline(b, p).distance);
  for (std::size_t i = 0; i < a.segmentCount(); ++i) {
    for (int k = 1; k < n; ++k) {
      const double t = static_cast<double>(k) / n;
      const Vec3 p = a.segmentStart(i) + t * (a.segmentEnd(i) - a.segmentStart(i));
      worst = std::max(worst, closestPointOnPolyline(b, p).distance);
    }
  }
  return worst;
}

bool hasSelfIntersection(const Polyline& polyline, double tolerance) {
  const std::size_t m = polyline.segmentCount();
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = i + 2; j < m; ++j) {
      if (polyline.closed && i == 0 && j == m - 1) continue;  // adjacent through the closing point
      if (segmentSegmentDistance(polyline.segmentStart(i), polyline.segmentEnd(i),
                                 polyline.segmentStart(j), polyline.segmentEnd(j)) < tolerance) {
        return true;
      }
    }
  }
  return false;
}

}  // namespace curvedslicer
