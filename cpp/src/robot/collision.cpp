// Collision check of a planned motion (robot/collision.hpp): the torch envelope against the
// deposit so far and the positioner table, move by move in execution order.
#include "curvedslicer/robot/collision.hpp"

// <cassert> first: FCL 0.7's convex-inl.h uses assert without including it (GCC 16, Debian sid)
#include <cassert>

#include <fcl/fcl.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "torch_checker.hpp"

namespace curvedslicer {

namespace detail {

// ---- one torch pose -------------------------------------------------------------------------

struct TorchChecker::Fcl {
  // envelope sections (capsules, the nozzle a cylinder), then arm links (capsules)
  std::vector<std::shared_ptr<fcl::CollisionGeometryd>> shapes;
  std::shared_ptr<fcl::Cylinderd> table;
  fcl::Transform3d tableInPart = fcl::Transform3d::Identity();
  std::shared_ptr<fcl::Cylinderd> riser;  // null without a riser
  fcl::Transform3d riserInPart = fcl::Transform3d::Identity();
  std::shared_ptr<fcl::Boxd> substrate;  // null without a plate
  fcl::Transform3d substrateInPart = fcl::Transform3d::Identity();
  std::shared_ptr<fcl::Cylinderd> body;  // null without a positioner body
  fcl::Transform3d bodyInPart = fcl::Transform3d::Identity();
};

const char* partName(TorchHit::Part part) {
  switch (part) {
    case TorchHit::Part::Torch:
      return "torch";
    case TorchHit::Part::Column:
      return "robot column";
    case TorchHit::Part::UpperArm:
      return "upper arm";
    case TorchHit::Part::Forearm:
      return "forearm";
    case TorchHit::Part::Wrist:
      return "wrist";
  }
  return "torch";
}

namespace {

/// Pose of an FCL capsule/cylinder (centred, along its z axis) spanning [a, b].
fcl::Transform3d alongSegment(const Vec3& a, const Vec3& b) {
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  const Vec3 d = b - a;
  if (d.norm() > 1e-12) {
    pose.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d).toRotationMatrix();
  }
  pose.translation() = 0.5 * (a + b);
  return pose;
}

/// Deepest FCL contact of two shapes, or a negative value when they do not touch.
double fclPenetration(const fcl::CollisionGeometryd* a, const fcl::Transform3d& poseA,
                      const fcl::CollisionGeometryd* b, const fcl::Transform3d& poseB) {
  fcl::CollisionRequestd request(1, true);
  fcl::CollisionResultd result;
  fcl::collide(a, poseA, b, poseB, request, result);
  if (!result.isCollision()) return -1.0;
  double depth = 0.0;
  for (std::size_t i = 0; i < result.numContacts(); ++i) {
    depth = std::max(depth, result.getContact(i).penetration_depth);
  }
  return depth;
}

/// Signed distance (mm, negative inside) of `p` to the cylinder about the z axis of `radius`
/// between heights z0 and z1 (table frame).
double cylinderDistance(const Vec3& p, double radius, double z0, double z1) {
  const double dr = std::hypot(p.x(), p.y()) - radius;
  const double dz = std::max(z0 - p.z(), p.z() - z1);
  if (dr <= 0.0 && dz <= 0.0) return std::max(dr, dz);
  return std::hypot(std::max(dr, 0.0), std::max(dz, 0.0));
}

/// Signed distance (mm, negative inside) of `p` to the box centred on the z axis with half
/// sides `half` across and heights z0 to z1 (table frame).
double plateDistance(const Vec3& p, double half, double z0, double z1) {
  const Vec3 q(std::abs(p.x()) - half, std::abs(p.y()) - half, std::max(z0 - p.z(), p.z() - z1));
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// The deepest reach of a capsule (axis b–t in the table frame, `radius`) into a solid given
/// by its signed distance, sampling the axis every millimetre: max(radius − distance).
template <class Distance>
double capsuleReach(const Vec3& b, const Vec3& t, double radius, Distance&& distance) {
  double reach = -kInf;
  const int n = std::max(1, static_cast<int>(std::ceil((t - b).norm())));
  for (int k = 0; k <= n; ++k) {
    reach = std::max(reach, radius - distance(b + (t - b) * (static_cast<double>(k) / n)));
  }
  return reach;
}

/// Whether segment [a, b] comes within `reach` of the box (slab clipping of the segment
/// against the box grown by `reach`; conservative at the grown box's corners).
bool segmentNearBox(const Vec3& a, const Vec3& b, const Aabb& box, double reach) {
  if (box.empty()) return false;
  double t0 = 0.0, t1 = 1.0;
  const Vec3 d = b - a;
  for (int i = 0; i < 3; ++i) {
    const double lo = box.min[i] - reach, hi = box.max[i] + reach;
    if (std::abs(d[i]) < 1e-12) {
      if (a[i] < lo || a[i] > hi) return false;
      continue;
    }
    double u0 = (lo - a[i]) / d[i], u1 = (hi - a[i]) / d[i];
    if (u0 > u1) std::swap(u0, u1);
    t0 = std::max(t0, u0);
    t1 = std::min(t1, u1);
    if (t0 > t1) return false;
  }
  return true;
}

void keepDeeper(TorchHit& worst, const TorchHit& hit) {
  if (hit.collides() && (!worst.collides() || hit.depth > worst.depth)) worst = hit;
}

/// The ends of the arm's links in the robot base frame: the column's foot, the column's top
/// (joint 1's axis at joint 2's height), shoulder and elbow moved by the upper arm's offset along
/// joint 2's axis, elbow, forearm root, wrist centre, flange. The foot is where joint 1's axis
/// meets the floor (world z = 0) when the robot stands upright above it (on a pedestal, or with
/// its base frame at joint 2's height), else the base origin.
std::vector<Vec3> armPointsInBase(const RobotDescription& robot, const JointVector& joints) {
  const ArmPoints a = computeArmPoints(robot, joints);
  const Pose& base = robot.base;
  const Vec3 axis = base.linear().col(2);
  const double height = base.translation().z();
  const Vec3 foot =
      axis.z() > 0.5 && height > 0.0 ? Vec3(-Vec3::UnitZ() * (height / axis.z())) : Vec3::Zero();
  const Vec3 offset = robot.links.upperArmOffset * a.side;
  return {foot,    a.column, a.shoulder + offset, a.elbow + offset, a.elbow, a.forearmRoot,
          a.wrist, a.flange};
}

}  // namespace

/// The cone of the torch envelope covered along the axis (heights above the TCP): four
/// quarters, each a capsule with the cone's largest radius over it (one capsule for a
/// cylinder), the lowest starting one radius above the nozzle, and below it the nozzle: a
/// cylinder with the cone's largest radius there, from the nozzle face up to where the
/// capsule's axis starts (a
/// capsule's round end reaching the face would leave the face's rim out; one reaching below it
/// would hit the beads beside the wire). The highest capsule's round end reaches the top.
std::vector<TorchChecker::Section> envelopeSections(const TorchEnvelope& torch) {
  const int n = torch.topRadius == torch.radius ? 1 : 4;
  std::vector<TorchChecker::Section> sections;
  // the lowest capsule's radius, and the cone's largest radius below where its axis starts
  const double lowest = std::max(torch.radius, torch.radius + (torch.topRadius - torch.radius) / n);
  const double nozzle = std::max(
      torch.radius, torch.radius + (torch.topRadius - torch.radius) * lowest / torch.length);
  sections.push_back({torch.stickout, torch.stickout + lowest, nozzle, true});
  for (int k = 0; k < n; ++k) {
    const double h0 = torch.stickout + torch.length * k / n;
    const double h1 = torch.stickout + torch.length * (k + 1) / n;
    const double r = std::max(torch.radius + (torch.topRadius - torch.radius) * k / n,
                              torch.radius + (torch.topRadius - torch.radius) * (k + 1) / n);
    const double from = k == 0 ? h0 + r : h0;
    const double to = k == n - 1 ? h1 - r : h1;
    sections.push_back({from, std::max(from, to), r});
  }
  return sections;
}

TorchChecker::TorchChecker(const Cell& cell, const CollisionGeometry& geometry,
                           const DepositIndex& deposit)
    : cell_(cell),
      deposit_(deposit),
      sections_(envelopeSections(geometry.torch)),
      partToTable_(cell.positioner.tableToPart),
      tableRadius_(geometry.table.tableRadius),
      fixture_(geometry.fixture),
      fcl_(std::make_unique<Fcl>()) {
  for (const Section& section : sections_) {
    if (section.flat) {
      fcl_->shapes.push_back(
          std::make_shared<fcl::Cylinderd>(section.radius, section.to - section.from));
    } else {
      fcl_->shapes.push_back(
          std::make_shared<fcl::Capsuled>(section.radius, section.to - section.from));
    }
  }
  // the arm's links between the points armPointsInBase lists
  const ArmEnvelope& arm = cell.robot.links;
  if (arm.known()) {
    links_ = {{0, 1, arm.column, TorchHit::Part::Column},
              {2, 3, arm.upperArm, TorchHit::Part::UpperArm},
              {4, 5, arm.elbow, TorchHit::Part::Forearm},
              {5, 6, arm.forearm, TorchHit::Part::Forearm},
              {6, 7, arm.wrist, TorchHit::Part::Wrist}};
    // the links' lengths do not depend on the joints: taken at the zero pose
    const std::vector<Vec3> points = armPointsInBase(cell.robot, JointVector{});
    for (const Link& link : links_) {
      fcl_->shapes.push_back(std::make_shared<fcl::Capsuled>(
          link.radius, (points[link.to] - points[link.from]).norm()));
    }
    // the wrist centre and the flange in the tool frame (the wrist centre lies on joint 6's
    // axis, so its place in the flange frame is that of the zero pose): on the tool's z axis,
    // the wrist link is a capsule at fixed heights above the TCP
    const Pose toolInBase = computeFlangePose(cell.robot, JointVector{}) * cell.tool.tcp;
    const Pose baseToTool = toolInBase.inverse();
    const Vec3 wristInTool = baseToTool * points[6];
    const Vec3 flangeInTool = baseToTool * points[7];
    if (wristInTool.head<2>().norm() < 1e-6 && flangeInTool.head<2>().norm() < 1e-6) {
      const double a = -flangeInTool.z(), b = -wristInTool.z();
      wrist_ = {std::min(a, b), std::max(a, b), arm.wrist, false};
    }
  }
  fcl_->table =
      std::make_shared<fcl::Cylinderd>(geometry.table.tableRadius, geometry.table.tableThickness);
  const Pose tableToPartInverse = cell.positioner.tableToPart.inverse();
  // the table disc in the table frame: top face at z = 0, centred on the rotation axis
  fcl::Transform3d tableInTable = fcl::Transform3d::Identity();
  tableInTable.translation() = Vec3(0.0, 0.0, -0.5 * geometry.table.tableThickness);
  fcl_->tableInPart = tableToPartInverse * tableInTable;
  // the body under the table: from its underside down the rotation axis to the tilt axis
  const PositionerDescription& p = cell.positioner;
  const double axisDepth =
      (p.rotationAxisPoint - p.tiltAxisPoint).dot(p.rotationAxisDirection.normalized());
  bodyTop_ = -geometry.table.tableThickness;
  bodyBottom_ = -axisDepth;
  if (geometry.table.bodyRadius > 0.0 && bodyBottom_ < bodyTop_) {
    bodyRadius_ = geometry.table.bodyRadius;
    fcl_->body = std::make_shared<fcl::Cylinderd>(bodyRadius_, bodyTop_ - bodyBottom_);
    fcl::Transform3d bodyInTable = fcl::Transform3d::Identity();
    bodyInTable.translation() = Vec3(0.0, 0.0, 0.5 * (bodyTop_ + bodyBottom_));
    fcl_->bodyInPart = tableToPartInverse * bodyInTable;
  }
  const FixtureGeometry& f = geometry.fixture;
  if (f.hasRiser()) {
    fcl_->riser = std::make_shared<fcl::Cylinderd>(0.5 * f.riserDiameter, f.riserHeight);
    fcl::Transform3d riserInTable = fcl::Transform3d::Identity();
    riserInTable.translation() = Vec3(0.0, 0.0, 0.5 * f.riserHeight);
    fcl_->riserInPart = tableToPartInverse * riserInTable;
  }
  if (f.hasSubstrate()) {
    fcl_->substrate =
        std::make_shared<fcl::Boxd>(f.substrateSize, f.substrateSize, f.substrateThickness);
    fcl::Transform3d plateInTable = fcl::Transform3d::Identity();
    plateInTable.translation() = Vec3(0.0, 0.0, f.riserHeight + 0.5 * f.substrateThickness);
    fcl_->substrateInPart = tableToPartInverse * plateInTable;
  }
}

TorchChecker::~TorchChecker() = default;

TorchChecker::Capsule TorchChecker::section(std::size_t k) const {
  return {k, sections_[k].radius, sections_[k].flat};
}

namespace {

/// The least signed distance (mm, negative inside) of segment [p, q] from the solid cylinder of
/// `radius` about the axis from `b` to `t` (cylinderDistance in the cylinder's own frame): the
/// signed distance of a convex solid is convex, so along the segment it has one minimum
/// (golden-section search).
double segmentCylinderDistance(const Vec3& p, const Vec3& q, const Vec3& b, const Vec3& t,
                               double radius) {
  const Vec3 axis = t - b;
  const double length = axis.norm();
  const Vec3 u = length > 1e-12 ? Vec3(axis / length) : Vec3(Vec3::UnitZ());
  const auto at = [&](double s) {
    const Vec3 x = p + s * (q - p) - b;
    const double h = x.dot(u);
    return cylinderDistance(Vec3((x - h * u).norm(), 0.0, h), radius, 0.0, length);
  };
  constexpr double kGolden = 0.6180339887498949;
  double lo = 0.0, hi = 1.0;
  double x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo);
  double f1 = at(x1), f2 = at(x2);
  for (int k = 0; k < 60 && (hi - lo) * (q - p).norm() > 1e-7; ++k) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1, x1 = hi - kGolden * (hi - lo), f1 = at(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2, x2 = lo + kGolden * (hi - lo), f2 = at(x2);
    }
  }
  return std::min({at(0.0), at(1.0), f1, f2});
}

}  // namespace

