// Configuration bits / turn numbers in the JBI, KRL, RAPID and LS exports: read back by the strict
// readers of program_readers.hpp, they must be constant within every weld (from the move onto the
// path start, after which the arc goes on, to the move after which it goes off) and be the
// weld's configuration (MotionPathSpan::configuration); arc-off points state their own. Synthetic
// motions put joints on the boundaries rounding noise flips (J4 exactly 0 among ±1e-16, J6
// crossing -180°), so a writer that recomputed the configuration per point would fail here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/robot/configuration.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"
#include "export_test_support.hpp"
#include "program_readers.hpp"
#include "synthetic_motion.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

TEST(ConfigurationBits, NoiseOnABoundaryDoesNotFlipThemWithinAWeld) {
  const MotionPlan motion = makeNoisyMotion();
  // The premise: recomputed per point, the configuration would flip inside both welds.
  for (const MotionPathSpan& span : motion.paths) {
    bool flips = false;
    for (std::size_t i = span.begin; i < span.end; ++i) {
      const MotionPoint& p = motion.points[i];
      flips = flips || configurationOf(p.joints, p.configuration) != span.configuration;
    }
    EXPECT_TRUE(flips) << "weld " << span.path << " has no noise on a boundary";
  }
  const Cell cell = defaultCell();
  for (ExportFormat format : kRobotFormats) {
    const std::string name(toString(format));
    const ReadProgram program = exportAndRead(motion, cell, format);
    ASSERT_EQ(program.moves.size(), motion.points.size()) << name;
    ASSERT_EQ(program.welds.size(), motion.paths.size()) << name;
    expectConstantWithinWelds(program, name);
    for (std::size_t w = 0; w < motion.paths.size(); ++w) {
      const MotionPathSpan& span = motion.paths[w];
      EXPECT_EQ(program.welds[w].first, span.begin) << name;
      EXPECT_EQ(program.welds[w].second, span.end - 1) << name;
      for (std::size_t i = span.begin; i < span.end; ++i) {
        ASSERT_TRUE(program.moves[i].configuration) << name << ": " << program.moves[i].line;
        expectStates(*program.moves[i].configuration, span.configuration,
                     name + ": " + program.moves[i].line);
      }
    }
    // Arc-off points state the configuration of their own joints (home is a joint target, or
    // Cartesian with its own configuration in JBI).
    for (std::size_t i = 0; i < motion.points.size(); ++i) {
      const MotionPoint& p = motion.points[i];
      if (p.kind == MoveKind::Path || !program.moves[i].configuration) continue;
      expectStates(*program.moves[i].configuration, configurationOf(p.joints, p.configuration),
                   name + " arc-off: " + program.moves[i].line);
    }
  }
}

TEST(ConfigurationBits, JbiWithTwentyFourRconfFieldsKeepsThemToo) {
  Cell cell = defaultCell();
  cell.exportOptions.maxNameLength = 32;  // DX100 and later: 24 RCONF fields
  const MotionPlan motion = makeNoisyMotion();
  const ReadProgram program = exportAndRead(motion, cell, ExportFormat::Jbi);
  ASSERT_EQ(program.moves.size(), motion.points.size());
  expectConstantWithinWelds(program, "jbi");
  ASSERT_TRUE(program.moves[motion.paths[1].begin].configuration);
  EXPECT_EQ(program.moves[motion.paths[1].begin].configuration->text,
            "1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0");
}

TEST(ConfigurationBits, SplitJbiKeepsThemAcrossSubJobs) {
  Cell cell = defaultCell();
  cell.exportOptions.maxLinesPerJob = 9;  // forces sub-jobs, one weld continues in the next job
  const MotionPlan motion = makeNoisyMotion();
  const ExportResult r = exportProgram(motion, cell, ExportFormat::Jbi);
  ASSERT_GT(r.files.size(), 2u);
  const ReadProgram program = readJbiProgram(r, cell);
  ASSERT_EQ(program.moves.size(), motion.points.size());
  ASSERT_EQ(program.welds.size(), motion.paths.size());
  expectConstantWithinWelds(program, "split jbi");
}

TEST(ConfigurationBits, AWeldPointInAnotherBranchIsWarnedAbout) {
  const Cell cell = defaultCell();
  MotionPlan motion = makeNoisyMotion();
  for (ExportFormat format : kRobotFormats) {
    EXPECT_TRUE(exportProgram(motion, cell, format).warnings.empty()) << toString(format);
  }
  motion.points[motion.paths[0].begin + 3].configuration = 4;  // a wrist flip inside weld 0
  for (ExportFormat format : kRobotFormats) {
    const std::vector<std::string> warnings = exportProgram(motion, cell, format).warnings;
    ASSERT_EQ(warnings.size(), 1u) << toString(format);
    EXPECT_NE(warnings[0].find("1 weld point(s) lie in another IK branch"), std::string::npos)
        << warnings[0];
    EXPECT_NE(warnings[0].find("layer 0 path 0 point 3 has IK branch 4, its weld states 0"),
              std::string::npos)
        << warnings[0];
  }
}

/// The wrist centre's x in KUKA's A1 frame (the frame of $ROBROOT turned with A1, x towards the
/// arm) and the turn of the forearm from the upper arm's direction about the A2 axis (0 when the
/// arm is stretched), both from the arm's joint points.
struct ArmState {
  double wristX = 0.0;
  double bend = 0.0;
};

