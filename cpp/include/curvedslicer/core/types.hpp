// Basic geometric value types shared by every stage.
//
// Units: lengths in millimetres, angles in radians, unless a field comment says otherwise.
// Frames: "part frame" is the model's original coordinate system (every result is expressed in
// it); "grid frame" is the voxel grid's (PCA-aligned) frame; "cell" means integer voxel indices.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <limits>

namespace curvedslicer {

using Vec3 = Eigen::Vector3d;
using Vec3f = Eigen::Vector3f;
using Vec3i = Eigen::Vector3i;
using Mat3 = Eigen::Matrix3d;

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr float kInfF = std::numeric_limits<float>::infinity();

/// Axis-aligned box; empty (min > max) until a point is added.
struct Aabb {
  Vec3 min = Vec3::Constant(kInf);
  Vec3 max = Vec3::Constant(-kInf);

  void extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void extend(const Aabb& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  bool empty() const { return (min.array() > max.array()).any(); }
  Vec3 size() const { return empty() ? Vec3::Zero() : Vec3(max - min); }
  Vec3 center() const { return 0.5 * (min + max); }
  double diagonal() const { return size().norm(); }
};

}  // namespace curvedslicer