double TorchChecker::reachInto(const Capsule& c, const Vec3& b, const Vec3& t,
                               const std::function<double(const Vec3&)>& distance) const {
  if (!c.flat) return capsuleReach(b, t, c.radius, distance);
  // the cylinder's surface: its two end discs and its side, every mm along the axis and every
  // 15° around, each ring from the axis out to the rim (the solids are convex: a cylinder that
  // reaches into one has a sample point of its surface in it, up to the sampling)
  const Vec3 axis = t - b;
  const double length = axis.norm();
  const Vec3 u = length > 1e-12 ? Vec3(axis / length) : Vec3(Vec3::UnitZ());
  const Vec3 e1 = u.unitOrthogonal();
  const Vec3 e2 = u.cross(e1);
  double reach = -kInf;
  const int rings = std::max(1, static_cast<int>(std::ceil(length)));
  const int radial = std::max(1, static_cast<int>(std::ceil(c.radius)));
  for (int k = 0; k <= rings; ++k) {
    const Vec3 centre = b + axis * (static_cast<double>(k) / rings);
    const bool end = k == 0 || k == rings;
    reach = std::max(reach, -distance(centre));
    for (int j = 0; j < 24; ++j) {
      const double phi = 2.0 * 3.14159265358979323846 * j / 24;
      const Vec3 out = std::cos(phi) * e1 + std::sin(phi) * e2;
      for (int i = end ? 1 : radial; i <= radial; ++i) {
        reach = std::max(reach, -distance(centre + out * (c.radius * i / radial)));
      }
    }
  }
  return reach;
}

