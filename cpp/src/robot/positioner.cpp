// Positioner forward kinematics and the closed-form gravity alignment of eq. 16.
#include "curvedslicer/robot/positioner.hpp"

#include <algorithm>
#include <cmath>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

/// Rotation by `angle` about the line through `point` with unit `direction`.
Pose rotationAbout(const Vec3& point, const Vec3& direction, double angle) {
  Pose pose = Pose::Identity();
  pose.linear() = Eigen::AngleAxisd(angle, direction).toRotationMatrix();
  pose.translation() = point - pose.linear() * point;
  return pose;
}

Mat3 rotation(const Vec3& direction, double angle) {
  return Eigen::AngleAxisd(angle, direction).toRotationMatrix();
}

/// Signed angle about unit `axis` that turns `from` towards `to` (components along the axis
/// ignored): Paden–Kahan subproblem 1.
double angleAbout(const Vec3& axis, const Vec3& from, const Vec3& to) {
  const double y = axis.dot(from.cross(to));
  const double x = from.dot(to) - axis.dot(from) * axis.dot(to);
  return std::atan2(y, x);
}

double wrapPi(double angle) {
  double a = std::remainder(angle, kTwoPi);
  if (a <= -kPi) a += kTwoPi;
  return a;
}

double angleBetween(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// V in the positioner base frame at a1 = a2 = 0, gravity in the positioner base frame.
Vec3 depositionAtZero(const PositionerDescription& p, const Vec3& v) {
  return computeTableZeroPose(p).linear() * (p.tableToPart.linear() * v);
}
Vec3 gravityInBase(const PositionerDescription& p, const Vec3& g) {
  return p.base.linear().transpose() * g;
}

}  // namespace

double unwrapNear(double angle, double reference) {
  return angle + kTwoPi * std::round((reference - angle) / kTwoPi);
}

Pose computeTableZeroPose(const PositionerDescription& p) {
  const Vec3 z = p.rotationAxisDirection.normalized();
  Vec3 x = p.tiltAxisDirection - z * z.dot(p.tiltAxisDirection);
  if (x.norm() < 1e-12) {
    throw InvalidInput("positioner rotation axis is parallel to the tilt axis: " +
                       std::to_string(z.dot(p.tiltAxisDirection)) +
                       "; give axes that differ by at least 1 degree");
  }
  x.normalize();
  Pose pose = Pose::Identity();
  pose.linear().col(0) = x;
  pose.linear().col(1) = z.cross(x);
  pose.linear().col(2) = z;
  pose.translation() = p.rotationAxisPoint;
  return pose;
}

Pose computePartInPositionerBase(const PositionerDescription& p, double a1, double a2) {
  return rotationAbout(p.tiltAxisPoint, p.tiltAxisDirection, a1) *
         rotationAbout(p.rotationAxisPoint, p.rotationAxisDirection, a2) * computeTableZeroPose(p) *
         p.tableToPart;
}

Pose computePartInWorld(const PositionerDescription& p, double a1, double a2) {
  return p.base * computePartInPositionerBase(p, a1, a2);
}

Pose computeTableInWorld(const PositionerDescription& p, double a1, double a2) {
  return p.base * rotationAbout(p.tiltAxisPoint, p.tiltAxisDirection, a1) *
         rotationAbout(p.rotationAxisPoint, p.rotationAxisDirection, a2) * computeTableZeroPose(p);
}

GravityAlignment alignWithGravity(const PositionerDescription& p, const Vec3& depositionInPart,
                                  const Vec3& gravityInWorld) {
  const Vec3& uT = p.tiltAxisDirection;
  const Vec3& uR = p.rotationAxisDirection;
  const Vec3 v = depositionAtZero(p, depositionInPart.normalized());
  const Vec3 g = gravityInBase(p, gravityInWorld.normalized());
  GravityAlignment result;
  result.axisAngle = std::atan2(uR.cross(v).norm(), std::abs(uR.dot(v)));
  // eq. 16, second condition after the first: uR · R_T(-a1) g = uR · v, i.e.
  // A cos a1 + B sin a1 = d.
  const double gT = uT.dot(g);
  const double A = uR.dot(g) - gT * uR.dot(uT);
  const double B = -uR.dot(uT.cross(g));
  const double C = gT * uR.dot(uT);
  const double r = std::hypot(A, B);
  double d = uR.dot(v) - C;
  double alpha = 0.0;
  const double phi = std::atan2(B, A);
  if (r < 1e-12) {
    // Gravity along the tilt axis: tilting cannot change it; any a1 is as good as another.
    result.feasible = std::abs(d) < 1e-12;
  } else {
    if (std::abs(d) > r) {
      result.feasible = false;
      d = std::clamp(d, -r, r);
    }
    alpha = std::acos(std::clamp(d / r, -1.0, 1.0));
  }
  const double a1s[2] = {wrapPi(phi + alpha), wrapPi(phi - alpha)};
  for (int b = 0; b < 2; ++b) {
    const Vec3 w = rotation(uT, -a1s[b]) * g;
    result.branches[b].a1 = a1s[b];
    result.branches[b].a2 = wrapPi(angleAbout(uR, v, w));
  }
  return result;
}

double optimalTiltForRotation(const PositionerDescription& p, const Vec3& depositionInPart,
                              const Vec3& gravityInWorld, double a2) {
  const Vec3 v = depositionAtZero(p, depositionInPart.normalized());
  const Vec3 g = gravityInBase(p, gravityInWorld.normalized());
  const Vec3 u = rotation(p.rotationAxisDirection, a2) * v;
  return angleAbout(p.tiltAxisDirection, u, g);
}

double optimalRotationForTilt(const PositionerDescription& p, const Vec3& depositionInPart,
                              const Vec3& gravityInWorld, double a1) {
  const Vec3 v = depositionAtZero(p, depositionInPart.normalized());
  const Vec3 g = gravityInBase(p, gravityInWorld.normalized());
  const Vec3 w = rotation(p.tiltAxisDirection, -a1) * g;
  return angleAbout(p.rotationAxisDirection, v, w);
}

double computeGravityResidual(const PositionerDescription& p, const Vec3& depositionInPart,
                              const Vec3& gravityInWorld, double a1, double a2) {
  const Vec3 v = depositionAtZero(p, depositionInPart.normalized());
  const Vec3 g = gravityInBase(p, gravityInWorld.normalized());
  const Vec3 turned =
      rotation(p.tiltAxisDirection, a1) * (rotation(p.rotationAxisDirection, a2) * v);
  return angleBetween(turned, g);
}

PositionerAngles solvePositionerPose(const PositionerDescription& p, const Pose& partInBase) {
  const Vec3& uT = p.tiltAxisDirection;
  const Vec3& uR = p.rotationAxisDirection;
  // R = R_T(a1) R_R(a2): R_R leaves uR fixed, so R uR = R_T(a1) uR.
  const Mat3 zero = computeTableZeroPose(p).linear() * p.tableToPart.linear();
  const Mat3 R = partInBase.linear() * zero.transpose();
  PositionerAngles angles;
  angles.a1 = angleAbout(uT, uR, R * uR);
  const Mat3 RR = rotation(uT, -angles.a1) * R;
  const Vec3 x0 = computeTableZeroPose(p).linear().col(0);  // orthogonal to uR
  angles.a2 = wrapPi(angleAbout(uR, x0, RR * x0));
  return angles;
}

}  // namespace curvedslicer
