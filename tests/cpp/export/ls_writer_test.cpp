// Tests of export/ls_writer.hpp: /POS points (GP1 XYZWPR, GP2 J1 J2) parsed back land on the
// planned path; /MN numbering, COORD on linear moves, one Arc Start/End pair per path.
#include "curvedslicer/export/ls_writer.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "export_test_support.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

TEST(LsWriter, PositionsOfBothGroupsLandOnThePlannedPath) {
  const Cell cell = defaultCell();
  const Plan plan = makeConePlan(3, 20);
  const MotionPlan motion = planMotion(plan, cell);
  const ExportResult result = LsWriter().write(motion, cell, {}, {});
  ASSERT_EQ(result.files.size(), 1u);
  EXPECT_EQ(result.files[0].name, "WAAM.LS");
  const std::string& text = result.files[0].text;
  bool crlf = false;
  const auto lines = splitLines(text, true, &crlf);
  EXPECT_TRUE(crlf);
  EXPECT_EQ(lines.front(), "/PROG  WAAM");
  EXPECT_NE(text.find("DEFAULT_GROUP\t= 1,1,*,*,*;"), std::string::npos);
  enum { kHead, kMn, kPos } section = kHead;
  std::size_t numbered = 0, moves = 0, arcStart = 0, arcEnd = 0, declaredLineCount = 0;
  std::vector<std::string> blocks;
  for (const std::string& line : lines) {
    if (line.rfind("LINE_COUNT", 0) == 0) {
      declaredLineCount = static_cast<std::size_t>(valueAfter(line, "= "));
    }
    if (line == "/MN") {
      section = kMn;
      continue;
    }
    if (line == "/POS") {
      section = kPos;
      continue;
    }
    if (section == kMn) {
      unsigned n = 0;
      ASSERT_EQ(std::sscanf(line.c_str(), "%u:", &n), 1) << line;
      EXPECT_EQ(n, ++numbered);
      if (line.find(" L P[") != std::string::npos || line.find(" J P[") != std::string::npos) {
        ++moves;
        ASSERT_LE(moves, motion.points.size()) << line;
        // joint moves: the first (from an unknown pose) and every move to the home pose
        const bool joint = moves == 1 || motion.points[moves - 1].kind == MoveKind::Home;
        EXPECT_EQ(line.find(" J P[") != std::string::npos, joint) << line;
        if (!joint) {
          EXPECT_NE(line.find(" COORD ;"), std::string::npos) << line;
        }
        EXPECT_NE(line.find("P[" + std::to_string(moves) + "]"), std::string::npos);
      }
      if (line.find("Arc Start[1]") != std::string::npos) ++arcStart;
      if (line.find("Arc End[1]") != std::string::npos) ++arcEnd;
    } else if (section == kPos) {
      if (line.rfind("P[", 0) == 0) blocks.emplace_back();
      if (!blocks.empty()) blocks.back() += line + "\n";
    }
  }
  EXPECT_EQ(declaredLineCount, numbered);
  EXPECT_EQ(moves, motion.points.size());
  EXPECT_EQ(arcStart, plan.pathCount());
  EXPECT_EQ(arcEnd, plan.pathCount());
  ASSERT_EQ(blocks.size(), motion.points.size());
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const std::string& b = blocks[i];
    EXPECT_EQ(b.rfind("P[" + std::to_string(i + 1) + "]{", 0), 0u);
    const std::size_t gp2 = b.find("GP2:");
    ASSERT_NE(gp2, std::string::npos) << b;
    const std::string robot = b.substr(0, gp2), station = b.substr(gp2);
    const double a1 = valueAfter(station, "J1 = ") * kDegT;
    const double a2 = valueAfter(station, "J2 = ") * kDegT;
    EXPECT_NEAR(a1, motion.points[i].a1, 1e-6);
    EXPECT_NEAR(a2, motion.points[i].a2, 1e-6);
    Vec3 p;
    if (motion.points[i].kind == MoveKind::Home) {
      // the home pose in joint representation, through forward kinematics
      EXPECT_EQ(robot.find("X = "), std::string::npos) << b;
      std::vector<double> joints;
      for (const char* key : {"J1 = ", "J2 = ", "J3 = ", "J4 = ", "J5 = ", "J6 = "}) {
        joints.push_back(valueAfter(robot, key));
      }
      p = partPointFromJointDegrees(placedCell(cell, motion), joints, a1, a2);
    } else {
      const Pose tcp = poseFromXyzRpy(valueAfter(robot, "X = "), valueAfter(robot, "Y = "),
                                      valueAfter(robot, "Z = "), valueAfter(robot, "W = "),
                                      valueAfter(robot, "P = "), valueAfter(robot, "R = "));
      p = partPointFromTable(placedCell(cell, motion), tcp, a1, a2);
    }
    EXPECT_LT((p - motion.points[i].position).norm(), 0.01) << b;
  }
  EXPECT_THROW(LsWriter().write(MotionPlan{}, cell, {}, {}), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