TorchHit TorchChecker::checkDepositCylinder(const Capsule& c, const Vec3& bottom, const Vec3& top,
                                            bool firstOnly) const {
  // the cylinder lies inside the capsule of its axis and radius: the beads within that reach
  // are the candidates, each measured exactly
  TorchHit worst;
  const double beadRadius = deposit_.beadRadius();
  const Vec3 axis = top - bottom;
  const double length = axis.norm();
  const Vec3 u = length > 1e-12 ? Vec3(axis / length) : Vec3(Vec3::UnitZ());
  deposit_.forEachWithin(
      bottom, top, c.radius,
      [&](std::size_t s, double) {
        const DepositSegment& bead = deposit_.segments()[s];
        // a bead wholly below the nozzle face or above the cylinder's top by more than its radius
        // cannot touch it (most candidates: the beads under the torch)
        const double ha = (bead.a - bottom).dot(u), hb = (bead.b - bottom).dot(u);
        if (std::max(ha, hb) <= -beadRadius || std::min(ha, hb) >= length + beadRadius) return true;
        const double depth =
            beadRadius - segmentCylinderDistance(bead.a, bead.b, bottom, top, c.radius);
        if (depth <= 0.0 || (worst.collides() && depth <= worst.depth)) return true;
        worst = {TorchHit::Object::Deposit, depth, s};
        return !firstOnly;
      },
      u, u.dot(bottom) - beadRadius);
  return worst;
}

