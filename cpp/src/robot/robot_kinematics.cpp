// Forward and closed-form inverse kinematics of the ortho-parallel spherical-wrist robot.
#include "curvedslicer/robot/robot_kinematics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace curvedslicer {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;
constexpr double kWristSingular = 1e-7;  // rad, |joint 5| below this: wrist singular

Mat3 rotX(double a) {
  return Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix();
}
Mat3 rotY(double a) {
  return Eigen::AngleAxisd(a, Vec3::UnitY()).toRotationMatrix();
}
Mat3 rotZ(double a) {
  return Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix();
}

/// Flange orientation at the model zero pose: z along +x, x along -z.
Mat3 flangeZero() {
  return rotY(kPi / 2.0);
}

/// angle in (-π, π].
double wrapPi(double angle) {
  const double a = angle - kTwoPi * std::floor((angle + kPi) / kTwoPi);  // [-π, π)
  return a <= -kPi ? a + kTwoPi : a;
}

JointVector toModel(const RobotDescription& robot, const JointVector& controller) {
  JointVector q;
  for (int i = 0; i < 6; ++i) q[i] = robot.jointSigns[i] * controller[i] + robot.jointOffsets[i];
  if (robot.j3RelativeToHorizontal) q[2] -= q[1];  // J3 measured from the horizontal
  return q;
}

JointVector toController(const RobotDescription& robot, const JointVector& model) {
  JointVector m = model;
  if (robot.j3RelativeToHorizontal) m[2] += m[1];
  JointVector t;
  for (int i = 0; i < 6; ++i) t[i] = robot.jointSigns[i] * (m[i] - robot.jointOffsets[i]);
  return t;
}

/// Moves one angle by 2πk into [min, max] nearest `reference`; false if no shift fits (the angle
/// then goes to the shift nearest the range).
bool unwrapInto(double& angle, const JointLimit& limit, double reference) {
  constexpr double kTolerance = 1e-9;  // as JointLimit::contains
  const double base = angle + kTwoPi * std::round((reference - angle) / kTwoPi);
  if (limit.contains(base, kTolerance)) {
    angle = base;
    return true;
  }
  // shifts k with min <= base + 2πk <= max; the nearest to the reference is an end of that run
  const double kLow = std::ceil((limit.min - kTolerance - base) / kTwoPi);
  const double kHigh = std::floor((limit.max + kTolerance - base) / kTwoPi);
  if (kLow <= kHigh) {
    const double low = base + kLow * kTwoPi, high = base + kHigh * kTwoPi;
    angle = std::abs(low - reference) <= std::abs(high - reference) ? low : high;
    return true;
  }
  // no shift fits (range narrower than a turn): the one nearest the range
  const double below = base + kHigh * kTwoPi, above = base + kLow * kTwoPi;
  angle = (limit.min - below) <= (above - limit.max) ? below : above;
  return false;
}

}  // namespace

Pose computeFlangePose(const RobotDescription& robot, const JointVector& joints) {
  const RobotKinematics& k = robot.kinematics;
  const JointVector q = toModel(robot, joints);
  const Vec3 shoulder(k.a1, k.b, k.c1);
  const Mat3 arm = rotY(q[1] + q[2]);
  const Vec3 wrist = shoulder + rotY(q[1]) * Vec3(0, 0, k.c2) + arm * Vec3(k.c3, 0, k.a2);
  const Mat3 wristRotation = arm * rotX(q[3]) * rotY(q[4]) * rotX(q[5]);
  const Mat3 r1 = rotZ(q[0]);
  Pose pose = Pose::Identity();
  pose.linear() = r1 * wristRotation * flangeZero();
  pose.translation() = r1 * (wrist + wristRotation * Vec3(k.c4, 0, 0));
  return pose;
}

