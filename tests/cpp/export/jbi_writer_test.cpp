// Tests of export/jbi_writer.hpp: the job files are parsed back (NPOS, declarations, references,
// names, line limits, CRLF) and every position, decoded from pulses / Cartesian values through
// the forward kinematics, lands on the planned path.
#include "curvedslicer/export/jbi_writer.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "export_test_support.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

constexpr double kPathTolerance = 0.01;  // mm, acceptance

struct Program {
  std::map<std::string, JbiJob> jobs;
  std::vector<std::string> order;  ///< jobs in execution order
};

/// Parses every file of a JBI export and checks the structural rules on each job.
Program parseAndCheck(const ExportResult& result, const Cell& cell) {
  Program program;
  for (const ExportFile& f : result.files) {
    JbiJob job = parseJbi(f.text);
    EXPECT_TRUE(job.crlf) << f.name << ": every line must end in CRLF";
    EXPECT_EQ(f.name, job.name + ".JBI");
    EXPECT_LE(job.name.size(), static_cast<std::size_t>(cell.exportOptions.maxNameLength));
    EXPECT_LE(job.instructions.size(), static_cast<std::size_t>(cell.exportOptions.maxLinesPerJob))
        << job.name;
    EXPECT_FALSE(job.instructions.empty());
    if (!job.instructions.empty()) {
      EXPECT_EQ(job.instructions.front(), "NOP");
      EXPECT_EQ(job.instructions.back(), "END");
    }
    // NPOS: robot and station counts equal the declared positions.
    EXPECT_EQ(job.npos.size(), 6u);
    if (job.npos.size() == 6) {
      EXPECT_EQ(job.npos[0], static_cast<long>(job.c.size())) << job.name;
      EXPECT_EQ(job.npos[2], static_cast<long>(job.ec.size())) << job.name;
      EXPECT_EQ(job.npos[1] + job.npos[3] + job.npos[4] + job.npos[5], 0);
    }
    for (const auto& [k, n] : job.cDeclared) EXPECT_EQ(n, 1) << "C" << k << " in " << job.name;
    for (const auto& [k, n] : job.ecDeclared) EXPECT_EQ(n, 1) << "EC" << k << " in " << job.name;
    // Every reference declared; every declaration referenced exactly once.
    std::map<int, int> cRefs, ecRefs;
    for (const std::string& line : job.instructions) {
      std::vector<int> c, ec;
      collectReferences(line, c, ec);
      for (int k : c) ++cRefs[k];
      for (int k : ec) ++ecRefs[k];
    }
    for (const auto& [k, n] : cRefs) EXPECT_TRUE(job.c.count(k)) << "C" << k << " undeclared";
    for (const auto& [k, n] : ecRefs) EXPECT_TRUE(job.ec.count(k)) << "EC" << k << " undeclared";
    EXPECT_EQ(cRefs.size(), job.c.size());
    EXPECT_EQ(ecRefs.size(), job.ec.size());
    program.jobs[job.name] = std::move(job);
  }
  // Execution order: the main job (first file) itself, or the jobs it calls.
  const JbiJob& main = program.jobs[parseJbi(result.files.front().text).name];
  bool calls = false;
  for (const std::string& line : main.instructions) {
    if (line.rfind("CALL JOB:", 0) == 0) {
      calls = true;
      const std::string name = line.substr(9);
      EXPECT_TRUE(program.jobs.count(name)) << "called job missing: " << name;
      program.order.push_back(name);
    }
  }
  if (!calls) program.order.push_back(main.name);
  EXPECT_EQ(program.jobs.size(), program.order.size() + (calls ? 1 : 0));
  return program;
}

/// One decoded motion: instruction text and the part-frame point the program states.
struct DecodedMove {
  std::string instruction;
  Vec3 partPoint;
  double a1 = 0.0, a2 = 0.0;
};