TorchHit TorchChecker::checkCapsule(const Capsule& c, const Vec3& bottom, const Vec3& top) const {
  TorchHit worst;
  keepDeeper(worst, checkDeposit(c, bottom, top));
  keepDeeper(worst, checkTable(c, bottom, top));
  keepDeeper(worst, checkFixture(c, bottom, top));
  keepDeeper(worst, checkBody(c, bottom, top));
  return worst;
}

TorchHit TorchChecker::check(const Vec3& tip, const Vec3& up) const {
  TorchHit worst;
  for (std::size_t k = 0; k < sections_.size(); ++k) {
    keepDeeper(worst,
               checkCapsule(section(k), tip + sections_[k].from * up, tip + sections_[k].to * up));
  }
  return worst;
}

bool TorchChecker::collides(const Vec3& tip, const Vec3& up) const {
  for (std::size_t k = 0; k < sections_.size(); ++k) {
    const Vec3 bottom = tip + sections_[k].from * up;
    const Vec3 top = tip + sections_[k].to * up;
    const Capsule c = section(k);
    if (checkTable(c, bottom, top).collides() || checkFixture(c, bottom, top).collides() ||
        checkBody(c, bottom, top).collides()) {
      return true;
    }
    if (!segmentNearBox(bottom, top, deposit_.extent(), c.radius + deposit_.beadRadius())) continue;
    if (c.flat ? checkDepositCylinder(c, bottom, top, true).collides()
               : deposit_.anyWithin(bottom, top, sections_[k].radius)) {
      return true;
    }
  }
  return false;
}

bool TorchChecker::collidesWithWrist(const Vec3& tip, const Vec3& up) const {
  if (collides(tip, up)) return true;
  if (!wristOnAxis()) return false;
  const Vec3 bottom = tip + wrist_.from * up;
  const Vec3 top = tip + wrist_.to * up;
  const Capsule c{sections_.size() + links_.size() - 1, wrist_.radius, false};
  return checkTable(c, bottom, top).collides() || checkFixture(c, bottom, top).collides() ||
         checkBody(c, bottom, top).collides() ||
         (segmentNearBox(bottom, top, deposit_.extent(), c.radius + deposit_.beadRadius()) &&
          deposit_.anyWithin(bottom, top, c.radius));
}

TorchHit TorchChecker::checkArm(const JointVector& joints, double a1, double a2) const {
  if (links_.empty()) return {};
  const Pose baseToPart = computePartInWorld(cell_.positioner, a1, a2).inverse() * cell_.robot.base;
  std::vector<Vec3> points = armPointsInBase(cell_.robot, joints);
  for (Vec3& x : points) x = baseToPart * x;
  TorchHit worst;
  for (std::size_t k = 0; k < links_.size(); ++k) {
    const Link& link = links_[k];
    TorchHit hit =
        checkCapsule({sections_.size() + k, link.radius}, points[link.from], points[link.to]);
    hit.part = link.part;
    keepDeeper(worst, hit);
  }
  return worst;
}