ArmPoints computeArmPoints(const RobotDescription& robot, const JointVector& joints) {
  const RobotKinematics& k = robot.kinematics;
  const JointVector q = toModel(robot, joints);
  const Mat3 r1 = rotZ(q[0]);
  const Vec3 shoulder(k.a1, k.b, k.c1);
  const Vec3 elbow = shoulder + rotY(q[1]) * Vec3(0, 0, k.c2);
  const Mat3 r23 = rotY(q[1] + q[2]);
  const Vec3 forearmRoot = elbow + r23 * Vec3(0, 0, k.a2);
  const Vec3 wrist = forearmRoot + r23 * Vec3(k.c3, 0, 0);
  ArmPoints points;
  points.column = Vec3(0, 0, k.c1);
  points.shoulder = r1 * shoulder;
  points.elbow = r1 * elbow;
  points.forearmRoot = r1 * forearmRoot;
  points.side = r1 * Vec3::UnitY();
  points.wrist = r1 * wrist;
  points.flange = computeFlangePose(robot, joints).translation();
  return points;
}

double elbowAngle(const RobotDescription& robot, const JointVector& joints) {
  const ArmPoints a = computeArmPoints(robot, joints);
  const Vec3 upper = a.shoulder - a.elbow, fore = a.wrist - a.elbow;
  return std::atan2(upper.cross(fore).norm(), upper.dot(fore));
}

std::optional<JointVector> findFoldedPose(const RobotDescription& robot, double minElbowAngle) {
  constexpr double kStep = kPi / 180.0;
  const JointLimit& l2 = robot.joints[1];
  const JointLimit& l3 = robot.joints[2];
  for (double q2 = l2.min; q2 <= l2.max + 1e-12; q2 += kStep) {
    for (double q3 = l3.min; q3 <= l3.max + 1e-12; q3 += kStep) {
      const JointVector q{0.0, q2, q3, 0.0, 0.0, 0.0};
      if (elbowAngle(robot, q) < minElbowAngle && violatedInterference(robot, q) == nullptr) {
        return q;
      }
    }
  }
  return std::nullopt;
}

IkResult solveInverseKinematics(const RobotDescription& robot, const Pose& flange,
                                double wristReference) {
  const RobotKinematics& k = robot.kinematics;
  IkResult result;
  const Mat3 R = flange.linear();
  const Vec3 w = flange.translation() - k.c4 * R.col(2);
  const double rho2 = w.x() * w.x() + w.y() * w.y();
  const double b2 = k.b * k.b;
  if (rho2 < b2) {
    result.reachShortfall = std::abs(k.b) - std::sqrt(rho2);
    return result;
  }
  const double xr = std::sqrt(rho2 - b2);
  const double kk = std::hypot(k.c3, k.a2);
  const double psi = std::atan2(k.c3, k.a2);
  const double qRef4 = robot.jointSigns[3] * wristReference + robot.jointOffsets[3];
  double bestShortfall = kInf;
  for (int back = 0; back < 2; ++back) {
    const double x = back ? -xr : xr;
    const double q1 = std::atan2(w.y(), w.x()) - std::atan2(k.b, x);
    const double dx = x - k.a1;
    const double dz = w.z() - k.c1;
    const double dist = std::hypot(dx, dz);
    const double shortfall = std::max({0.0, dist - (k.c2 + kk), std::abs(k.c2 - kk) - dist});
    bestShortfall = std::min(bestShortfall, shortfall);
    if (shortfall > 1e-9) continue;
    const double s =
        std::clamp((dist * dist - k.c2 * k.c2 - kk * kk) / (2.0 * k.c2 * kk), -1.0, 1.0);
    const double elbow = std::acos(s);
    for (int down = 0; down < 2; ++down) {
      const double q3 = (down ? -elbow : elbow) - psi;
      const double ux = k.c3 * std::cos(q3) + k.a2 * std::sin(q3);
      const double uz = -k.c3 * std::sin(q3) + k.a2 * std::cos(q3);
      const double q2 = std::atan2(dx, dz) - std::atan2(ux, k.c2 + uz);
      const Mat3 arm = rotZ(q1) * rotY(q2 + q3);
      const Mat3 Rw = arm.transpose() * R * flangeZero().transpose();
      const double s5 = std::hypot(Rw(1, 0), Rw(2, 0));
      for (int flip = 0; flip < 2; ++flip) {
        double q4, q5, q6;
        bool singular = false;
        if (s5 < kWristSingular) {
          singular = true;
          if (Rw(0, 0) > 0) {  // Rw = Rx(q4 + q6)
            q5 = 0.0;
            q4 = qRef4;
            q6 = std::atan2(Rw(2, 1), Rw(1, 1)) - q4;
          } else {  // Rw = Rx(q4 - q6) Ry(π)
            q5 = flip ? -kPi : kPi;
            q4 = qRef4;
            const Mat3 m = Rw * rotY(-kPi);
            q6 = q4 - std::atan2(m(2, 1), m(1, 1));
          }
          if (flip) {
            // the flipped wrist at a singularity is the same pose; offer it with q4 + π
            q4 += kPi;
            q6 -= kPi;
          }
        } else {
          q5 = std::atan2(s5, Rw(0, 0));
          q4 = std::atan2(Rw(1, 0), -Rw(2, 0));
          q6 = std::atan2(Rw(0, 1), Rw(0, 2));
          if (flip) {
            q5 = -q5;
            q4 += kPi;
            q6 += kPi;
          }
        }
        const JointVector model{wrapPi(q1), wrapPi(q2), wrapPi(q3),
                                wrapPi(q4), wrapPi(q5), wrapPi(q6)};
        IkSolution solution;
        solution.joints = toController(robot, model);
        for (double& a : solution.joints) a = wrapPi(a);
        solution.configuration = back | (down << 1) | (flip << 2);
        solution.wristSingular = singular;
        JointVector shifted = solution.joints;
        solution.withinLimits = unwrapJoints(robot, shifted, solution.joints);
        if (solution.withinLimits) solution.joints = shifted;
        result.solutions.push_back(solution);
      }
    }
  }
  result.reachShortfall = result.solutions.empty() ? bestShortfall : 0.0;
  return result;
}