ArmState armState(const Cell& cell, const JointVector& q) {
  const ArmPoints a = computeArmPoints(cell.robot, q);
  const Vec3 towardsArm = Vec3(a.shoulder.x(), a.shoulder.y(), 0.0).normalized();
  const Vec3 axis2 = towardsArm.cross(Vec3::UnitZ()).normalized();  // A2's axis direction
  const Vec3 upper = a.elbow - a.shoulder, fore = a.wrist - a.elbow;
  return {a.wrist.dot(towardsArm), std::atan2(upper.cross(fore).dot(axis2), upper.dot(fore))};
}

/// A joint (index j, degrees) at which `f` changes sign between lo and hi, by bisection.
template <class F>
double signChange(JointVector q, int j, double lo, double hi, F f) {
  q[j] = lo * kDegT;
  const bool low = f(q) < 0.0;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    q[j] = mid * kDegT;
    ((f(q) < 0.0) == low ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// KUKA's definition of S and T (KUKA System Software, "Status" and "Turn"; the same table in
// Siemens' SINUMERIK programming manual 6FC5398-2EP40-0BA0 for KUKA-type robots): S bit 0 set in
// the overhead area, where the wrist centre has negative x in the A1 frame; bit 1 set when A3 is
// at or above the angle φ at which the arm is stretched (elbow up; for robots whose A3 and A4
// intersect φ = 0°, the KR 16's forearm offset moves it); bit 2 set when A5 < 0. T bit k set when
// joint k+1 < 0. Each boundary is crossed here by 2° either way, with the KR 16 cell.
TEST(ConfigurationBits, KrlStatusAndTurnFollowKukasDefinitionAcrossEachBoundary) {
  const Cell cell = readCell(std::filesystem::path(CURVEDSLICER_SOURCE_DIR) / "resources" /
                             "cells" / "kuka_kr16_r1610_2_dkp400.json");
  const JointVector base{20 * kDegT, -60 * kDegT, 40 * kDegT, 30 * kDegT, 50 * kDegT, 40 * kDegT};
  const auto bend = [&](const JointVector& q) { return armState(cell, q).bend; };
  const auto wristX = [&](const JointVector& q) { return armState(cell, q).wristX; };
  const double phi = signChange(base, 2, -100.0, 100.0, bend);
  JointVector overhead = base;
  overhead[2] = (phi + 30.0) * kDegT;
  const double a2Boundary = signChange(overhead, 1, -150.0, -60.0, wristX);
  std::vector<JointVector> poses;
  for (double d : {-2.0, 2.0}) {
    JointVector q = base;
    q[2] = (phi + d) * kDegT;  // bit 1
    poses.push_back(q);
    q = overhead;
    q[1] = (a2Boundary + d) * kDegT;  // bit 0
    poses.push_back(q);
    q = base;
    q[4] = d * 5.0 * kDegT;  // bit 2 (±10°, off the wrist singularity)
    poses.push_back(q);
    q = {d * kDegT, d * kDegT, d * kDegT, d * kDegT, 20 * d * kDegT, d * kDegT};
    poses.push_back(q);  // every T bit both ways
  }
  MotionPlan motion;
  for (const JointVector& q : poses) {
    MotionPoint p = makePoint(MoveKind::Travel, 0, -1, Vec3(0, 0, 50), q, 0, 50.0);
    const IkResult ik = solveInverseKinematics(cell.robot, computeFlangePose(cell.robot, q), q[3]);
    for (const IkSolution& s : ik.solutions) {
      bool same = true;
      for (int j = 0; j < 6; ++j) same = same && std::abs(s.joints[j] - q[j]) < 1e-7;
      if (same) p.configuration = s.configuration;
    }
    p.time = static_cast<double>(motion.points.size());
    motion.points.push_back(p);
  }
  const ExportResult r = exportProgram(motion, cell, ExportFormat::Krl);
  std::vector<std::pair<int, int>> stated;
  for (const ExportFile& f : r.files) {
    bool ok = true;
    for (const std::string& line : splitLines(f.text, false, &ok)) {
      const std::size_t at = line.find(",S ");
      int s = -1, t = -1;
      if (line.rfind("DECL E6POS XP", 0) == 0 && at != std::string::npos &&
          std::sscanf(line.c_str() + at, ",S %d,T %d", &s, &t) == 2) {
        stated.emplace_back(s, t);
      }
    }
  }
  ASSERT_EQ(stated.size(), poses.size());
  int bitsSet[3] = {0, 0, 0};
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const JointVector& q = poses[i];
    const ArmState arm = armState(cell, q);
    int s = 0, t = 0;
    if (arm.wristX < 0.0) s |= 1;
    if (q[2] >= phi * kDegT) s |= 2;
    if (q[4] < 0.0) s |= 4;
    for (int j = 0; j < 6; ++j) t |= q[j] < 0.0 ? 1 << j : 0;
    for (int b = 0; b < 3; ++b) bitsSet[b] += (s >> b) & 1;
    EXPECT_EQ(stated[i].first, s) << "pose " << i << ": A2 " << q[1] / kDegT << ", A3 "
                                  << q[2] / kDegT << " (phi " << phi << "), A5 " << q[4] / kDegT;
    EXPECT_EQ(stated[i].second, t) << "pose " << i;
  }
  for (int b = 0; b < 3; ++b) {  // each bit appears both set and clear
    EXPECT_GT(bitsSet[b], 0) << b;
    EXPECT_LT(bitsSet[b], static_cast<int>(poses.size())) << b;
  }
}

}  // namespace
}  // namespace curvedslicer