TorchHit TorchChecker::checkDeposit(const Capsule& c, const Vec3& bottom, const Vec3& top) const {
  // the deposit's box first: arm links are long and wide, and mostly far from the part
  if (!segmentNearBox(bottom, top, deposit_.extent(), c.radius + deposit_.beadRadius())) {
    return {};
  }
  if (c.flat) {
    const TorchHit hit = checkDepositCylinder(c, bottom, top, false);
    if (!hit.collides()) return {};
    const DepositSegment& bead = deposit_.segments()[hit.segment];
    const fcl::Capsuled beadShape(deposit_.beadRadius(), (bead.b - bead.a).norm());
    if (fclPenetration(fcl_->shapes[c.shape].get(), alongSegment(bottom, top), &beadShape,
                       alongSegment(bead.a, bead.b)) < 0.0) {
      return {};  // grazing contact FCL does not confirm
    }
    return hit;
  }
  // exact capsule distances find the nearest bead; FCL confirms the contact and its depth
  const DepositHit near = deposit_.nearest(bottom, top, c.radius);
  if (!near.found()) return {};
  const DepositSegment& bead = deposit_.segments()[near.segment];
  const fcl::Capsuled beadShape(deposit_.beadRadius(), (bead.b - bead.a).norm());
  const double depth = fclPenetration(fcl_->shapes[c.shape].get(), alongSegment(bottom, top),
                                      &beadShape, alongSegment(bead.a, bead.b));
  if (depth < 0.0) return {};  // grazing contact FCL does not confirm
  // the depth of two capsules in closed form (FCL 0.7's capsule/capsule contact depth is not
  // the penetration: seen 8.8 mm for 3.85 mm)
  return {TorchHit::Object::Deposit, c.radius - near.distance, near.segment};
}

TorchHit TorchChecker::checkTable(const Capsule& c, const Vec3& bottom, const Vec3& top) const {
  // cheap rejection in the table frame: the capsule entirely above the table surface or
  // entirely outside its radius
  const double radius = c.radius;
  const Vec3 b = partToTable_ * bottom;
  const Vec3 t = partToTable_ * top;
  if (std::min(b.z(), t.z()) - radius > 0.0) return {};
  const double radial =
      pointSegmentDistance(Vec3::Zero(), Vec3(b.x(), b.y(), 0.0), Vec3(t.x(), t.y(), 0.0));
  if (radial - radius > tableRadius_) return {};
  const double fclDepth = fclPenetration(fcl_->shapes[c.shape].get(), alongSegment(bottom, top),
                                         fcl_->table.get(), fcl_->tableInPart);
  if (fclDepth < 0.0) return {};
  // depth: how far the envelope reaches below the table surface over the disc (axis sampled
  // every mm); FCL's capsule/cylinder depth is the EPA translation, which can be the disc's
  // radius for a torch lying across it. At the rim only, FCL's value.
  double depth = -kInf;
  if (c.flat) {
    depth = reachInto(
        c, b, t, [&](const Vec3& x) { return x.head<2>().norm() <= tableRadius_ ? x.z() : kInf; });
  } else {
    const int n = std::max(1, static_cast<int>(std::ceil((t - b).norm())));
    for (int k = 0; k <= n; ++k) {
      const Vec3 x = b + (t - b) * (static_cast<double>(k) / n);
      if (x.head<2>().norm() <= tableRadius_) depth = std::max(depth, radius - x.z());
    }
  }
  return {TorchHit::Object::Table, depth > 0.0 ? depth : fclDepth, 0};
}

TorchHit TorchChecker::checkBody(const Capsule& c, const Vec3& bottom, const Vec3& top) const {
  if (!fcl_->body) return {};
  const Vec3 b = partToTable_ * bottom;
  const Vec3 t = partToTable_ * top;
  // cheap rejection: the capsule entirely above the body's top or outside its radius
  if (std::min(b.z(), t.z()) - c.radius > bodyTop_) return {};
  const double radial =
      pointSegmentDistance(Vec3::Zero(), Vec3(b.x(), b.y(), 0.0), Vec3(t.x(), t.y(), 0.0));
  if (radial - c.radius > bodyRadius_) return {};
  const double reach = reachInto(c, b, t, [&](const Vec3& x) {
    return cylinderDistance(x, bodyRadius_, bodyBottom_, bodyTop_);
  });
  if (reach <= -1e-9) return {};
  const double fclDepth = fclPenetration(fcl_->shapes[c.shape].get(), alongSegment(bottom, top),
                                         fcl_->body.get(), fcl_->bodyInPart);
  if (fclDepth < 0.0) return {};
  return {TorchHit::Object::PositionerBody, reach > 0.0 ? reach : fclDepth, 0};
}

