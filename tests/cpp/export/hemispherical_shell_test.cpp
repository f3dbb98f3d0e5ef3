// A part whose first layers meet the table steeply: a hemispherical shell (inner radius 30 mm,
// outer 40 mm) grown from its inner hemisphere, its rim on the table, planned with the defaults
// (layers 1.5 mm, voxel 1 mm, beads 3.7 mm). With the torch along gravity on the bare table the
// torch reaches 11.9 mm into the table on the rim's beads; with placement auto each of the four
// bundled cells plans it without a collision and writes its own language. Checked independently
// of the planner's collision model: the torch cone itself, sampled every 2 mm along its axis and
// every 15° around, against the table disc and the riser the placement chose, on every motion
// point and along every move (linear moves every millimetre, moves to and from home through the
// robot's forward kinematics), and its axis against every bead deposited before the point; the
// robot arm's link capsules (the cell's robot/link_capsules_mm about the joint points of the
// forward kinematics) sampled every 5 mm along their axes against the table, the positioner's
// body, the riser and the deposit, at every motion point and along the moves to and from home; and
// the programs read back strictly (welds, one configuration per weld), the axis speeds from the
// CSV within the cell's limits, a2 within its step limit between consecutive weld points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <unordered_map>
#include <vector>

#include "axis_speeds.hpp"
#include "common/sanitized_build.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "export_test_support.hpp"
#include "program_readers.hpp"
#include "program_readers_krl_rapid.hpp"
#include "synthetic_motion.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

constexpr double kShellInner = 30.0;  // mm
constexpr double kShellOuter = 40.0;  // mm

/// Vertex index of a hemisphere grid: ring i (0 = the pole, `rings` = the rim), column j.
int shellVertex(int first, int i, int j, int columns) {
  return i == 0 ? first : first + 1 + (i - 1) * columns + (j % columns);
}