std::vector<DecodedMove> decodeMoves(const Program& program, const Cell& cell) {
  std::vector<DecodedMove> moves;
  for (const std::string& name : program.order) {
    const JbiJob& job = program.jobs.at(name);
    for (const std::string& line : job.instructions) {
      std::vector<int> c, ec;
      collectReferences(line, c, ec);
      if (c.empty()) continue;
      EXPECT_EQ(c.size(), 1u);
      EXPECT_EQ(ec.size(), 1u) << "every robot move carries the station: " << line;
      if (c.size() != 1 || ec.size() != 1) continue;
      const auto& cv = job.c.at(c[0]);
      const auto& ev = job.ec.at(ec[0]);
      DecodedMove m;
      m.instruction = line;
      m.a1 = tiltFromPulses(cell, ev.at(0));
      m.a2 = rotationFromPulses(cell, ev.at(1));
      Pose tcpInBase;  // PULSE: in the robot base frame; BASE: in Yaskawa's robot coordinates
      if (job.cPosType == "PULSE") {
        JointVector joints{};
        for (int j = 0; j < 6; ++j) {
          joints[j] = cv.at(j) / cell.robot.pulsesPerDegree[j] * kDegT;
        }
        tcpInBase = computeFlangePose(cell.robot, joints) * cell.tool.tcp;
      } else {
        EXPECT_EQ(job.cPosType, "BASE");
        tcpInBase = poseFromXyzRpy(cv.at(0), cv.at(1), cv.at(2), cv.at(3), cv.at(4), cv.at(5));
      }
      m.partPoint = job.cPosType == "PULSE"
                        ? partPointFromRobotBase(cell, tcpInBase, m.a1, m.a2)
                        : partPointFromControllerFrame(cell, tcpInBase, m.a1, m.a2);
      moves.push_back(m);
    }
  }
  return moves;
}

void expectOnPlannedPath(const std::vector<DecodedMove>& moves, const MotionPlan& motion) {
  ASSERT_EQ(moves.size(), motion.points.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const double e = (moves[i].partPoint - motion.points[i].position).norm();
    worst = std::max(worst, e);
    EXPECT_LT(e, kPathTolerance) << "motion " << i << ": " << moves[i].instruction;
  }
  ::testing::Test::RecordProperty("worst_deviation_um", static_cast<int>(worst * 1000.0));
}

TEST(JbiWriter, CartesianJobReadsBackOntoThePlannedPath) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  const ExportResult result = JbiWriter().write(motion, cell, {}, {});
  ASSERT_EQ(result.files.size(), 1u);
  EXPECT_EQ(result.files[0].name, "WAAM.JBI");
  const Program program = parseAndCheck(result, cell);
  expectOnPlannedPath(decodeMoves(program, placedCell(cell, motion)), motion);
  EXPECT_EQ(result.motionCount, motion.points.size());
  EXPECT_EQ(result.arcCount, 4u);
}

// Yaskawa's robot coordinates (POSTYPE BASE) have their origin on the S axis at the height of the
// L axis, 505 mm above the floor for the HP20D. Its home (S, L, U, R, B, T = 0, -20, -10, 0, -100,
// 0 deg, 400 mm straight torch) puts the TCP 648.7 mm in front of the S axis and 995.1 mm above
// the floor: 490.1 mm in robot coordinates.
TEST(JbiWriter, Hp20dHomeIsWrittenInRobotCoordinatesAtLAxisHeight) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  ASSERT_EQ(motion.points.front().kind, MoveKind::Home);
  const ExportResult result = JbiWriter().write(motion, cell, {}, {});
  const JbiJob job = parseJbi(result.files.front().text);
  ASSERT_EQ(job.cPosType, "BASE");
  const std::vector<double>& home = job.c.at(0);
  ASSERT_EQ(home.size(), 6u);
  EXPECT_NEAR(home[0], 648.7, 0.05);
  EXPECT_NEAR(home[1], 0.0, 1e-3);
  EXPECT_NEAR(home[2], 490.1, 0.05);
  const Pose tool = poseFromXyzRpy(home[0], home[1], home[2], home[3], home[4], home[5]);
  EXPECT_LT((tool.linear().col(2) + Vec3::UnitZ()).norm(), 1e-5) << "torch pointing down";
}

// Yaskawa's flange frame (MotoSim's "flange" = ROS-Industrial tool0) at all joints 0: z forward
// out of the flange, x up. A tool file with the TCP 50 mm along flange x and 400 mm along z puts
// the TCP 400 mm in front of the flange centre (a1 + c3 + c4, 0, c1 + c2 + a2) = (1045, 0, 1405)
// mm and 50 mm above it, 950 mm above the L axis; the tool frame is the flange frame.
TEST(JbiWriter, LateralTcpOffsetLiesAlongYaskawasFlangeX) {
  Cell cell = defaultCell();
  cell.tool.tcp = makePose(Vec3(50.0, 0.0, 400.0), Vec3::Zero());
  MotionPlan motion;
  MotionPoint p;
  p.kind = MoveKind::Home;
  p.joints = {0, 0, 0, 0, 0, 0};
  p.toolInRobotBase = computeFlangePose(cell.robot, p.joints) * cell.tool.tcp;
  p.toolInWorld = cell.robot.base * p.toolInRobotBase;
  motion.points.push_back(p);
  const ExportResult result = JbiWriter().write(motion, cell, {}, {});
  const JbiJob job = parseJbi(result.files.front().text);
  const std::vector<double>& c = job.c.at(0);
  ASSERT_EQ(c.size(), 6u);
  EXPECT_NEAR(c[0], 1445.0, 1e-3);
  EXPECT_NEAR(c[1], 0.0, 1e-3);
  EXPECT_NEAR(c[2], 950.0, 1e-3);
  const Pose tool = poseFromXyzRpy(c[0], c[1], c[2], c[3], c[4], c[5]);
  EXPECT_LT((tool.linear().col(0) - Vec3::UnitZ()).norm(), 1e-5) << "tool x up";
  EXPECT_LT((tool.linear().col(2) - Vec3::UnitX()).norm(), 1e-5) << "tool z forward";
}

