// Tests of export/gcode_writer.hpp: TCP mode states the part-frame point and the table angles;
// machine mode's X Y Z, taken back through the table kinematics, land on the planned path.
#include "curvedslicer/export/gcode_writer.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "export_test_support.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

struct GMove {
  std::string line;
  Vec3 xyz;
  double a = 0.0, c = 0.0;
};

std::vector<GMove> parseGcode(const std::string& text, std::size_t* on, std::size_t* off) {
  bool ok = false;
  std::vector<GMove> moves;
  *on = *off = 0;
  for (const std::string& line : splitLines(text, true, &ok)) {
    if (line == "M3") ++*on;
    if (line == "M5") ++*off;
    if (line.rfind("G0 ", 0) != 0 && line.rfind("G1 ", 0) != 0) continue;
    GMove m;
    m.line = line;
    m.xyz = Vec3(valueAfter(line, " X"), valueAfter(line, " Y"), valueAfter(line, " Z"));
    m.a = valueAfter(line, " A");
    m.c = valueAfter(line, " C");
    moves.push_back(m);
  }
  EXPECT_TRUE(ok);
  return moves;
}

TEST(GcodeWriter, TcpModeStatesPartPointsAndTableAngles) {
  const Cell cell = defaultCell();
  const Plan plan = makeConePlan(3, 24);
  const MotionPlan motion = planMotion(plan, cell);
  // the writer gets the cell the motion was planned in (the part where the placement put it)
  const ExportResult result = GcodeWriter().write(motion, placedCell(cell, motion), {}, {});
  EXPECT_EQ(result.files[0].name, "WAAM.ngc");
  const std::string& text = result.files[0].text;
  EXPECT_NE(text.find("; mode: tcp"), std::string::npos);
  EXPECT_NE(text.find("; axes: A = tilt a1, sign 1; C = rotation a2, sign 1"), std::string::npos);
  EXPECT_NE(text.find("; pivot: tilt axis point 0.000 0.000 380.000 mm"), std::string::npos);
  const std::size_t tableToPart = text.find("; table to part: translation ");
  ASSERT_NE(tableToPart, std::string::npos);
  std::istringstream placement(text.substr(tableToPart + 29));
  Vec3 t;
  placement >> t.x() >> t.y() >> t.z();
  EXPECT_LT((t - motion.tableToPart.translation()).norm(), 0.001) << "the placement used";
  std::size_t on = 0, off = 0;
  const auto moves = parseGcode(text, &on, &off);
  ASSERT_EQ(moves.size(), motion.points.size());
  for (std::size_t i = 0; i < moves.size(); ++i) {
    EXPECT_LT((moves[i].xyz - motion.points[i].position).norm(), 0.001);
    EXPECT_NEAR(moves[i].a * kDegT, motion.points[i].a1, 1e-6);
    EXPECT_NEAR(moves[i].c * kDegT, motion.points[i].a2, 1e-6);
    // rapid (G0, no feed) to the first point and the home pose; every other move feeds at its
    // planned speed
    const bool rapid = i == 0 || motion.points[i].kind == MoveKind::Home;
    EXPECT_EQ(moves[i].line.rfind(rapid ? "G0 " : "G1 ", 0), 0u) << moves[i].line;
    if (rapid) {
      EXPECT_EQ(moves[i].line.find(" F"), std::string::npos) << moves[i].line;
    } else {
      EXPECT_NEAR(valueAfter(moves[i].line, " F"), motion.points[i].speed * 60.0, 0.05);
    }
  }
  EXPECT_EQ(on, plan.pathCount());
  EXPECT_EQ(off, plan.pathCount());
}

TEST(GcodeWriter, MachineModeInvertsThroughTheTableKinematics) {
  Cell cell = defaultCell();
  cell.positioner.tilt.sign = -1;  // the header records it and the angles follow it
  cell.positioner.tableToPart = makePose(Vec3(5, -3, 20), Vec3(0, 0, 0.3));
  const MotionPlan motion = planMotion(makeConePlan(2, 24), cell);
  cell = placedCell(cell, motion);  // the cell the motion was planned in
  ExportOptions options;
  options.gcodeMode = GcodeMode::Machine;
  const std::string text = GcodeWriter().write(motion, cell, options, {}).files[0].text;
  EXPECT_NE(text.find("; mode: machine"), std::string::npos);
  EXPECT_NE(text.find("A = tilt a1, sign -1"), std::string::npos);
  std::size_t on = 0, off = 0;
  const auto moves = parseGcode(text, &on, &off);
  ASSERT_EQ(moves.size(), motion.points.size());
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const double a1 = -moves[i].a * kDegT, a2 = moves[i].c * kDegT;
    const Vec3 p = computePartInPositionerBase(cell.positioner, a1, a2).inverse() * moves[i].xyz;
    EXPECT_LT((p - motion.points[i].position).norm(), 0.01) << moves[i].line;
  }
  EXPECT_THROW(GcodeWriter().write(MotionPlan{}, cell, options, {}), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