TorchHit TorchChecker::checkFixture(const Capsule& c, const Vec3& bottom, const Vec3& top) const {
  if (!fcl_->riser && !fcl_->substrate) return {};
  const double radius = c.radius;
  const Vec3 b = partToTable_ * bottom;
  const Vec3 t = partToTable_ * top;
  // cheap rejection: the capsule entirely above the fixture's top
  if (std::min(b.z(), t.z()) - radius > fixture_.top()) return {};
  TorchHit worst;
  // the depth: how far the capsule reaches into the solid (its axis sampled every mm, in closed
  // form); FCL confirms the contact (a grazing one it does not confirm is none) and gives the
  // depth where the samples miss a shallow touch
  const auto confirm = [&](TorchHit::Object object, const fcl::CollisionGeometryd* shape,
                           const fcl::Transform3d& pose, double reach) {
    if (reach <= -1e-9) return;
    const double fclDepth =
        fclPenetration(fcl_->shapes[c.shape].get(), alongSegment(bottom, top), shape, pose);
    if (fclDepth < 0.0) return;
    const double depth = reach > 0.0 ? reach : fclDepth;
    if (!worst.collides() || depth > worst.depth) worst = {object, depth, 0};
  };
  if (fcl_->riser) {
    const double r = 0.5 * fixture_.riserDiameter, h = fixture_.riserHeight;
    confirm(TorchHit::Object::Riser, fcl_->riser.get(), fcl_->riserInPart,
            reachInto(c, b, t, [&](const Vec3& x) { return cylinderDistance(x, r, 0.0, h); }));
  }
  if (fcl_->substrate) {
    const double half = 0.5 * fixture_.substrateSize;
    const double z0 = fixture_.riserHeight, z1 = fixture_.top();
    confirm(TorchHit::Object::Substrate, fcl_->substrate.get(), fcl_->substrateInPart,
            reachInto(c, b, t, [&](const Vec3& x) { return plateDistance(x, half, z0, z1); }));
  }
  return worst;
}

namespace {

/// TCP pose in the part frame of joints and positioner angles (forward kinematics).
Pose toolInPartAt(const Cell& cell, const JointVector& joints, double a1, double a2) {
  const Pose toolInWorld = cell.robot.base * computeFlangePose(cell.robot, joints) * cell.tool.tcp;
  return computePartInWorld(cell.positioner, a1, a2).inverse() * toolInWorld;
}

}  // namespace

namespace {

/// Samples of a joint-interpolated move: every 0.25° of the axis that moves most.
int jointMoveSamples(const MotionPoint& from, const MotionPoint& to) {
  constexpr double kStep = 0.25 * 3.14159265358979323846 / 180.0;
  double span = std::max(std::abs(to.a1 - from.a1), std::abs(to.a2 - from.a2));
  for (int j = 0; j < 6; ++j) span = std::max(span, std::abs(to.joints[j] - from.joints[j]));
  return std::max(1, static_cast<int>(std::ceil(span / kStep)));
}

JointVector jointsBetween(const MotionPoint& from, const MotionPoint& to, double t) {
  JointVector q;
  for (int j = 0; j < 6; ++j) q[j] = from.joints[j] + t * (to.joints[j] - from.joints[j]);
  return q;
}

}  // namespace

TorchHit checkJointMove(const Cell& cell, const TorchChecker& checker, const MotionPoint& from,
                        const MotionPoint& to) {
  const int n = jointMoveSamples(from, to);
  TorchHit worst;
  for (int k = 1; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    const JointVector q = jointsBetween(from, to, t);
    const double a1 = from.a1 + t * (to.a1 - from.a1), a2 = from.a2 + t * (to.a2 - from.a2);
    Vec3 tip, up;
    torchAxisOf(toolInPartAt(cell, q, a1, a2), tip, up);
    keepDeeper(worst, checker.check(tip, up));
    keepDeeper(worst, checker.checkArm(q, a1, a2));
  }
  return worst;
}

TorchHit checkArmAlongMove(const TorchChecker& checker, const MotionPoint& from,
                           const MotionPoint& to) {
  if (!checker.checksArm()) return {};
  const int n = jointMoveSamples(from, to);
  TorchHit worst;
  for (int k = 1; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    keepDeeper(worst, checker.checkArm(jointsBetween(from, to, t), from.a1 + t * (to.a1 - from.a1),
                                       from.a2 + t * (to.a2 - from.a2)));
  }
  return worst;
}

TorchHit checkLinearMove(const TorchChecker& checker, const TorchEnvelope& torch,
                         const Pose& fromToolInPart, const Pose& toToolInPart) {
  Vec3 tip0, up0, tip1, up1;
  torchAxisOf(fromToolInPart, tip0, up0);
  torchAxisOf(toToolInPart, tip1, up1);
  const double turn = std::atan2(up0.cross(up1).norm(), up0.dot(up1));
  const double sweep = (tip1 - tip0).norm() + turn * (torch.stickout + torch.length);
  const int n = std::max(1, static_cast<int>(std::ceil(sweep / (0.5 * torch.radius))));
  TorchHit worst;
  for (int k = 1; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    Vec3 up = (1.0 - t) * up0 + t * up1;
    up = up.norm() > 1e-12 ? Vec3(up.normalized()) : up1;
    keepDeeper(worst, checker.check(tip0 + t * (tip1 - tip0), up));
  }
  return worst;
}

}  // namespace detail