TEST(JbiWriter, RefusesAPointViolatingAnInterferenceLimit) {
  Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  cell.robot.interference.push_back({"L/U", {0, 1, 0, 0, 0, 0}, -30.0 * kDegT});  // home: L -20
  try {
    JbiWriter().write(motion, cell, {}, {});
    ADD_FAILURE() << "written";
  } catch (const InvalidInput& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("motion point 0"), std::string::npos) << m;
    EXPECT_NE(m.find("violates the robot's interference limit L/U (robot/interference)"),
              std::string::npos)
        << m;
  }
}

TEST(JbiWriter, PulseJobDecodesThroughForwardKinematicsOntoThePath) {
  Cell cell = defaultCell();
  cell.exportOptions.positionType = PositionType::Pulse;
  cell.robot.pulsesPerDegree = {4000.0, 4000.0, 4000.0, 3000.0, 3000.0, 2000.0};
  const MotionPlan motion = planMotion(makeConePlan(3, 24), cell);
  const ExportResult result = JbiWriter().write(motion, cell, {}, {});
  const Program program = parseAndCheck(result, cell);
  for (const auto& [name, job] : program.jobs) {
    if (!job.c.empty()) {
      EXPECT_EQ(job.cPosType, "PULSE");
    }
  }
  expectOnPlannedPath(decodeMoves(program, placedCell(cell, motion)), motion);
}

TEST(JbiWriter, ConeSurfacePlanIsCoordinatedWithOneArcPairPerPath) {
  const Cell cell = defaultCell();
  const Plan plan = makeConePlan(12, 48);
  const MotionPlan motion = planMotion(plan, cell);
  const ExportResult result = JbiWriter().write(motion, cell, {}, {});
  const Program program = parseAndCheck(result, cell);
  const std::vector<DecodedMove> moves = decodeMoves(program, placedCell(cell, motion));
  expectOnPlannedPath(moves, motion);

  // Walk the instructions in execution order: between ARCON and ARCOF every move is coordinated,
  // and the moves of one arc segment are exactly the points of one path.
  std::vector<std::pair<int, int>> arcPaths;  // (layer, path) of each ARCON … ARCOF segment
  bool arcOn = false;
  std::size_t move = 0;
  std::set<std::pair<int, int>> segmentPaths;
  for (const std::string& name : program.order) {
    for (const std::string& line : program.jobs.at(name).instructions) {
      if (line.rfind("ARCON", 0) == 0) {
        ASSERT_FALSE(arcOn) << "ARCON while the arc is on";
        arcOn = true;
        ASSERT_GT(move, 0u);
        segmentPaths = {{motion.points[move - 1].layer, motion.points[move - 1].path}};
      } else if (line.rfind("ARCOF", 0) == 0) {
        ASSERT_TRUE(arcOn) << "ARCOF without ARCON";
        arcOn = false;
        EXPECT_EQ(segmentPaths.size(), 1u) << "an arc segment spans several paths";
        arcPaths.push_back(*segmentPaths.begin());
      } else if (line.find(" C") != std::string::npos && line.find("EC") != std::string::npos) {
        if (arcOn) {
          EXPECT_EQ(line.rfind("SMOVL C", 0), 0u) << "deposition move not coordinated: " << line;
          EXPECT_NE(line.find(" +MOVJ EC"), std::string::npos) << line;
          segmentPaths.insert({motion.points[move].layer, motion.points[move].path});
          EXPECT_TRUE(motion.points[move].arcOn);
        } else {
          EXPECT_FALSE(motion.points[move].arcOn) << "welded move outside ARCON/ARCOF";
        }
        ++move;
      }
    }
  }
  EXPECT_FALSE(arcOn);
  ASSERT_EQ(arcPaths.size(), plan.pathCount());
  for (std::size_t k = 0; k < arcPaths.size(); ++k) {
    EXPECT_EQ(arcPaths[k], std::make_pair(0, static_cast<int>(k)));
  }
}

