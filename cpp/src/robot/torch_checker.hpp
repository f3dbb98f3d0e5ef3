// Internal to robot/: one torch pose against the deposit so far and the positioner table (FCL
// narrow phase; see robot/collision.hpp for the model). Shared by the collision check and the
// travel planner, which raises travel routes until the torch clears.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "curvedslicer/robot/collision.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "deposit_index.hpp"

namespace curvedslicer::detail {

struct TorchHit {
  enum class Object { None, Deposit, Table, Riser, Substrate };
  Object object = Object::None;
  double depth = 0.0;       ///< mm, penetration depth
  std::size_t segment = 0;  ///< DepositIndex segment hit (Object::Deposit)
  bool collides() const { return object != Object::None; }
};

/// Torch tip and the unit direction from the tip up the torch body (part frame) of a TCP pose
/// in the part frame (the tool z axis points out of the torch towards the tip).
inline void torchAxisOf(const Pose& toolInPart, Vec3& tip, Vec3& up) {
  tip = toolInPart.translation();
  up = -toolInPart.linear().col(2);
}

class TorchChecker {
 public:
  TorchChecker(const Cell& cell, const CollisionGeometry& geometry, const DepositIndex& deposit);
  ~TorchChecker();
  TorchChecker(const TorchChecker&) = delete;
  TorchChecker& operator=(const TorchChecker&) = delete;

  /// The torch with its tip at `tip` and its body along unit `up` (part frame).
  TorchHit check(const Vec3& tip, const Vec3& up) const;

  /// Whether check() could find a hit, without its depth: stops at the first contact and takes
  /// a bead closer than the envelope's radius as one without FCL's confirmation (so it never
  /// clears a pose check() rejects). For searches that try many poses.
  bool collides(const Vec3& tip, const Vec3& up) const;

  /// One capsule of the envelope: its axis from `from` to `to` mm above the TCP, its radius.
  struct Section {
    double from = 0.0;
    double to = 0.0;
    double radius = 0.0;
  };

 private:
  struct Fcl;
  TorchHit checkDeposit(std::size_t section, const Vec3& bottom, const Vec3& top) const;
  TorchHit checkTable(std::size_t section, const Vec3& bottom, const Vec3& top) const;
  TorchHit checkFixture(std::size_t section, const Vec3& bottom, const Vec3& top) const;

  const DepositIndex& deposit_;
  std::vector<Section> sections_;
  Pose partToTable_;  // part frame -> table frame
  double tableRadius_ = 0.0;
  FixtureGeometry fixture_;
  std::unique_ptr<Fcl> fcl_;
};

/// The deepest hit along a joint-interpolated move (robot joints and positioner angles linear,
/// sampled every 0.25° of the axis that moves most; forward kinematics).
TorchHit checkJointMove(const Cell& cell, const TorchChecker& checker, const MotionPoint& from,
                        const MotionPoint& to);

/// The deepest hit along a move linear in the part frame (tip on the chord, axis turned evenly;
/// samples at most half the envelope radius apart, counting the sweep of the torch's far end).
TorchHit checkLinearMove(const TorchChecker& checker, const TorchEnvelope& torch,
                         const Pose& fromToolInPart, const Pose& toToolInPart);

}  // namespace curvedslicer::detail
