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

namespace {
constexpr double kQuarter = 3.14159265358979323846 / 2.0;
}

RobotConfiguration configurationOfRange(const JointVector& minJoints, const JointVector& maxJoints,
                                        int branch, double tolerance) {
  JointVector centre{};
  for (int j = 0; j < 6; ++j) {
    double quadrant = std::floor((minJoints[j] + tolerance) / kQuarter);
    if (maxJoints[j] > (quadrant + 1.0) * kQuarter + tolerance) {
      // a real crossing: the quadrant of the middle of the range
      quadrant = std::floor(0.5 * (minJoints[j] + maxJoints[j]) / kQuarter);
    }
    centre[j] = (quadrant + 0.5) * kQuarter;
  }
  return configurationOf(centre, branch);
}

bool isWithinConfiguration(const JointVector& joints, const RobotConfiguration& configuration,
                           double tolerance) {
  for (int j = 0; j < 6; ++j) {
    const double low = configuration.quadrant[j] * kQuarter;
    if (joints[j] < low - tolerance || joints[j] > low + kQuarter + tolerance) return false;
  }
  return true;
}

}  // namespace curvedslicer