TEST(JbiWriter, SplitsIntoSubJobsWithinLineAndNameLimits) {
  Cell cell = defaultCell();
  cell.exportOptions.maxLinesPerJob = 40;
  const MotionPlan motion = planMotion(makeConePlan(4, 30), cell);
  const ExportResult result = JbiWriter().write(motion, cell, {}, {});
  ASSERT_GT(result.files.size(), 3u);
  const Program program = parseAndCheck(result, cell);
  EXPECT_EQ(program.order.size() + 1, result.files.size());
  std::set<std::string> names;
  for (const ExportFile& f : result.files) EXPECT_TRUE(names.insert(f.name).second) << f.name;
  expectOnPlannedPath(decodeMoves(program, placedCell(cell, motion)), motion);
  // 32-character names (DX100 and later) keep the whole requested name.
  cell.exportOptions.maxNameLength = 32;
  ExportOptions options;
  options.programName = "turbine base blade";
  const ExportResult longNames = JbiWriter().write(motion, cell, options, {});
  EXPECT_EQ(longNames.files[0].name, "TURBINE_BASE_BLADE.JBI");
  parseAndCheck(longNames, cell);
}

TEST(JbiWriter, WritesDirectArcConditionsAndDwell) {
  Cell cell = defaultCell();
  cell.process.arcControl = ArcControl::Direct;
  cell.process.current = 180.0;
  cell.process.voltage = 19.5;
  cell.process.arcStartTime = 0.3;
  cell.process.pathDwell = 2.0;
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  const std::string text = JbiWriter().write(motion, cell, {}, {}).files[0].text;
  EXPECT_NE(text.find("\r\nARCON AC=180 AV=19.5 T=0.30\r\n"), std::string::npos);
  EXPECT_NE(text.find("\r\nARCOF\r\n"), std::string::npos);
  EXPECT_NE(text.find("\r\nTIMER T=2.00\r\n"), std::string::npos);
  EXPECT_NE(text.find("\r\nTIMER T=62.00\r\n"), std::string::npos);  // path + layer dwell
  EXPECT_EQ(text.find("ASF#"), std::string::npos);
}

TEST(JbiWriter, WritesSpeedsInTheCellsUnit) {
  Cell cell = defaultCell();
  cell.process.speedUnit = SpeedUnit::CentimetresPerMinute;
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  const std::string text = JbiWriter().write(motion, cell, {}, {}).files[0].text;
  EXPECT_NE(text.find(" V=48 +MOVJ"), std::string::npos);   // 8 mm/s weld
  EXPECT_NE(text.find(" V=300 +MOVJ"), std::string::npos);  // 50 mm/s travel
}

TEST(JbiWriter, RefusesWhatItCannotWrite) {
  Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  EXPECT_THROW(JbiWriter().write(MotionPlan{}, cell, {}, {}), InvalidInput);
  Cell user = cell;
  user.exportOptions.positionType = PositionType::User;
  EXPECT_THROW(JbiWriter().write(motion, user, {}, {}), InvalidInput);
  Cell pulse = cell;
  pulse.exportOptions.positionType = PositionType::Pulse;  // default cell has no robot pulses
  EXPECT_THROW(JbiWriter().write(motion, pulse, {}, {}), InvalidInput);
  Cell tiny = cell;
  tiny.exportOptions.maxLinesPerJob = 2;
  EXPECT_THROW(JbiWriter().write(motion, tiny, {}, {}), InvalidInput);
}

TEST(JbiWriter, RefusesAPathCrossingAJointLimit) {
  const Cell cell = defaultCell();
  MotionPlan motion = planMotion(makeSmallPlan(), cell);
  motion.points[4].joints[4] = cell.robot.joints[4].max + 2.0 * kDegT;
  try {
    JbiWriter().write(motion, cell, {}, {});
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("robot joint 5"), std::string::npos) << what;
    EXPECT_NE(what.find("by 2.000 deg"), std::string::npos) << what;
    EXPECT_NE(what.find("motion point 4"), std::string::npos) << what;
  }
  motion = planMotion(makeSmallPlan(), cell);
  motion.points[1].a1 = cell.positioner.tilt.limit.min - 0.5 * kDegT;
  EXPECT_THROW(JbiWriter().write(motion, cell, {}, {}), InvalidInput);
}

TEST(JbiWriter, CancelsThroughProgress) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  const Progress cancel([](double, std::string_view) { return false; });
  EXPECT_THROW(JbiWriter().write(motion, cell, {}, cancel), Cancelled);
}

TEST(JbiWriter, IsDeterministic) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeConePlan(2, 16), cell);
  const ExportResult a = JbiWriter().write(motion, cell, {}, {});
  const ExportResult b = JbiWriter().write(motion, cell, {}, {});
  ASSERT_EQ(a.files.size(), b.files.size());
  for (std::size_t k = 0; k < a.files.size(); ++k) EXPECT_EQ(a.files[k].text, b.files[k].text);
}

}  // namespace
}  // namespace curvedslicer
