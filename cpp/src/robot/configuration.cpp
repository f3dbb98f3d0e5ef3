#include "curvedslicer/robot/configuration.hpp"

#include <cmath>

namespace curvedslicer {

RobotConfiguration configurationOf(const JointVector& joints, int branch) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  RobotConfiguration c;
  c.branch = branch;
  for (int j = 0; j < 6; ++j) {
    const double degrees = joints[j] / kDeg;
    c.quadrant[j] = static_cast<int>(std::floor(degrees / 90.0));
    c.turn[j] = static_cast<int>(std::floor((degrees + 180.0) / 360.0));
    c.negative[j] = degrees < 0.0;
    c.beyond180[j] = std::abs(degrees) >= 180.0;
  }
  return c;
}

}  // namespace curvedslicer
