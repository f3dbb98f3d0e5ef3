// Arc-off moves that clear the part (robot/travel.hpp). Phases: home, per path the arc-off
// route into it (retract, travel, approach), the path itself, home.
#include "curvedslicer/robot/travel.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "torch_checker.hpp"

namespace curvedslicer {

namespace {

using detail::DepositIndex;
using detail::TorchChecker;

std::string fmt(double value, int precision = 2) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(precision);
  out << value;
  return out.str();
}

/// A candidate arc-off route in the part frame: retract top, via points, approach top.
struct Route {
  std::vector<Vec3> points;   // TCP, part frame; front = retract top, back = approach top
  std::vector<double> along;  // arc-length fraction of each point (0 .. 1)
};

/// The direction (part frame, unit) an arc-off move leaves a path point along: back up the
/// torch's own axis. The layer normal can differ from it by any angle on small layer patches
/// (a blade tip's islands), and a move along it then drives the torch sideways or into the table.
Vec3 retreatOf(const MotionPoint& at) {
  Vec3 tip, up;
  detail::torchAxisOf(at.toolInPart, tip, up);
  return up.norm() > 1e-9 ? Vec3(up.normalized()) : at.normal;
}

Route makeRoute(std::vector<Vec3> points) {
  Route route;
  route.points = std::move(points);
  route.along.assign(route.points.size(), 0.0);
  double total = 0.0;
  for (std::size_t k = 1; k < route.points.size(); ++k) {
    total += (route.points[k] - route.points[k - 1]).norm();
    route.along[k] = total;
  }
  for (double& a : route.along) a = total > 0.0 ? a / total : 0.0;
  if (route.along.size() > 1) route.along.back() = 1.0;
  return route;
}

class TravelPlanner {
 public:
  TravelPlanner(MotionPlan& motion, const Cell& cell, const TravelSetup& setup, double beadRadius,
                const MotionOptions& options)
      : motion_(motion),
        cell_(cell),
        setup_(setup),
        options_(options),
        radius_(beadRadius),
        step_(0.5 * options.clearance),
        baseInverse_(cell.robot.base.inverse()),
        tcpInverse_(cell.tool.tcp.inverse()),
        deposit_(pathBounds(motion), beadRadius,
                 std::max(options.clearance, setup.geometry.torch.radius) + beadRadius),
        checker_(cell, setup.geometry, deposit_) {}

  void run(const Progress& progress);

 private:
  static Aabb pathBounds(const MotionPlan& motion);
  void appendHome(const MotionPoint& neighbour);
  void clearHomeMove(std::size_t home, std::size_t neighbour, const MotionPoint& owner);
  void appendArcOff(const MotionPoint* from, const MotionPoint* to);
  MotionPoint axisPoint(MoveKind kind, const MotionPoint& at);
  void appendPath(const MotionPathSpan& span, std::vector<MotionPathSpan>& spans);
  double clearHeight(const MotionPoint& at) const;
  std::optional<std::vector<MotionPoint>> tryRoute(const Route& route, const MotionPoint& from,
                                                   const MotionPoint& to,
                                                   const MotionPoint& retract, double* shortfall);
  bool routeClears(const Route& route, const MotionPoint& from, const MotionPoint& to,
                   double* shortfall) const;
  MotionPoint arcOffPoint(MoveKind kind, const MotionPoint& owner, const Vec3& position, double a1,
                          double a2, const Mat3& worldRotation) const;
  Pose toolInPart(const Vec3& position, double a1, double a2, const Mat3& worldRotation) const;
  bool solveJoints(MotionPoint& m, const JointVector& reference, int configuration) const;
  void unreachable(MotionPoint& m, const JointVector& reference, const std::string& move);