/// Appends a hemisphere of `radius` (z >= 0) as a grid of `rings` x `columns`; returns the index
/// of its pole vertex.
int appendHemisphere(TriMesh& mesh, double radius, int rings, int columns, bool outward) {
  const int first = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back(Vec3(0, 0, radius));
  for (int i = 1; i <= rings; ++i) {
    const double theta = 0.5 * kPiT * i / rings;
    for (int j = 0; j < columns; ++j) {
      const double phi = 2.0 * kPiT * j / columns;
      mesh.vertices.push_back(radius * Vec3(std::sin(theta) * std::cos(phi),
                                            std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  const auto add = [&](int a, int b, int c) {
    mesh.triangles.push_back(outward ? Vec3i(a, b, c) : Vec3i(a, c, b));
  };
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < columns; ++j) {
      const int a = shellVertex(first, i, j, columns), b = shellVertex(first, i + 1, j, columns);
      const int c = shellVertex(first, i + 1, j + 1, columns);
      const int d = shellVertex(first, i, j + 1, columns);
      add(a, b, c);  // (∂θ × ∂φ points outward)
      if (i > 0) add(a, c, d);
    }
  }
  return first;
}

/// The closed shell between the two hemispheres, the rim annulus at z = 0 facing down.
TriMesh hemisphericalShell(int rings, int columns) {
  TriMesh mesh;
  const int outer = appendHemisphere(mesh, kShellOuter, rings, columns, true);
  const int inner = appendHemisphere(mesh, kShellInner, rings, columns, false);
  for (int j = 0; j < columns; ++j) {
    const int o0 = shellVertex(outer, rings, j, columns),
              o1 = shellVertex(outer, rings, j + 1, columns);
    const int i0 = shellVertex(inner, rings, j, columns),
              i1 = shellVertex(inner, rings, j + 1, columns);
    mesh.triangles.push_back(Vec3i(o0, i0, o1));
    mesh.triangles.push_back(Vec3i(i0, i1, o1));
  }
  return mesh;
}

PlanJobResult planHemisphericalShell() {
  TriMesh start;
  appendHemisphere(start, kShellInner, 24, 96, true);
  PlanJobOptions options;
  options.layerJob.layers.layerThickness = 1.5;
  options.layerJob.voxelize.voxelSize = 1.0;
  options.layerJob.start = StartSurface::surface(start);
  options.planner.beadSpacing = 3.7;
  options.modelName = "hemispherical_shell";
  options.startSpec = "mesh:inner_hemisphere";
  return runPlanJob(hemisphericalShell(24, 96), options);
}

/// Signed distance (mm, negative inside) of `p` (table frame) to the cylinder about the z axis
/// of `radius` between heights z0 and z1.
double shellCylinderDistance(const Vec3& p, double radius, double z0, double z1) {
  const double dr = std::hypot(p.x(), p.y()) - radius;
  const double dz = std::max(z0 - p.z(), p.z() - z1);
  if (dr <= 0.0 && dz <= 0.0) return std::max(dr, dz);
  return std::hypot(std::max(dr, 0.0), std::max(dz, 0.0));
}

/// The smallest clearance found, and where.
struct ShellClearance {
  double table = kInf, riser = kInf, deposit = kInf;
  double armTable = kInf, armBody = kInf, armRiser = kInf, armDeposit = kInf;
  std::string where;
};

/// The torch cone (the cell's envelope) at a TCP pose in the part frame against the table and
/// the riser: every sample of its surface (every 2 mm along the axis, every 15° around).
void coneAgainstTableAndRiser(const Cell& placed, const FixtureGeometry& fixture,
                              const Pose& toolInPart, const std::string& where, ShellClearance& c) {
  const TorchEnvelope& torch = placed.tool.envelope;
  const Vec3 tip = toolInPart.translation();
  const Vec3 up = -toolInPart.linear().col(2);
  const Vec3 e1 = up.unitOrthogonal(), e2 = up.cross(e1);
  const PositionerGeometry& g = placed.positioner.geometry;
  for (double h = torch.stickout; h <= torch.stickout + torch.length + 1e-9; h += 2.0) {
    const double r =
        torch.radius + (torch.topRadius - torch.radius) * (h - torch.stickout) / torch.length;
    for (int k = 0; k < 24; ++k) {
      const double a = 2.0 * kPiT * k / 24;
      const Vec3 x = placed.positioner.tableToPart *
                     (tip + h * up + r * (std::cos(a) * e1 + std::sin(a) * e2));
      const double table = shellCylinderDistance(x, g.tableRadius, -g.tableThickness, 0.0);
      if (table < c.table) c.table = table, c.where = where + " (table)";
      if (fixture.hasRiser()) {
        const double riser =
            shellCylinderDistance(x, 0.5 * fixture.riserDiameter, 0.0, fixture.riserHeight);
        if (riser < c.riser) c.riser = riser, c.where = where + " (riser)";
      }
    }
  }
}

/// The deposit so far: welded segments in a uniform 8 mm grid (by the cells their box grown by
/// the bead radius covers).
class ShellDeposit {
 public:
  explicit ShellDeposit(double beadRadius) : radius_(beadRadius) {}
  void add(const Vec3& a, const Vec3& b) {
    const std::size_t id = segments_.size();
    segments_.push_back({a, b});
    lo_ = lo_.cwiseMin(a).cwiseMin(b);
    hi_ = hi_.cwiseMax(a).cwiseMax(b);
    stamp_.push_back(0);
    const Vec3 lo = a.cwiseMin(b) - Vec3::Constant(radius_);
    const Vec3 hi = a.cwiseMax(b) + Vec3::Constant(radius_);
    forCells(lo, hi, [&](long long key) { cells_[key].push_back(id); });
  }
  /// Smallest distance of the surface of a disc-free sphere of `r` around `p` to a bead surface.
  double clearance(const Vec3& p, double r) {
    double best = kInf;
    ++query_;
    const Vec3 grow = Vec3::Constant(r + radius_);
    forCells(p - grow, p + grow, [&](long long key) {
      const auto it = cells_.find(key);
      if (it == cells_.end()) return;
      for (std::size_t id : it->second) {
        if (stamp_[id] == query_) continue;
        stamp_[id] = query_;
        const auto& [a, b] = segments_[id];
        const Vec3 d = b - a;
        const double t =
            d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
        best = std::min(best, (a + t * d - p).norm() - radius_ - r);
      }
    });
    return best;
  }
  /// The same for a wide sphere (an arm link): every bead, once `p` is within reach of the box
  /// of the deposit.
  double clearanceOfWide(const Vec3& p, double r) const {
    if (segments_.empty()) return kInf;
    if ((p.cwiseMax(lo_).cwiseMin(hi_) - p).norm() > r + radius_ + 1.0) return kInf;
    double best = kInf;
    for (const auto& [a, b] : segments_) {
      const Vec3 d = b - a;
      const double t =
          d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
      best = std::min(best, (a + t * d - p).norm() - radius_ - r);
    }
    return best;
  }

 private:
  template <class F>
  void forCells(const Vec3& lo, const Vec3& hi, F&& f) const {
    const Vec3i a = (lo / kCell).array().floor().cast<int>();
    const Vec3i b = (hi / kCell).array().floor().cast<int>();
    for (int x = a.x(); x <= b.x(); ++x)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int z = a.z(); z <= b.z(); ++z)
          f((static_cast<long long>(x) * 100003 + y) * 100003 + z);
  }
  static constexpr double kCell = 8.0;
  double radius_;
  Vec3 lo_ = Vec3::Constant(kInf), hi_ = Vec3::Constant(-kInf);  // box of the segments
  std::vector<std::pair<Vec3, Vec3>> segments_;
  std::unordered_map<long long, std::vector<std::size_t>> cells_;
  std::vector<std::size_t> stamp_;
  std::size_t query_ = 0;
};

/// The torch's axis at a pose against the deposit before it: every 2 mm from the nozzle up, the
/// cone's radius there, while the axis is near the part.
void axisAgainstDeposit(const TorchEnvelope& torch, const Pose& toolInPart, ShellDeposit& deposit,
                        const std::string& where, ShellClearance& c) {
  const Vec3 tip = toolInPart.translation();
  const Vec3 up = -toolInPart.linear().col(2);
  for (double h = torch.stickout; h <= std::min(torch.stickout + torch.length, 150.0); h += 2.0) {
    const double r =
        torch.radius + (torch.topRadius - torch.radius) * (h - torch.stickout) / torch.length;
    const double d = deposit.clearance(tip + h * up, r);
    if (d < c.deposit) c.deposit = d, c.where = where + " (deposit)";
  }
}

/// The arm's link capsules at joints q and positioner angles a1, a2 (the model of
/// resources/cells/README.md, "Collision model of the arm"): each link's axis in the table frame
/// sampled every 5 mm, each sample's sphere of the link's radius, against the table disc, the
/// positioner's body (table underside down to the tilt axis), the riser and the deposit.
void armAgainstCell(const Cell& placed, const FixtureGeometry& fixture, const JointVector& q,
                    double a1, double a2, ShellDeposit& deposit, const std::string& where,
                    ShellClearance& c) {
  const RobotDescription& robot = placed.robot;
  const ArmEnvelope& links = robot.links;
  const ArmPoints a = computeArmPoints(robot, q);
  const Vec3 side = links.upperArmOffset * a.side;
  // the bundled robots stand upright on the floor or with their base frame above it
  const Vec3 foot =
      robot.base.inverse() * Vec3(robot.base.translation().x(), robot.base.translation().y(), 0.0);
  const struct {
    Vec3 from, to;
    double radius;
  } capsules[] = {{foot, a.column, links.column},
                  {a.shoulder + side, a.elbow + side, links.upperArm},
                  {a.elbow, a.forearmRoot, links.elbow},
                  {a.forearmRoot, a.wrist, links.forearm},
                  {a.wrist, a.flange, links.wrist}};
  const Pose baseToTable = placed.positioner.tableToPart *
                           computePartInWorld(placed.positioner, a1, a2).inverse() * robot.base;
  const Pose toPart = placed.positioner.tableToPart.inverse();
  const PositionerGeometry& g = placed.positioner.geometry;
  const PositionerDescription& p = placed.positioner;
  const double axisDepth = (p.rotationAxisPoint - p.tiltAxisPoint).dot(p.rotationAxisDirection);
  for (const auto& capsule : capsules) {
    const Vec3 from = baseToTable * capsule.from, to = baseToTable * capsule.to;
    const int n = std::max(1, static_cast<int>(std::ceil((to - from).norm() / 5.0)));
    for (int k = 0; k <= n; ++k) {
      const Vec3 x = from + (to - from) * (static_cast<double>(k) / n);
      const double r = capsule.radius;
      const auto keep = [&](double d, double& smallest, const char* what) {
        if (d < smallest) smallest = d, c.where = where + " (arm vs " + what + ")";
      };
      keep(shellCylinderDistance(x, g.tableRadius, -g.tableThickness, 0.0) - r, c.armTable,
           "table");
      keep(shellCylinderDistance(x, g.bodyRadius, -axisDepth, -g.tableThickness) - r, c.armBody,
           "body");
      if (fixture.hasRiser()) {
        keep(shellCylinderDistance(x, 0.5 * fixture.riserDiameter, 0.0, fixture.riserHeight) - r,
             c.armRiser, "riser");
      }
      keep(deposit.clearanceOfWide(toPart * x, r), c.armDeposit, "deposit");
    }
  }
}

/// TCP pose in the part frame of joints and positioner angles, by forward kinematics.
Pose shellToolInPart(const Cell& placed, const JointVector& q, double a1, double a2) {
  return computePartInWorld(placed.positioner, a1, a2).inverse() * placed.robot.base *
         computeFlangePose(placed.robot, q) * placed.tool.tcp;
}

ShellClearance measureClearance(const MotionPlan& motion, const Cell& placed, double beadRadius) {
  ShellClearance c;
  ShellDeposit deposit(beadRadius);
  const TorchEnvelope& torch = placed.tool.envelope;
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const MotionPoint& m = motion.points[i];
    const std::string where = "motion point " + std::to_string(i);
    if (i > 0) {
      const MotionPoint& p = motion.points[i - 1];
      if (p.kind == MoveKind::Home || m.kind == MoveKind::Home) {
        for (int k = 1; k < 32; ++k) {
          const double t = k / 32.0;
          JointVector q;
          for (int j = 0; j < 6; ++j) q[j] = p.joints[j] + t * (m.joints[j] - p.joints[j]);
          const double a1 = p.a1 + t * (m.a1 - p.a1), a2 = p.a2 + t * (m.a2 - p.a2);
          coneAgainstTableAndRiser(placed, motion.fixture, shellToolInPart(placed, q, a1, a2),
                                   where + " (move from home)", c);
          armAgainstCell(placed, motion.fixture, q, a1, a2, deposit, where + " (move from home)",
                         c);
        }
      } else {
        const int n = static_cast<int>(
            std::ceil((m.toolInPart.translation() - p.toolInPart.translation()).norm()));
        for (int k = 1; k < n; ++k) {
          const double t = static_cast<double>(k) / n;
          Pose pose = Pose::Identity();
          pose.translation() =
              (1 - t) * p.toolInPart.translation() + t * m.toolInPart.translation();
          const Vec3 z = ((1 - t) * p.toolInPart.linear().col(2) + t * m.toolInPart.linear().col(2))
                             .normalized();
          pose.linear().col(2) = z;  // the checks use the axis only
          coneAgainstTableAndRiser(placed, motion.fixture, pose, where + " (on the move)", c);
        }
      }
    }
    coneAgainstTableAndRiser(placed, motion.fixture, m.toolInPart, where, c);
    axisAgainstDeposit(torch, m.toolInPart, deposit, where, c);
    armAgainstCell(placed, motion.fixture, m.joints, m.a1, m.a2, deposit, where, c);
    if (m.arcOn) deposit.add(motion.points[i - 1].position, m.position);
  }
  return c;
}

