#include "common/raw_paths.hpp"

#include <cmath>

namespace curvedslicer::testing {

Polyline makeBulgedSquareRing(double side, double bulge, double step, double microGap,
                              std::vector<Vec3>& corners) {
  Polyline p;
  p.closed = true;
  corners.clear();
  const double h = 0.5 * side;
  const Vec3 v[4] = {Vec3(-h, -h, 0), Vec3(h, -h, 0), Vec3(h, h, 0), Vec3(-h, h, 0)};
  const int perSide = static_cast<int>(std::lround(side / step));
  auto zWave = [&](const Vec3& q) { return 0.8 * std::sin(0.05 * q.x()) * std::cos(0.04 * q.y()); };
  int count = 0;
  for (int c = 0; c < 4; ++c) {
    const Vec3 a = v[c], b = v[(c + 1) % 4];
    const Vec3 outward = (0.5 * (a + b)).normalized();
    for (int i = 0; i < perSide; ++i) {
      const double t = static_cast<double>(i) / perSide;
      // Parabolic bulge, 0 at the corners.
      Vec3 q = a + (b - a) * t + outward * (4.0 * bulge * t * (1.0 - t));
      q.z() = zWave(q);
      if (i == 0) corners.push_back(q);
      p.points.push_back(q);
      if (microGap > 0.0 && ++count % 10 == 0 && i + 1 < perSide) {
        const Vec3 next = a + (b - a) * ((i + 1.0) / perSide);
        p.points.push_back(q + (next - q).normalized() * microGap);
      }
    }
  }
  return p;
}

}  // namespace curvedslicer::testing
