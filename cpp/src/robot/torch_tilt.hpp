// Internal to robot/: collision avoidance by torch angle. Before the robot's inverse kinematics,
// every weld point whose torch (along gravity, so along the deposition direction the positioner
// turned onto gravity) would reach into the deposit so far, the positioner table or the fixture
// gets the smallest tilt of the torch, within the process's torch window, that clears, smooth
// along the path.
//
// Method (docs/METHODS.md, "Torch angle"):
//   1. per path, in execution order, each weld point's torch is checked with the torch
//      envelope against the deposit up to that point (the welded segments of earlier paths and
//      of the path before the point) and the table and fixture (robot/torch_checker.hpp);
//   2. for a point that collides, tilts of the torch axis about its tip are tried in rings of
//      16 directions: first the window's angle (and where nothing clears there, a smaller
//      fallback window's), where nothing clears the point keeps its torch along gravity (the
//      collision check then names it); else rings of growing angle (steps of
//      at most 2.5°), the directions nearest a wanted one tried first and the first that clears
//      taken: the previous point's tilt, or without one the middle of the longest run of
//      clearing directions at the window's angle (farthest from what the torch hits); the first
//      ring that clears is refined by bisection of the angle (two halvings) in that direction;
//   3. the tilts are made smooth along the path: a tilt spreads to its neighbours, shrinking by
//      kTiltRate per mm of path; a point that needs a tilt of its own keeps it, any other takes
//      the largest of its neighbours' spread tilts, is checked with it and, where that collides,
//      searched from there and spreads in turn (at most three rounds);
//   4. each point records its torch angle and its split into travel (push > 0, drag < 0) and
//      work angle against the travel direction (MotionPoint).
// Preconditions: `motion` holds the path points with positioner angles (planMotion's positioner
// pass), MotionPlan::paths covers them. Cost: one torch check per path point, 16 for a point
// no tilt clears, up to about a hundred for one that a tilt clears (tests/bench/README.md).
#pragma once

#include <cmath>
#include <cstddef>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/collision.hpp"
#include "curvedslicer/robot/motion.hpp"

namespace curvedslicer::detail {

/// rad per mm of path: how fast a tilt may grow or shrink along a path (1°/mm).
inline constexpr double kTiltRate = 0.0174532925199433;

/// The torch body's direction (part frame) for the direction `up` along gravity and a lean
/// (orthogonal to `up`, norm = angle in rad): `up` turned by the angle towards the lean.
inline Vec3 tiltedTorchUp(const Vec3& up, const Vec3& lean) {
  const double angle = lean.norm();
  if (angle <= 0.0) return up;
  return std::cos(angle) * up + std::sin(angle) * (lean / angle);
}

/// What the tilt pass did: points tilted, the largest angle, points it could not clear.
struct TorchTiltSummary {
  std::size_t tilted = 0;     ///< weld points with a non-zero torch angle
  std::size_t uncleared = 0;  ///< points still colliding at the window's angle
  double maxAngle = 0.0;      ///< rad
};

/// Sets MotionPoint::torchTilt, torchAngle, travelAngle, workAngle and kMotionTorchTilted of the
/// weld points of `motion` (see the file comment); `maxAngle` (rad) is the largest tilt, 0
/// leaves every torch along gravity; where nothing clears at `maxAngle`, a smaller
/// `fallbackAngle` (> 0) is tried as the widest ring instead (the torch window, when `maxAngle`
/// adds the gravity deviation window to it). `gravity` is unit, world frame. `earlier`
/// (optional): a pass over the same plan whose leans are taken over for every path with the
/// same points, positioner angles and flags there and leans within `maxAngle` (the search would
/// find them again; the pass after a gravity deviation searches only the paths it turned).
/// Cancelled when `progress` asks (stage "torch angles").
TorchTiltSummary planTorchTilts(MotionPlan& motion, const Cell& cell,
                                const CollisionGeometry& geometry, const Vec3& gravity,
                                double beadRadius, double maxAngle, const Progress& progress = {},
                                double fallbackAngle = 0.0, const MotionPlan* earlier = nullptr);

}  // namespace curvedslicer::detail