/// |Δa2| between consecutive points of each weld, at most the planner's a2 step (5° default).
void expectA2Steps(const MotionPlan& motion) {
  double largest = 0.0;
  for (const MotionPathSpan& span : motion.paths) {
    for (std::size_t k = span.begin + 1; k < span.end; ++k) {
      largest = std::max(largest, std::abs(motion.points[k].a2 - motion.points[k - 1].a2));
    }
  }
  EXPECT_LE(largest, MotionOptions{}.maxA2Step + 1e-9) << largest / kDegT << " deg";
}

/// The program in the cell's own language read back strictly: one weld per path, the stated
/// configuration constant within each weld and consistent with the planned joints.
void expectOwnLanguageReadsBack(const MotionPlan& motion, const Cell& placed, ExportFormat format) {
  const ReadProgram program = exportAndRead(motion, placed, format);
  ASSERT_EQ(program.moves.size(), motion.points.size());
  ASSERT_EQ(program.welds.size(), motion.paths.size());
  std::size_t changes = 0, inconsistent = 0;
  for (const MotionPathSpan& span : motion.paths) {
    const auto& start = program.moves[span.begin].configuration;
    ASSERT_TRUE(start.has_value()) << program.moves[span.begin].line;
    for (std::size_t i = span.begin; i < span.end; ++i) {
      const auto& stated = program.moves[i].configuration;
      ASSERT_TRUE(stated.has_value()) << program.moves[i].line;
      changes += stated->text != start->text;
      inconsistent += !inconsistencyWithJoints(*stated, motion.points[i], 15.0 * kDegT).empty();
    }
  }
  EXPECT_EQ(changes, 0u);
  EXPECT_EQ(inconsistent, 0u);
}

