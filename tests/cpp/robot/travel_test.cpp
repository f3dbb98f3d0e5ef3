// Arc-off moves (robot/travel): on the curved example and the cylinder with the default cell, no
// travel move comes closer than the clearance to the material deposited before it — checked by
// an independent brute-force distance (the TCP polyline in the part frame sampled every 0.2 mm
// against every previously welded segment, minus the bead radius); the program starts and ends
// at home; retract and approach run along the torch's axis; arc-off joints reproduce their TCP
// poses; a travel over a wall is lifted; options and bad input.
#include "curvedslicer/robot/travel.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/sanitized_build.hpp"
#include "common/small_part.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "robot_test_support.hpp"

namespace curvedslicer {
namespace {

using robot_test::distanceToSegment;
using robot_test::straightPath;

// ---- plans ----------------------------------------------------------------------------------

/// The curved example at a coarse voxel (1 mm instead of 0.5 mm; a few seconds).
const Plan& curvedExamplePlan() {
  static const Plan plan = [] {
    PlanJobOptions options;
    options.layerJob.start = loadStartSurface(
        parseStartSurfaceSpec("mesh:" + testing::modelPath("custom_base_surface.obj").string()));
    options.layerJob.capHoles = true;
    options.layerJob.layers.layerThickness = 1.5;
    options.layerJob.voxelize.voxelSize = 1.0;
    options.planner.beadSpacing = 3.7;
    const TriMesh model = readMesh(testing::modelPath("custom_base_geom_to_slice.obj"));
    return runPlanJob(model, options).planned.plan;
  }();
  return plan;
}

/// The 200 mm cylinder, coarse (voxel 4 mm, layers 6 mm, beads 10 mm apart).
const Plan& cylinderPlan() {
  static const Plan plan = [] {
    PlanJobOptions options;
    options.layerJob.layers.layerThickness = 6.0;
    options.layerJob.voxelize.voxelSize = 4.0;
    options.planner.beadSpacing = 10.0;
    options.planner.pointSpacing = 4.0;
    const TriMesh model = readMesh(testing::modelPath("simple_cylinder_closed_mid_res.stl"));
    return runPlanJob(model, options).planned.plan;
  }();
  return plan;
}

/// The default cell with the part centred on the table and its lowest point one bead radius
/// above the table surface (stands in for the placement rule of the cell / placement stage).
Cell placedCell(const Plan& plan) {
  Aabb box;
  for (const PlanLayer& layer : plan.layers) {
    for (const PlanPath& path : layer.paths) {
      for (const PathPoint& p : path.points) box.extend(p.position);
    }
  }
  Cell cell = defaultCell();
  const double r = depositBeadRadius(plan.parameters);
  cell.positioner.tableToPart = Pose::Identity();
  cell.positioner.tableToPart.translation() =
      Vec3(-box.center().x(), -box.center().y(), r - box.min.z());
  return cell;
}

/// A wall along x at y = 0 (`layers` layers 1.5 mm apart), then, in one more layer, a path at
/// y = -30 and one at y = +30 on the table: the travel between them must climb over the wall.
Plan wallPlan(int layers) {
  Plan plan;
  plan.parameters.beadSpacing = 3.7;
  plan.parameters.layerThickness = 1.5;
  for (int l = 0; l < layers; ++l) {
    PlanLayer layer;
    layer.index = l;
    const double z = 1.5 * (l + 1);
    layer.paths.push_back(straightPath(Vec3(-40, 0, z), Vec3(40, 0, z)));
    plan.layers.push_back(layer);
  }
  PlanLayer last;
  last.index = layers;
  last.paths.push_back(straightPath(Vec3(-30, -30, 1.5), Vec3(30, -30, 1.5)));
  last.paths.push_back(straightPath(Vec3(30, 30, 1.5), Vec3(-30, 30, 1.5)));
  plan.layers.push_back(last);
  for (std::size_t l = 0; l < plan.layers.size(); ++l) {
    for (std::size_t p = 0; p < plan.layers[l].paths.size(); ++p) {
      plan.layers[l].paths[p].layer = static_cast<int>(l);
      plan.layers[l].paths[p].index = static_cast<int>(p);
    }
  }
  return plan;
}

// ---- independent checks -----------------------------------------------------------------------

bool isArcOff(const MotionPoint& m) {
  return m.kind == MoveKind::Retract || m.kind == MoveKind::Travel || m.kind == MoveKind::Approach;
}

/// The welded segments in execution order, grouped 16 at a time with a bounding sphere so the
/// brute force stays affordable (a group is skipped only when its sphere is farther than
/// `cutoff` from the sample).
struct Deposit {
  struct Group {
    Vec3 centre;
    double radius = 0.0;
    std::vector<std::pair<Vec3, Vec3>> segments;
  };
  std::vector<Group> groups;
  void add(const Vec3& a, const Vec3& b) {
    if (groups.empty() || groups.back().segments.size() == 16) groups.emplace_back();
    Group& g = groups.back();
    g.segments.emplace_back(a, b);
    Aabb box;
    for (const auto& s : g.segments) {
      box.extend(s.first);
      box.extend(s.second);
    }
    g.centre = box.center();
    g.radius = 0.5 * box.diagonal();
  }
  /// Smallest distance from x to a segment centre line (capped at `cutoff`).
  double distance(const Vec3& x, double cutoff) const {
    double best = cutoff;
    for (const Group& g : groups) {
      if ((x - g.centre).norm() - g.radius >= best) continue;
      for (const auto& s : g.segments)
        best = std::min(best, distanceToSegment(x, s.first, s.second));
    }
    return best;
  }
};

/// Smallest clearance (TCP to bead surface) over every travel move (both ends retract, travel
/// or approach points), sampled every 0.2 mm; the beads are capsules of radius `r`.
double smallestTravelClearance(const MotionPlan& motion, double r, double clearance,
                               std::size_t* moves) {
  Deposit deposit;
  double smallest = kInf;
  *moves = 0;
  for (std::size_t i = 1; i < motion.points.size(); ++i) {
    const MotionPoint& a = motion.points[i - 1];
    const MotionPoint& b = motion.points[i];
    if (b.arcOn) {
      deposit.add(a.position, b.position);
      continue;
    }
    if (!isArcOff(a) || !isArcOff(b)) continue;
    ++*moves;
    const int n = std::max(1, static_cast<int>(std::ceil((b.position - a.position).norm() / 0.2)));
    for (int k = 0; k <= n; ++k) {
      const Vec3 x = a.position + (b.position - a.position) * (static_cast<double>(k) / n);
      smallest = std::min(smallest, deposit.distance(x, clearance + r + 1.0) - r);
    }
  }
  return smallest;
}

/// The envelope model of robot/collision.hpp, written out here: the cone from the nozzle to the
/// top in four quarters, each a capsule with the cone's largest radius over it, the lowest
/// capsule's round end on the nozzle and the highest's on the top (axis heights above the TCP).
struct EnvelopeCapsule {
  double from, to, radius;
};
std::vector<EnvelopeCapsule> envelopeCapsules(const TorchEnvelope& torch) {
  std::vector<EnvelopeCapsule> out;
  for (int k = 0; k < 4; ++k) {
    const double r = torch.radius + (torch.topRadius - torch.radius) *
                                        (k + (torch.topRadius > torch.radius)) / 4.0;
    const double h0 = torch.stickout + torch.length * k / 4.0;
    const double h1 = torch.stickout + torch.length * (k + 1) / 4.0;
    out.push_back({k == 0 ? h0 + r : h0, k == 3 ? h1 - r : h1, r});
  }
  return out;
}

/// Smallest gap (mm) between the cell's torch envelope capsules and the centre line of any bead
/// welded before the move, less the capsule radius, over every weld move (torch at the move's
/// end pose) — the collision check's own question, answered by brute force: each bead segment
/// is sampled every 0.1 mm against each capsule axis (an over-estimate by at most 0.05 mm).
/// Beads farther than `reach` from the axis are skipped.
double smallestTorchGap(const MotionPlan& motion, const TorchEnvelope& torch, double reach) {
  const std::vector<EnvelopeCapsule> capsules = envelopeCapsules(torch);
  Deposit deposit;
  double smallest = kInf;
  for (std::size_t i = 1; i < motion.points.size(); ++i) {
    const MotionPoint& a = motion.points[i - 1];
    const MotionPoint& b = motion.points[i];
    if (!b.arcOn) continue;
    const Vec3 tip = b.toolInPart.translation();
    const Vec3 up = -b.toolInPart.linear().col(2);
    for (const EnvelopeCapsule& c : capsules) {
      const Vec3 low = tip + c.from * up;
      const Vec3 high = tip + c.to * up;
      for (const Deposit::Group& g : deposit.groups) {
        if (distanceToSegment(g.centre, low, high) - g.radius >= reach) continue;
        for (const auto& [p, q] : g.segments) {
          const int n = std::max(1, static_cast<int>(std::ceil((q - p).norm() / 0.1)));
          for (int k = 0; k <= n; ++k) {
            const Vec3 x = p + (q - p) * (static_cast<double>(k) / n);
            smallest = std::min(smallest, distanceToSegment(x, low, high) - c.radius);
          }
        }
      }
    }
    deposit.add(a.position, b.position);
  }
  return smallest;
}

/// Structure every motion with travel must have: home at both ends, spans over path points
/// only, arc-off points with index -1, retract/approach back up the torch's axis, joints that
/// reproduce the TCP pose.
void expectTravelStructure(const MotionPlan& motion, const Plan& plan, const Cell& cell) {
  ASSERT_GE(motion.points.size(), 2u);
  const HomePose& home = cell.home;
  for (const MotionPoint* end : {&motion.points.front(), &motion.points.back()}) {
    EXPECT_EQ(end->kind, MoveKind::Home);
    for (int j = 0; j < 6; ++j) EXPECT_EQ(end->joints[j], home.robot[j]);
  }
  ASSERT_EQ(motion.paths.size(), plan.pathCount());
  std::size_t pathPoints = 0;
  for (const MotionPathSpan& span : motion.paths) {
    EXPECT_TRUE(motion.points[span.begin].pathStart);
    EXPECT_TRUE(motion.points[span.end - 1].pathEnd);
    for (std::size_t k = span.begin; k < span.end; ++k) {
      EXPECT_EQ(motion.points[k].kind, MoveKind::Path);
    }
    pathPoints += span.end - span.begin;
    // retract from the previous path end and approach this start back up the torch's axis (the
    // tool's -z in the part frame), the way the torch can always go
    const MotionPoint& before = motion.points[span.begin - 1];
    const MotionPoint& start = motion.points[span.begin];
    EXPECT_EQ(before.kind, MoveKind::Approach);
    const Vec3 down = before.position - start.position;
    const Vec3 startAxis = -start.toolInPart.linear().col(2);
    EXPECT_LT(down.cross(startAxis).norm(), 1e-9 * down.norm());
    EXPECT_GT(down.dot(startAxis), 0.0);
    const MotionPoint& after = motion.points[span.end];
    const MotionPoint& end = motion.points[span.end - 1];
    EXPECT_EQ(after.kind, MoveKind::Retract);
    const Vec3 up = after.position - end.position;
    const Vec3 endAxis = -end.toolInPart.linear().col(2);
    EXPECT_LT(up.cross(endAxis).norm(), 1e-9 * up.norm());
    EXPECT_GT(up.dot(endAxis), 0.0);
  }
  std::size_t arcOff = 0;
  for (const MotionPoint& m : motion.points) {
    if (m.kind == MoveKind::Path) continue;
    ++arcOff;
    EXPECT_EQ(m.index, -1);
    EXPECT_FALSE(m.arcOn);
    EXPECT_FALSE(m.flags & kMotionRobotLimit);
    const Pose tool = computeFlangePose(cell.robot, m.joints) * cell.tool.tcp;
    EXPECT_LT((tool.translation() - m.toolInRobotBase.translation()).norm(), 1e-6);
    EXPECT_LT((tool.linear() - m.toolInRobotBase.linear()).norm(), 1e-9);
    for (int j = 0; j < 6; ++j) EXPECT_TRUE(cell.robot.joints[j].contains(m.joints[j]));
  }
  EXPECT_EQ(pathPoints + arcOff, motion.points.size());
}

// ---- tests ----------------------------------------------------------------------------------

/// The default clearance kept by every travel move of `plan`'s motion (default options), the
/// program starting and ending at home, no collision and no torch axis near a bead.
void expectClearTravelFromHome(const Plan& plan) {
  const Cell cell = placedCell(plan);
  const MotionOptions options;
  const MotionPlan motion = planMotion(plan, cell, options);
  expectTravelStructure(motion, plan, cell);
  std::size_t moves = 0;
  const double smallest = smallestTravelClearance(motion, depositBeadRadius(plan.parameters),
                                                  options.clearance, &moves);
  EXPECT_GT(moves, plan.pathCount() - 1);
  EXPECT_GE(smallest, options.clearance - 1e-9);
  // the collision check found nothing: no torch axis comes within torch + bead radius of a bead
  // (the closest is the bead under the nozzle, stick-out + radius = 25 mm from the axis end)
  EXPECT_TRUE(motion.collisions.empty());
  const double bead = depositBeadRadius(plan.parameters);
  EXPECT_GE(smallestTorchGap(motion, cell.tool.envelope, 30.0), bead);
}

TEST(Travel, CurvedExampleKeepsTheClearanceAndStartsAndEndsAtHome) {
  CURVEDSLICER_SKIP_IF_SANITIZED("Travel.SmallPartKeepsTheClearanceAndStartsAndEndsAtHome");
  const Plan& plan = curvedExamplePlan();
  ASSERT_GT(plan.pathCount(), 10u);
  expectClearTravelFromHome(plan);
}

/// The same on the small part of common/small_part.hpp (the sanitizer build runs this one).
TEST(Travel, SmallPartKeepsTheClearanceAndStartsAndEndsAtHome) {
  const Plan plan = testing::planSmallPart().planned.plan;
  ASSERT_GT(plan.pathCount(), 5u);  // a weld per layer: its rings joined by connected insets
  expectClearTravelFromHome(plan);
}

TEST(Travel, CylinderKeepsTheClearanceAndStartsAndEndsAtHome) {
  CURVEDSLICER_SKIP_IF_SANITIZED("Travel.SmallPartKeepsTheClearanceAndStartsAndEndsAtHome");
  const Plan& plan = cylinderPlan();
  ASSERT_GT(plan.pathCount(), 10u);
  const Cell cell = placedCell(plan);
  for (double clearance : {10.0, 25.0}) {
    SCOPED_TRACE(clearance);
    MotionOptions options;
    options.clearance = clearance;
    const MotionPlan motion = planMotion(plan, cell, options);
    expectTravelStructure(motion, plan, cell);
    std::size_t moves = 0;
    const double smallest =
        smallestTravelClearance(motion, depositBeadRadius(plan.parameters), clearance, &moves);
    EXPECT_GE(moves, plan.pathCount() - 1);
    EXPECT_GE(smallest, clearance - 1e-9);
    EXPECT_TRUE(motion.collisions.empty());
    const double bead = depositBeadRadius(plan.parameters);
    EXPECT_GE(smallestTorchGap(motion, cell.tool.envelope, 30.0), bead);
  }
}

TEST(Travel, ClimbsOverAWallBetweenTwoPaths) {
  const Plan plan = wallPlan(30);  // wall top at 45 mm
  const Cell cell = placedCell(plan);
  const MotionOptions options;
  const MotionPlan motion = planMotion(plan, cell, options);
  expectTravelStructure(motion, plan, cell);
  std::size_t moves = 0;
  const double r = depositBeadRadius(plan.parameters);
  EXPECT_GE(smallestTravelClearance(motion, r, options.clearance, &moves),
            options.clearance - 1e-9);
  // the move from the path at y = -30 to the one at y = +30 goes over the wall top
  const MotionPathSpan& last = motion.paths.back();
  double highest = -kInf;
  std::size_t via = 0;
  for (std::size_t k = motion.paths[motion.paths.size() - 2].end; k < last.begin; ++k) {
    highest = std::max(highest, motion.points[k].position.z());
    via += motion.points[k].kind == MoveKind::Travel;
  }
  EXPECT_EQ(via, 2u);
  EXPECT_GE(highest, 45.0 + r + options.clearance);
  EXPECT_LE(highest, 45.0 + r + options.clearance + options.clearance / 2 + 1e-9);
}

TEST(Travel, WithoutHomeStartsAtTheFirstApproachAndEndsAtTheLastRetract) {
  const Plan plan = wallPlan(3);
  const Cell cell = placedCell(plan);
  MotionOptions options;
  options.addHome = false;
  const MotionPlan motion = planMotion(plan, cell, options);
  EXPECT_EQ(motion.points.front().kind, MoveKind::Approach);
  EXPECT_EQ(motion.points.back().kind, MoveKind::Retract);
  for (const MotionPoint& m : motion.points) EXPECT_NE(m.kind, MoveKind::Home);
  EXPECT_EQ(motion.points.front().layer, 0);
  EXPECT_EQ(motion.points.back().layer, 3);
  EXPECT_EQ(motion.points.back().path, 1);
}

TEST(Travel, RetractHeightIsTheClearanceAboveTheBead) {
  const Plan plan = wallPlan(1);
  const Cell cell = placedCell(plan);
  for (double clearance : {5.0, 10.0, 40.0}) {
    MotionOptions options;
    options.clearance = clearance;
    const MotionPlan motion = planMotion(plan, cell, options);
    const MotionPoint& end = motion.points[motion.paths.front().end - 1];
    const MotionPoint& retract = motion.points[motion.paths.front().end];
    EXPECT_NEAR((retract.position - end.position).norm(),
                clearance + depositBeadRadius(plan.parameters), 1e-9);
  }
}

TEST(Travel, BadClearanceIsRejected) {
  // a clearance of a few microns would make the travel planner's lifts take millions of steps;
  // one of kilometres is a unit slip
  const Plan plan = wallPlan(1);
  for (double clearance : {0.0, -1.0, std::nan(""), 1e-20, 0.4, 1e9}) {
    MotionOptions options;
    options.clearance = clearance;
    try {
      planMotion(plan, placedCell(plan), options);
      ADD_FAILURE() << "no error for clearance " << clearance;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("clearance must be between 0.5 and 200 mm"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(Travel, MergeToleranceAsLargeAsTheBeadsIsRejected) {
  // merging consecutive points closer than half a bead spacing or more would collapse welds
  const Plan plan = wallPlan(1);  // beads 3.7 mm apart
  MotionOptions options;
  options.mergeTolerance = 50.0;
  try {
    planMotion(plan, placedCell(plan), options);
    ADD_FAILURE() << "no error for a merge tolerance of 50 mm";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("merge tolerance must be below half the bead spacing "
                                         "(1.85 mm): 50.00 mm"),
              std::string::npos)
        << e.what();
  }
  options.mergeTolerance = 0.5;
  EXPECT_NO_THROW(planMotion(plan, placedCell(plan), options));
}

TEST(Travel, Deterministic) {
  const Plan plan = wallPlan(5);
  const Cell cell = placedCell(plan);
  const MotionPlan a = planMotion(plan, cell);
  const MotionPlan b = planMotion(plan, cell);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].position, b.points[i].position);
    EXPECT_EQ(a.points[i].joints, b.points[i].joints);
    EXPECT_EQ(a.points[i].kind, b.points[i].kind);
  }
}

}  // namespace
}  // namespace curvedslicer