bool unwrapJoints(const RobotDescription& robot, JointVector& joints,
                  const JointVector& reference) {
  bool ok = true;
  for (int i = 0; i < 6; ++i) ok = unwrapInto(joints[i], robot.joints[i], reference[i]) && ok;
  if (!ok) return false;
  // The interference limits couple joints the box above treats separately (e.g. J2 and J3). A
  // joint whose range is wider than a turn may hold the same angle a turn away: when the nearest
  // turns violate a limit, the other turns of the coupled joints within their ranges are tried,
  // the combination nearest the reference that satisfies every limit kept.
  if (violatedInterference(robot, joints) == nullptr) return true;
  std::array<std::vector<double>, 6> candidates;
  for (int i = 0; i < 6; ++i) {
    bool coupled = false;
    for (const JointInequality& limit : robot.interference) {
      coupled = coupled || limit.coefficients[i] != 0.0;
    }
    candidates[i].push_back(joints[i]);
    if (!coupled) continue;
    for (int k = -2; k <= 2; ++k) {
      const double c = joints[i] + k * kTwoPi;
      if (k != 0 && robot.joints[i].contains(c, 1e-9)) candidates[i].push_back(c);
    }
  }
  JointVector best = joints, trial = joints;
  double bestCost = std::numeric_limits<double>::infinity();
  const auto search = [&](const auto& self, int i) -> void {
    if (i == 6) {
      if (violatedInterference(robot, trial) != nullptr) return;
      double cost = 0.0;
      for (int j = 0; j < 6; ++j) cost += std::abs(trial[j] - reference[j]);
      if (cost < bestCost) {
        bestCost = cost;
        best = trial;
      }
      return;
    }
    for (double c : candidates[i]) {
      trial[i] = c;
      self(self, i + 1);
    }
  };
  search(search, 0);
  if (!(bestCost < std::numeric_limits<double>::infinity())) return false;
  joints = best;
  return true;
}

}  // namespace curvedslicer