namespace {

using detail::DepositIndex;
using detail::DepositSegment;
using detail::TorchChecker;
using detail::TorchHit;

constexpr std::size_t kNamedCollisions = 5;

std::string collisionFmt(double value, int precision = 2) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(precision);
  out << value;
  return out.str();
}

/// Part-frame box of every path point, grown by `margin`.
Aabb pathBounds(const MotionPlan& motion, double margin) {
  Aabb box;
  for (const MotionPoint& m : motion.points) {
    if (m.kind == MoveKind::Path) box.extend(m.position);
  }
  if (box.empty()) box.extend(Vec3::Zero());
  box.min -= Vec3::Constant(margin);
  box.max += Vec3::Constant(margin);
  return box;
}

/// The worst hit along the move arriving at points[i]: joint-interpolated from or to the home
/// pose, linear in the part frame otherwise.
TorchHit checkArcOffMove(const MotionPlan& motion, std::size_t i, const Cell& cell,
                         const TorchChecker& checker, const TorchEnvelope& torch) {
  const MotionPoint& from = motion.points[i - 1];
  const MotionPoint& to = motion.points[i];
  if (from.kind == MoveKind::Home || to.kind == MoveKind::Home) {
    return detail::checkJointMove(cell, checker, from, to);
  }
  TorchHit hit = detail::checkLinearMove(checker, torch, from.toolInPart, to.toolInPart);
  const TorchHit arm = detail::checkArmAlongMove(checker, from, to);
  if (arm.collides() && (!hit.collides() || arm.depth > hit.depth)) hit = arm;
  return hit;
}

std::string describeHit(const TorchHit& hit, const DepositIndex& deposit) {
  const std::string part = std::string(detail::partName(hit.part)) + " vs ";
  if (hit.object == TorchHit::Object::Table) return part + "positioner table";
  if (hit.object == TorchHit::Object::PositionerBody) return part + "positioner body";
  if (hit.object == TorchHit::Object::Riser) return part + "riser";
  if (hit.object == TorchHit::Object::Substrate) return part + "substrate plate";
  const DepositSegment& s = deposit.segments()[hit.segment];
  return part + "deposit of layer " + std::to_string(s.layer) + " path " + std::to_string(s.path);
}

CollisionObstacle obstacleOf(const TorchHit& hit) {
  switch (hit.object) {
    case TorchHit::Object::Table:
      return CollisionObstacle::Table;
    case TorchHit::Object::Riser:
      return CollisionObstacle::Riser;
    case TorchHit::Object::Substrate:
      return CollisionObstacle::Substrate;
    case TorchHit::Object::PositionerBody:
      return CollisionObstacle::PositionerBody;
    default:
      return CollisionObstacle::Deposit;
  }
}

/// What would clear the remaining collisions: a riser as deep as the deepest reach into the
/// table (placement auto), a wider torch window against the deposit, the fixture smaller.
std::string collisionAdvice(const MotionPlan& motion, const ProcessDescription& process) {
  const double maxTorchAngle = process.maxTorchAngle;
  double table = 0.0;
  bool deposit = false, fixture = false, body = false;
  for (const CollisionReport& c : motion.collisions) {
    body = body || c.obstacle == CollisionObstacle::PositionerBody;
    if (c.obstacle == CollisionObstacle::Table) table = std::max(table, c.depth);
    deposit = deposit || c.obstacle == CollisionObstacle::Deposit;
    fixture = fixture || c.obstacle == CollisionObstacle::Riser ||
              c.obstacle == CollisionObstacle::Substrate;
  }
  std::string advice;
  const auto add = [&](const std::string& text) { advice += (advice.empty() ? "" : "; ") + text; };
  if (table > 0.0) {
    add("raise the part on a riser of at least " + collisionFmt(table + 2.0, 1) +
        " mm (--placement auto finds the lowest)");
  }
  if (deposit) {
    add(maxTorchAngle < 0.785
            ? "widen the torch window (the cell's process/max_torch_angle_deg, "
              "now " +
                  collisionFmt(maxTorchAngle * 180.0 / 3.14159265358979323846, 1) +
                  " deg, at most 45), change the path order"
            : "change the path order");
  }
  if ((deposit || fixture) && process.maxGravityDeviation < 0.785) {
    add("allow a larger gravity deviation (the cell's process/max_gravity_deviation_deg, now " +
        collisionFmt(process.maxGravityDeviation * 180.0 / 3.14159265358979323846, 1) +
        " deg, at most 45)");
  }
  if (fixture) add("use a narrower riser or a smaller substrate plate (positioner/fixture)");
  if (body) {
    add("raise the part further from the table (a riser) or check the positioner's body radius "
        "(positioner/geometry/body_radius_mm)");
  }
  return advice + (advice.empty() ? "" : ", ") + "use a slimmer torch envelope";
}