  MotionPlan& motion_;
  const Cell& cell_;
  const TravelSetup& setup_;
  const MotionOptions& options_;
  const double radius_;
  const double step_;
  const Pose baseInverse_;
  const Pose tcpInverse_;
  DepositIndex deposit_;
  TorchChecker checker_;
  std::vector<MotionPoint> out_;
  std::vector<std::string> shortWarnings_;
  std::size_t shortCount_ = 0;
};

Aabb TravelPlanner::pathBounds(const MotionPlan& motion) {
  Aabb box;
  for (const MotionPoint& m : motion.points) box.extend(m.position);
  return box;
}

void TravelPlanner::run(const Progress& progress) {
  progress.report(0.0, "travel");
  const std::vector<MotionPoint>& points = motion_.points;  // the spans index these
  std::vector<MotionPathSpan> spans;
  out_.reserve(points.size() + 4 * motion_.paths.size() + 2);
  for (std::size_t s = 0; s < motion_.paths.size(); ++s) {
    const MotionPathSpan& span = motion_.paths[s];
    const MotionPoint& start = points[span.begin];
    if (s == 0) {
      if (options_.addHome) appendHome(start);
      appendArcOff(nullptr, &start);
      if (options_.addHome) clearHomeMove(0, 1, start);
    } else {
      appendArcOff(&points[motion_.paths[s - 1].end - 1], &start);
    }
    appendPath(span, spans);
    progress.report(static_cast<double>(s + 1) / static_cast<double>(motion_.paths.size()),
                    "travel");
  }
  if (!motion_.paths.empty()) {
    const MotionPoint& last = points[motion_.paths.back().end - 1];
    appendArcOff(&last, nullptr);
    if (options_.addHome) {
      appendHome(out_.back());
      clearHomeMove(out_.size() - 1, out_.size() - 2, last);
    }
  }
  if (shortCount_ > 0) {
    std::string list;
    for (const auto& w : shortWarnings_) list += (list.empty() ? "" : "; ") + w;
    motion_.warnings.push_back("travel keeps less than the clearance of " +
                               fmt(options_.clearance) + " mm on " + std::to_string(shortCount_) +
                               " arc-off move(s) (no lift up to " + fmt(setup_.maxLift) +
                               " mm clears): " + list);
  }
  motion_.points = std::move(out_);
  motion_.paths = std::move(spans);
}

/// Copies one path's points and adds its welded segments to the deposit.
void TravelPlanner::appendPath(const MotionPathSpan& span, std::vector<MotionPathSpan>& spans) {
  MotionPathSpan moved = span;
  moved.begin = out_.size();
  for (std::size_t k = span.begin; k < span.end; ++k) {
    const MotionPoint& m = motion_.points[k];
    if (k > span.begin && m.arcOn) {
      const MotionPoint& prev = motion_.points[k - 1];
      deposit_.add({prev.position, m.position, m.layer, m.path}, k == span.begin + 1);
    }
    out_.push_back(m);
  }
  moved.end = out_.size();
  spans.push_back(moved);
}

/// TCP pose in the part frame for a part-frame position, positioner angles and a world
/// orientation of the tool.
Pose TravelPlanner::toolInPart(const Vec3& position, double a1, double a2,
                               const Mat3& worldRotation) const {
  const Pose partInWorld = computePartInWorld(cell_.positioner, a1, a2);
  Pose toolInWorld = Pose::Identity();
  toolInWorld.linear() = worldRotation;
  toolInWorld.translation() = partInWorld * position;
  return partInWorld.inverse() * toolInWorld;
}

/// Lowest height up the point's torch axis (from clearance + bead radius up) where the TCP
/// keeps the clearance from the deposit and the torch clears; the highest tried if none does.
double TravelPlanner::clearHeight(const MotionPoint& at) const {
  const Mat3 rotation = at.toolInWorld.linear();
  double h = options_.clearance + radius_;
  for (; h <= options_.clearance + radius_ + setup_.maxLift; h += step_) {
    const Vec3 p = at.position + h * retreatOf(at);
    if (deposit_.anyWithin(p, p, options_.clearance)) continue;
    Vec3 tip, up;
    detail::torchAxisOf(toolInPart(p, at.a1, at.a2, rotation), tip, up);
    if (!checker_.check(tip, up).collides()) return h;
  }
  return h - step_;
}

/// True when every route segment keeps the clearance (TCP) and the torch clears along it;
/// `shortfall` gets the smallest TCP distance found when it does not.
bool TravelPlanner::routeClears(const Route& route, const MotionPoint& from, const MotionPoint& to,
                                double* shortfall) const {
  for (std::size_t k = 1; k < route.points.size(); ++k) {
    detail::DepositHit hit;
    if (deposit_.anyWithin(route.points[k - 1], route.points[k], options_.clearance, &hit)) {
      *shortfall = std::min(*shortfall, hit.distance);
      return false;
    }
  }
  const Eigen::Quaterniond q0(from.toolInWorld.linear());
  const Eigen::Quaterniond q1(to.toolInWorld.linear());
  const TorchEnvelope& torch = setup_.geometry.torch;
  const double sampleStep = 0.5 * torch.radius;
  for (std::size_t k = 1; k < route.points.size(); ++k) {
    const Vec3& p = route.points[k - 1];
    const Vec3& q = route.points[k];
    // samples as the collision check takes them: the tip's way plus the sweep of the torch's far
    // end where the orientation turns along the segment
    const double turn =
        q0.slerp(route.along[k - 1], q1).angularDistance(q0.slerp(route.along[k], q1));
    const double sweep = (q - p).norm() + turn * (torch.stickout + torch.length);
    const int n = std::max(1, static_cast<int>(std::ceil(sweep / sampleStep)));
    for (int i = 0; i <= n; ++i) {
      const double u = static_cast<double>(i) / n;
      const double t = route.along[k - 1] + u * (route.along[k] - route.along[k - 1]);
      const Pose pose =
          toolInPart(p + u * (q - p), from.a1 + t * (to.a1 - from.a1),
                     from.a2 + t * (to.a2 - from.a2), q0.slerp(t, q1).toRotationMatrix());
      Vec3 tip, up;
      detail::torchAxisOf(pose, tip, up);
      if (checker_.check(tip, up).collides()) return false;
    }
  }
  return true;
}

MotionPoint TravelPlanner::arcOffPoint(MoveKind kind, const MotionPoint& owner,
                                       const Vec3& position, double a1, double a2,
                                       const Mat3& worldRotation) const {
  MotionPoint m;
  m.kind = kind;
  m.layer = owner.layer;
  m.path = owner.path;
  m.index = -1;
  m.position = position;
  m.normal = owner.normal;
  m.deposition = owner.deposition;
  m.usedDeposition = owner.usedDeposition;
  m.a1 = a1;
  m.a2 = a2;
  const Pose partInWorld = computePartInWorld(cell_.positioner, a1, a2);
  m.toolInWorld = Pose::Identity();
  m.toolInWorld.linear() = worldRotation;
  m.toolInWorld.translation() = partInWorld * position;
  m.toolInRobotBase = baseInverse_ * m.toolInWorld;
  m.toolInTable = computeTableInWorld(cell_.positioner, a1, a2).inverse() * m.toolInWorld;
  m.toolInPart = partInWorld.inverse() * m.toolInWorld;
  // the torch's angle off gravity (carried from a tilted path end or start; no travel/work split)
  const Vec3 z = worldRotation.col(2);
  const Vec3 g = cell_.gravity.normalized();
  m.torchAngle = std::atan2(z.cross(g).norm(), z.dot(g));
  if (m.torchAngle < 1e-9) m.torchAngle = 0.0;
  m.speed = cell_.process.travelSpeed;
  return m;
}

/// IK nearest `reference` within the joint limits, preferring `configuration`; false if no
/// solution lies within the limits.
bool TravelPlanner::solveJoints(MotionPoint& m, const JointVector& reference,
                                int configuration) const {
  const IkResult ik =
      solveInverseKinematics(cell_.robot, m.toolInRobotBase * tcpInverse_, reference[3]);
  double bestCost = kInf;
  for (const IkSolution& sol : ik.solutions) {
    JointVector q = sol.joints;
    if (!unwrapJoints(cell_.robot, q, reference)) continue;
    double cost = sol.configuration == configuration ? 0.0 : 1e3;
    for (int j = 0; j < 6; ++j) cost += std::abs(q[j] - reference[j]);
    if (cost < bestCost) {
      bestCost = cost;
      m.joints = q;
      m.configuration = sol.configuration;
    }
  }
  return bestCost < kInf;
}

void TravelPlanner::unreachable(MotionPoint& m, const JointVector& reference,
                                const std::string& move) {
  const std::string text = "robot cannot reach the " + move + " point at part (" +
                           fmt(m.position.x()) + ", " + fmt(m.position.y()) + ", " +
                           fmt(m.position.z()) + " mm)";
  if (options_.unreachable == UnreachablePolicy::Throw) {
    throw InvalidInput(text +
                       "; lower the clearance (--clearance), or move the positioner or "
                       "the part so the robot reaches above the part");
  }
  m.joints = reference;
  m.flags |= kMotionRobotLimit;
  motion_.warnings.push_back(text + " (joints held)");
}

/// The home pose as a motion point (forward kinematics), owned by `neighbour`'s path.
void TravelPlanner::appendHome(const MotionPoint& neighbour) {
  const HomePose& home = setup_.home;
  const Pose toolInWorld =
      cell_.robot.base * computeFlangePose(cell_.robot, home.robot) * cell_.tool.tcp;
  const Pose partInWorld = computePartInWorld(cell_.positioner, home.a1, home.a2);
  MotionPoint m =
      arcOffPoint(MoveKind::Home, neighbour, partInWorld.inverse() * toolInWorld.translation(),
                  home.a1, home.a2, toolInWorld.linear());
  m.joints = home.robot;
  // the IK branch of the home joints: the solution that reproduces them
  double best = kInf;
  for (const IkSolution& sol :
       solveInverseKinematics(cell_.robot, m.toolInRobotBase * tcpInverse_, home.robot[3])
           .solutions) {
    JointVector q = sol.joints;
    unwrapJoints(cell_.robot, q, home.robot);
    double d = 0.0;
    for (int j = 0; j < 6; ++j) d += std::abs(q[j] - home.robot[j]);
    if (d < best) {
      best = d;
      m.configuration = sol.configuration;
    }
  }
  out_.push_back(m);
}

/// Where the joint move between the home pose out_[home] and the arc-off point out_[neighbour]
/// (retract or approach of `owner`) would collide, inserts a travel point lifted above the
/// neighbour up owner's torch axis: the lowest lift whose straight move and joint move clear.
void TravelPlanner::clearHomeMove(std::size_t home, std::size_t neighbour,
                                  const MotionPoint& owner) {
  const MotionPoint& h = out_[home];
  const MotionPoint& n = out_[neighbour];
  if (!detail::checkJointMove(cell_, checker_, n, h).collides()) return;
  for (double d = step_; d <= setup_.maxLift + 1e-9; d += step_) {
    MotionPoint via = arcOffPoint(MoveKind::Travel, owner, n.position + d * retreatOf(owner), n.a1,
                                  n.a2, n.toolInWorld.linear());
    if (!solveJoints(via, n.joints, n.configuration)) break;  // higher is not reachable either
    if (detail::checkLinearMove(checker_, setup_.geometry.torch, n.toolInPart, via.toolInPart)
            .collides() ||
        detail::checkJointMove(cell_, checker_, via, h).collides()) {
      continue;
    }
    out_.insert(out_.begin() + static_cast<std::ptrdiff_t>(std::max(home, neighbour)), via);
    return;
  }
  // nothing clears: the collision check names the home move
}

/// Retract (from a path end) or approach (above a path start) point up the point's torch axis at
/// the lowest clear height, with the path point's positioner angles and tool orientation.
MotionPoint TravelPlanner::axisPoint(MoveKind kind, const MotionPoint& at) {
  const double h = clearHeight(at);
  MotionPoint m =
      arcOffPoint(kind, at, at.position + h * retreatOf(at), at.a1, at.a2, at.toolInWorld.linear());
  if (!solveJoints(m, at.joints, at.configuration)) {
    unreachable(m, at.joints,
                std::string(toString(kind)) + " point of layer " + std::to_string(at.layer) +
                    " path " + std::to_string(at.path));
  }
  return m;
}

/// The arc-off points from the end of `from` to the start of `to` (either may be null: program
/// start / end): retract, travel via points, approach.
void TravelPlanner::appendArcOff(const MotionPoint* from, const MotionPoint* to) {
  std::optional<MotionPoint> retract, approach;
  if (from) retract = axisPoint(MoveKind::Retract, *from);
  if (to) approach = axisPoint(MoveKind::Approach, *to);
  if (retract) out_.push_back(*retract);
  if (from && to) {
    const Vec3 r = retract->position, p = approach->position;
    Vec3 lift = retreatOf(*from) + retreatOf(*to);
    lift = lift.norm() > 1e-6 ? Vec3(lift.normalized()) : retreatOf(*from);
    double shortfall = options_.clearance;
    bool planned = false;
    for (double d = 0.0; d <= setup_.maxLift + 1e-9 && !planned; d += step_) {
      const Route route =
          d == 0.0 ? makeRoute({r, p}) : makeRoute({r, r + d * lift, p + d * lift, p});
      if (auto vias = tryRoute(route, *from, *to, *retract, &shortfall)) {
        out_.insert(out_.end(), vias->begin(), vias->end());
        planned = true;
      }
    }
    if (!planned) {
      ++shortCount_;
      if (shortWarnings_.size() < 3) {
        shortWarnings_.push_back("travel move towards layer " + std::to_string(to->layer) +
                                 " path " + std::to_string(to->path) + " (" + fmt(shortfall) +
                                 " mm)");
      }
    }
  }
  if (approach) out_.push_back(*approach);
}

/// The via points of `route` with joints, if the route clears and the robot reaches them.
std::optional<std::vector<MotionPoint>> TravelPlanner::tryRoute(const Route& route,
                                                                const MotionPoint& from,
                                                                const MotionPoint& to,
                                                                const MotionPoint& retract,
                                                                double* shortfall) {
  if (!routeClears(route, from, to, shortfall)) return std::nullopt;
  const Eigen::Quaterniond q0(from.toolInWorld.linear());
  const Eigen::Quaterniond q1(to.toolInWorld.linear());
  std::vector<MotionPoint> vias;
  JointVector reference = retract.joints;
  for (std::size_t k = 1; k + 1 < route.points.size(); ++k) {
    const double t = route.along[k];
    MotionPoint m =
        arcOffPoint(MoveKind::Travel, to, route.points[k], from.a1 + t * (to.a1 - from.a1),
                    from.a2 + t * (to.a2 - from.a2), q0.slerp(t, q1).toRotationMatrix());
    if (!solveJoints(m, reference, retract.configuration)) return std::nullopt;  // next lift
    reference = m.joints;
    vias.push_back(m);
  }
  return vias;
}

}  // namespace