TEST(HemisphericalShell, RimOnTheTableExportsCollisionFreeForEveryBundledCell) {
  CURVEDSLICER_SKIP_IF_SANITIZED(
      "TorchTilt.PathBesideATallWallIsWeldedLeaningAwayByTheSmallestAngle");
  const PlanJobResult job = planHemisphericalShell();
  const Plan& plan = job.planned.plan;
  ASSERT_GE(plan.layers.size(), 6u);  // 10 mm of wall in 1.5 mm layers
  const std::pair<const char*, ExportFormat> cells[] = {
      {"motoman_hp20d_tilt_rotate.json", ExportFormat::Jbi},
      {"kuka_kr16_r1610_2_dkp400.json", ExportFormat::Krl},
      {"abb_irb1660id_irbp_a250.json", ExportFormat::Rapid},
      {"fanuc_arcmate100ic_2axis_positioner.json", ExportFormat::Ls},
  };
  for (const auto& [file, language] : cells) {
    SCOPED_TRACE(file);
    const Cell cell =
        readCell(std::filesystem::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "cells" / file);
    // on the bare table the rim's beads bring the table to the torch
    try {
      planMotion(plan, cell);
      ADD_FAILURE() << "the bare table does not collide";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("torch vs positioner table"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("--placement auto"), std::string::npos) << e.what();
    }
    MotionOptions options;
    options.placement = PartPlacement::Auto;
    const MotionPlan motion = planMotion(plan, cell, options);
    EXPECT_TRUE(motion.collisions.empty());
    EXPECT_GT(motion.fixture.riserHeight, 0.0);
    Cell placed = placedCell(cell, motion);
    placed.positioner.fixture = motion.fixture;
    const ShellClearance c = measureClearance(motion, placed, 0.5 * 3.7);
    std::cout << file << ": riser " << motion.fixture.riserHeight << " mm high, "
              << motion.fixture.riserDiameter << " mm across; smallest clearance of the torch cone "
              << "from the table " << c.table << " mm, the riser " << c.riser << " mm, the deposit "
              << c.deposit << " mm; largest torch angle " << motion.total.maxTorchAngle / kDegT
              << " deg\n";
    EXPECT_GE(c.table, 0.0) << c.where;
    EXPECT_GE(c.riser, 0.0) << c.where;
    EXPECT_GE(c.deposit, 0.0) << c.where;
    std::cout << "  robot arm's capsules: smallest clearance from the table " << c.armTable
              << " mm, the positioner's body " << c.armBody << " mm, the riser " << c.armRiser
              << " mm, the deposit " << c.armDeposit << " mm\n";
    ASSERT_TRUE(placed.robot.links.known());
    EXPECT_GE(c.armTable, 0.0) << c.where;
    EXPECT_GE(c.armBody, 0.0) << c.where;
    EXPECT_GE(c.armRiser, 0.0) << c.where;
    EXPECT_GE(c.armDeposit, 0.0) << c.where;
    expectOwnLanguageReadsBack(motion, placed, language);
    expectAxisSpeedsFromCsv(motion, placed);
    expectA2Steps(motion);
  }
}

}  // namespace
}  // namespace curvedslicer
