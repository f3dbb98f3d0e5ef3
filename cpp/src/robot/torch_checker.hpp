// Internal to robot/: one torch pose, or one arm pose, against the deposit so far, the positioner
// table, its body and the fixture (FCL narrow phase; see robot/collision.hpp for the model).
// Shared by the collision check, the torch-angle search and the travel planner, which raises
// travel routes until the torch clears.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "curvedslicer/robot/collision.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "deposit_index.hpp"

namespace curvedslicer::detail {

struct TorchHit {
  enum class Object { None, Deposit, Table, Riser, Substrate, PositionerBody };
  /// What hits: the torch envelope or one of the arm's link capsules (ArmEnvelope).
  enum class Part { Torch, Column, UpperArm, Forearm, Wrist };
  Object object = Object::None;
  double depth = 0.0;       ///< mm, penetration depth
  std::size_t segment = 0;  ///< DepositIndex segment hit (Object::Deposit)
  Part part = Part::Torch;
  bool collides() const { return object != Object::None; }
};

/// "torch", "upper arm", ... for messages.
const char* partName(TorchHit::Part part);

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

  /// collides(), and the arm's wrist link where it lies on the torch axis: a straight torch whose
  /// TCP is on the flange's axis puts the wrist centre and the flange at fixed heights above the
  /// TCP whatever the joints and the turn about the torch axis (wristOnAxis()). For the searches
  /// of torch angle and gravity deviation, which choose the torch axis before the joints exist.
  bool collidesWithWrist(const Vec3& tip, const Vec3& up) const;

  /// Whether collidesWithWrist() checks a wrist: the cell gives the arm and its wrist link lies
  /// on the torch axis.
  bool wristOnAxis() const { return wrist_.radius > 0.0; }

  /// Whether the cell gives the arm's link capsules (robot/link_capsules_mm), so checkArm() checks.
  bool checksArm() const { return !links_.empty(); }

  /// The robot arm's link capsules at controller joints `joints` (rad) with the positioner at
  /// a1, a2 (rad) against the deposit, the table, the positioner's body and the fixture: the
  /// deepest hit; none when the cell does not give the arm (checksArm()).
  TorchHit checkArm(const JointVector& joints, double a1, double a2) const;

  /// One piece of the envelope: its axis from `from` to `to` mm above the TCP, its radius; a
  /// capsule, or a cylinder with flat ends (`flat`: the nozzle, whose face and rim no capsule
  /// covers without reaching below the face).
  struct Section {
    double from = 0.0;
    double to = 0.0;
    double radius = 0.0;
    bool flat = false;
  };

 private:
  struct Fcl;
  /// A capsule (or, `flat`, a cylinder) of the torch or the arm: its FCL shape (index into
  /// Fcl::shapes: the envelope's sections, then the arm's links) and radius; its axis
  /// bottom-top is given in the part frame.
  struct Capsule {
    std::size_t shape = 0;
    double radius = 0.0;
    bool flat = false;
  };
  /// The deepest reach (mm) of the piece into the solid of signed distance `distance` (table
  /// frame; `b`, `t` its axis there): a capsule's axis samples, a cylinder's surface samples.
  double reachInto(const Capsule& c, const Vec3& b, const Vec3& t,
                   const std::function<double(const Vec3&)>& distance) const;
  /// The deepest bead a cylinder piece reaches into (exact: the bead radius less the least
  /// signed distance of the bead's axis from the cylinder); `firstOnly` stops at the first.
  TorchHit checkDepositCylinder(const Capsule& c, const Vec3& bottom, const Vec3& top,
                                bool firstOnly) const;
  TorchHit checkDeposit(const Capsule& c, const Vec3& bottom, const Vec3& top) const;
  TorchHit checkTable(const Capsule& c, const Vec3& bottom, const Vec3& top) const;
  TorchHit checkFixture(const Capsule& c, const Vec3& bottom, const Vec3& top) const;
  TorchHit checkBody(const Capsule& c, const Vec3& bottom, const Vec3& top) const;
  TorchHit checkCapsule(const Capsule& c, const Vec3& bottom, const Vec3& top) const;
  Capsule section(std::size_t k) const;

  /// One arm link: the segment between two of computeArmPoints' points (indices into the list
  /// checkArm builds), its radius and what it is.
  struct Link {
    int from = 0;
    int to = 0;
    double radius = 0.0;
    TorchHit::Part part = TorchHit::Part::Column;
  };

  const Cell& cell_;
  const DepositIndex& deposit_;
  std::vector<Section> sections_;
  std::vector<Link> links_;  // empty when the cell does not give the arm
  Section wrist_;            // the wrist link above the TCP; radius 0 when not on the axis
  double bodyTop_ = 0.0;     // table z of the body's top (the table's underside), mm
  double bodyBottom_ = 0.0;  // table z of the body's bottom (the tilt axis), mm
  double bodyRadius_ = 0.0;  // 0: no body
  Pose partToTable_;         // part frame -> table frame
  double tableRadius_ = 0.0;
  FixtureGeometry fixture_;
  std::unique_ptr<Fcl> fcl_;
};

/// The deepest hit of the torch and the arm along a joint-interpolated move (robot joints and
/// positioner angles linear, sampled every 0.25° of the axis that moves most; forward
/// kinematics).
TorchHit checkJointMove(const Cell& cell, const TorchChecker& checker, const MotionPoint& from,
                        const MotionPoint& to);

/// The deepest hit of the arm alone along a move, its joints and positioner angles taken linear
/// between the end points (sampled as checkJointMove). For a move linear in the part frame this
/// is the joint path's chord: over the short arc-off moves the arm's links depart from it by
/// far less than their radii. None when the cell does not give the arm.
TorchHit checkArmAlongMove(const TorchChecker& checker, const MotionPoint& from,
                           const MotionPoint& to);

/// The deepest hit along a move linear in the part frame (tip on the chord, axis turned evenly;
/// samples at most half the envelope radius apart, counting the sweep of the torch's far end).
TorchHit checkLinearMove(const TorchChecker& checker, const TorchEnvelope& torch,
                         const Pose& fromToolInPart, const Pose& toToolInPart);

}  // namespace curvedslicer::detail
