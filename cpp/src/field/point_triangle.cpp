// Closest point on a triangle by Voronoi-region classification (Ericson, Real-Time Collision
// Detection, §5.1.5). Degenerate triangles fall through to the closest edge/vertex regions.
#include <algorithm>

#include "curvedslicer/field/geodesic_field.hpp"

namespace curvedslicer {

double pointTriangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                             Vec3* closest) {
  auto finish = [&](const Vec3& q) {
    if (closest) *closest = q;
    return (p - q).norm();
  };
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return finish(a);

  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return finish(b);

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double denom = d1 - d3;
    return finish(denom > 0 ? Vec3(a + (d1 / denom) * ab) : a);
  }

  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return finish(c);

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double denom = d2 - d6;
    return finish(denom > 0 ? Vec3(a + (d2 / denom) * ac) : a);
  }

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double denom = (d4 - d3) + (d5 - d6);
    return finish(denom > 0 ? Vec3(b + ((d4 - d3) / denom) * (c - b)) : b);
  }

  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    // Degenerate (collinear) triangle that reached the face region: use the closest edge.
    Vec3 best = a;
    double bestD = kInf;
    const Vec3* v[3] = {&a, &b, &c};
    for (int e = 0; e < 3; ++e) {
      const Vec3& s = *v[e];
      const Vec3& t = *v[(e + 1) % 3];
      const Vec3 st = t - s;
      const double len2 = st.squaredNorm();
      const double u = len2 > 0 ? std::clamp((p - s).dot(st) / len2, 0.0, 1.0) : 0.0;
      const Vec3 q = s + u * st;
      const double d = (p - q).squaredNorm();
      if (d < bestD) {
        bestD = d;
        best = q;
      }
    }
    return finish(best);
  }
  const double v = vb / sum, w = vc / sum;
  return finish(a + ab * v + ac * w);
}

}  // namespace curvedslicer
