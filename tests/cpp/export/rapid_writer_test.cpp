// Tests of export/rapid_writer.hpp: robtargets with extax parsed back land on the planned path;
// coordinated work object, ActUnit, one SetDO pair per path.
#include "curvedslicer/export/rapid_writer.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "export_test_support.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

/// The numbers of the inline robtarget of a MoveJ/MoveL line, in order.
std::vector<double> robtargetNumbers(const std::string& line) {
  const std::size_t begin = line.find("[[");
  const std::size_t end = line.find("]]", begin);
  std::string inner = line.substr(begin, end - begin);
  for (char& c : inner) {
    if (c == '[' || c == ']') c = ',';
  }
  std::vector<double> values;
  for (const auto& f : splitFields(inner, ',')) {
    if (!f.empty()) values.push_back(std::stod(f));
  }
  return values;
}

TEST(RapidWriter, RobtargetsAndExtaxLandOnThePlannedPath) {
  const Cell cell = defaultCell();
  const Plan plan = makeConePlan(3, 24);
  const MotionPlan motion = planMotion(plan, cell);
  const ExportResult result = RapidWriter().write(motion, cell, {}, {});
  ASSERT_EQ(result.files.size(), 1u);
  EXPECT_EQ(result.files[0].name, "WAAM.mod");
  const std::string& text = result.files[0].text;
  bool crlf = false;
  const auto lines = splitLines(text, true, &crlf);
  EXPECT_TRUE(crlf);
  EXPECT_EQ(lines.front(), "MODULE WAAM");
  EXPECT_EQ(lines.back(), "ENDMODULE");
  EXPECT_NE(text.find("[FALSE, FALSE, \"STN1\","), std::string::npos);
  EXPECT_NE(text.find("ActUnit STN1;"), std::string::npos);
  std::size_t move = 0, on = 0, off = 0;
  for (const std::string& line : lines) {
    if (line.find("SetDO doArc1, 1;") != std::string::npos) ++on;
    if (line.find("SetDO doArc1, 0;") != std::string::npos) ++off;
    const bool j = line.find("MoveJ [[") != std::string::npos;
    const bool l = line.find("MoveL [[") != std::string::npos;
    const bool absJ = line.find("MoveAbsJ [[") != std::string::npos;
    if (!j && !l && !absJ) continue;
    ASSERT_LT(move, motion.points.size());
    // the home pose as a jointtarget (MoveAbsJ), every other move a robtarget (the first MoveJ)
    const bool home = motion.points[move].kind == MoveKind::Home;
    EXPECT_EQ(absJ, home) << line;
    EXPECT_EQ(j, move == 0 && !home) << line;
    const std::vector<double> v = robtargetNumbers(line);
    Vec3 p;
    double a1 = 0.0, a2 = 0.0;
    if (absJ) {
      ASSERT_EQ(v.size(), 12u) << line;  // 6 + 6
      EXPECT_EQ(v[8], 9e9);
      a1 = v[6] * kDegT;
      a2 = v[7] * kDegT;
      p = partPointFromJointDegrees(placedCell(cell, motion), {v.begin(), v.begin() + 6}, a1, a2);
    } else {
      EXPECT_NE(line.find("\\WObj:=wobjTable;"), std::string::npos);
      ASSERT_EQ(v.size(), 17u) << line;  // 3 + 4 + 4 + 6
      EXPECT_EQ(v[13], 9e9);
      const Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
      EXPECT_NEAR(q.norm(), 1.0, 1e-7);
      Pose tcp = Pose::Identity();
      tcp.linear() = q.normalized().toRotationMatrix();
      tcp.translation() = Vec3(v[0], v[1], v[2]);
      a1 = v[11] * kDegT;
      a2 = v[12] * kDegT;
      p = partPointFromTable(placedCell(cell, motion), tcp, a1, a2);
    }
    EXPECT_NEAR(a1, motion.points[move].a1, 1e-6);
    EXPECT_NEAR(a2, motion.points[move].a2, 1e-6);
    EXPECT_LT((p - motion.points[move].position).norm(), 0.01) << line;
    ++move;
  }
  EXPECT_EQ(move, motion.points.size());
  EXPECT_EQ(on, plan.pathCount());
  EXPECT_EQ(off, plan.pathCount());
  EXPECT_THROW(RapidWriter().write(MotionPlan{}, cell, {}, {}), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