TravelSetup travelSetupOf(const Cell& cell) {
  TravelSetup setup;
  setup.home = cell.home;
  setup.geometry = collisionGeometryOf(cell);
  return setup;
}

void insertTravelMoves(MotionPlan& motion, const Cell& cell, const TravelSetup& setup,
                       double beadRadius, const MotionOptions& options, const Progress& progress) {
  if (!(options.clearance > 0.0) || !std::isfinite(options.clearance)) {
    throw InvalidInput("travel clearance must be positive: " + fmt(options.clearance) +
                       " mm; use e.g. 10 mm");
  }
  if (!(beadRadius > 0.0) || !(setup.maxLift >= 0.0)) {
    throw InvalidInput("bead radius must be positive and the maximum lift not negative: " +
                       fmt(beadRadius) + " / " + fmt(setup.maxLift) +
                       " mm; check the plan's "
                       "bead spacing");
  }
  TravelPlanner(motion, cell, setup, beadRadius, options).run(progress);
}

void planArcOffMoves(const Plan& plan, const Cell& cell, const TravelSetup& setup,
                     const MotionOptions& options, MotionPlan& motion, const Progress& progress) {
  const double beadRadius = depositBeadRadius(plan.parameters);
  insertTravelMoves(motion, cell, setup, beadRadius, options, progress.sub(0.0, 0.5));
  checkMotionCollisions(motion, cell, setup.geometry, beadRadius, options, progress.sub(0.5, 1.0));
}

}  // namespace curvedslicer
