// Internal to planMotion (robot/motion.cpp): the positioner angles along one path — merged
// near-duplicate points, eq. 16 per point, the near-singular band (a2 blended with a bounded
// rate, the tilt compensating), points inserted where a2 would still step more than
// MotionOptions::maxA2Step. Method in docs/METHODS.md, "Positioner and robot".
#pragma once

#include <cstdint>
#include <vector>

#include "curvedslicer/plan/plan.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/positioner.hpp"

namespace curvedslicer::detail {

/// One point of a path as the positioner phase sees it (part frame).
struct AngleSample {
  Vec3 position = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  Vec3 deposition = -Vec3::UnitZ();  // plan V (unit)
  Vec3 v = -Vec3::UnitZ();           // V used (smoothed), unit
  int index = 0;                     // plan point index (inserted: the point before)
  bool inserted = false;
  double arc = 0.0;  // mm along the path from its first point
  GravityAlignment align;
  bool band = false;          // V within the near-singular band of the rotation axis
  bool fixed = false;         // no exact alignment within the limits: angles of least residual kept
  double exactA2 = 0.0;       // a2 of an exact alignment, continuous along the path
  double a1 = 0.0, a2 = 0.0;  // chosen
  std::uint32_t flags = 0;
};

/// The path's points as welded (a closed path ends on point 0 again), V smoothed, consecutive
/// points closer than options.mergeTolerance merged (the first of them kept; an open path keeps
/// its last point). `merged` counts the points dropped. `targets`, when given (one per path
/// point, zero = none), replaces the smoothed V the positioner turns onto gravity at the points
/// it names (the gravity deviation that lets the torch clear; kMotionGravityDeviated); the plan
/// V stays the sample's `deposition`, so the residual measures the deviation.
std::vector<AngleSample> sampleDepositions(const PlanPath& path, const PositionerDescription& pos,
                                           const Vec3& gravity, const MotionOptions& options,
                                           std::size_t& merged,
                                           const std::vector<Vec3>* targets = nullptr);

/// Positioner angles along one path. `a2Rate` (rad/mm) bounds how fast a2 may move along the
/// path where it is blended; `refA1/refA2/haveRef` carry the end of the previous path.
void planPathAngles(const PositionerDescription& pos, const Vec3& gravity, double a2Rate,
                    std::vector<AngleSample>& samples, double& refA1, double& refA2, bool& haveRef,
                    const MotionOptions& options);

}  // namespace curvedslicer::detail