void reportCollisions(MotionPlan& motion, const MotionOptions& options,
                      const ProcessDescription& process) {
  if (motion.collisions.empty()) return;
  std::string list;
  for (std::size_t k = 0; k < std::min(kNamedCollisions, motion.collisions.size()); ++k) {
    const CollisionReport& c = motion.collisions[k];
    list += (k ? "; " : "") + describeMove(motion, c.point) + ": " + c.what + " by " +
            collisionFmt(c.depth) + " mm";
  }
  if (motion.collisions.size() > kNamedCollisions) list += "; ...";
  const bool arm = std::any_of(motion.collisions.begin(), motion.collisions.end(),
                               [](const CollisionReport& c) { return c.what.rfind("torch ", 0); });
  const std::string text = std::string(arm ? "torch or robot arm collide" : "torch collides") +
                           " on " + std::to_string(motion.collisions.size()) + " move(s): " + list;
  if (!options.allowCollisions) {
    throw InvalidInput(text + "; " + collisionAdvice(motion, process) +
                       ", or allow collisions (--allow-collisions) to export anyway");
  }
  motion.warnings.push_back(text + " (allowed: --allow-collisions)");
}

}  // namespace

double depositBeadRadius(const PlanParameters& parameters) {
  if (parameters.beadSpacing > 0.0) return 0.5 * parameters.beadSpacing;
  if (parameters.layerThickness > 0.0) return parameters.layerThickness;
  return 1.0;
}

std::string describeMove(const MotionPlan& motion, std::size_t index) {
  const MotionPoint& m = motion.points[index];
  const std::string path = "layer " + std::to_string(m.layer) + " path " + std::to_string(m.path);
  switch (m.kind) {
    case MoveKind::Path:
      if (m.arcOn) return path + " point " + std::to_string(m.index) + " (weld move)";
      return path + " point " + std::to_string(m.index) + " (approach onto the path start)";
    case MoveKind::Retract:
      return "retract from " + path;
    case MoveKind::Travel:
      return "travel move towards " + path;
    case MoveKind::Approach:
      return "approach above " + path;
    case MoveKind::Home:
      return index == 0 ? "home pose" : "move to the home pose after " + path;
  }
  return path;
}

CollisionGeometry collisionGeometryOf(const Cell& cell) {
  return {cell.tool.envelope, cell.positioner.geometry, cell.positioner.fixture};
}

void validateCollisionGeometry(const CollisionGeometry& geometry, double beadRadius) {
  const TorchEnvelope& torch = geometry.torch;
  const double widest = std::max(torch.radius, torch.topRadius);
  if (!(torch.stickout > 0.0 && torch.radius > 0.0 && torch.topRadius > 0.0 &&
        torch.length > 2.0 * widest && geometry.table.tableRadius > 0.0 &&
        geometry.table.tableThickness > 0.0 && beadRadius > 0.0)) {
    throw InvalidInput(
        "torch envelope, table and bead sizes must be positive (envelope length "
        "over twice its widest radius): stick-out " +
        collisionFmt(torch.stickout) + ", radius " + collisionFmt(torch.radius) + " to " +
        collisionFmt(torch.topRadius) + ", length " + collisionFmt(torch.length) + ", table " +
        collisionFmt(geometry.table.tableRadius) + " x " +
        collisionFmt(geometry.table.tableThickness) + ", bead radius " + collisionFmt(beadRadius) +
        " mm; fix the cell's tool envelope / positioner geometry");
  }
}

void checkMotionCollisions(MotionPlan& motion, const Cell& cell, const CollisionGeometry& geometry,
                           double beadRadius, const MotionOptions& options,
                           const Progress& progress) {
  validateCollisionGeometry(geometry, beadRadius);
  const TorchEnvelope& torch = geometry.torch;
  // a re-check (another envelope) replaces the verdicts of an earlier one, flags included
  motion.collisions.clear();
  for (MotionPoint& m : motion.points) m.flags &= ~static_cast<std::uint32_t>(kMotionCollision);
  DepositIndex deposit(pathBounds(motion, 0.0), beadRadius, 2.0 * (torch.radius + beadRadius));
  const TorchChecker checker(cell, geometry, deposit);
  progress.report(0.0, "collisions");
  for (std::size_t i = 1; i < motion.points.size(); ++i) {
    if (i % 16384 == 0) {
      progress.report(static_cast<double>(i) / static_cast<double>(motion.points.size()),
                      "collisions");
    }
    MotionPoint& m = motion.points[i];
    TorchHit hit;
    if (m.arcOn) {
      Vec3 tip, up;
      detail::torchAxisOf(m.toolInPart, tip, up);
      hit = checker.check(tip, up);
      const TorchHit arm = checker.checkArm(m.joints, m.a1, m.a2);
      if (arm.collides() && (!hit.collides() || arm.depth > hit.depth)) hit = arm;
    } else {
      hit = checkArcOffMove(motion, i, cell, checker, torch);
    }
    if (hit.collides()) {
      m.flags |= kMotionCollision;
      motion.collisions.push_back({i, describeHit(hit, deposit), hit.depth, obstacleOf(hit)});
    }
    if (m.arcOn) {
      const MotionPoint& prev = motion.points[i - 1];
      deposit.add({prev.position, m.position, m.layer, m.path}, prev.pathStart);
    }
  }
  progress.report(1.0, "collisions");
  reportCollisions(motion, options, cell.process);
}

}  // namespace curvedslicer
