// Tests of export/krl_writer.hpp: the .src is parsed back; E6POS positions with E1/E2 land on the
// planned path through the positioner's forward kinematics; first motion PTP; arc by TRIGGER.
#include "curvedslicer/export/krl_writer.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "export_test_support.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

struct KrlMove {
  std::string line;
  bool jointTarget = false;    ///< an E6AXIS (the home pose): A1..A6 in `joints`
  Pose tcp;                    ///< an E6POS: the TCP pose it states
  std::vector<double> joints;  ///< deg
  double e1 = 0.0, e2 = 0.0;
};

std::vector<KrlMove> parseKrlMoves(const std::string& text, bool crlf, bool* endingsOk) {
  std::vector<KrlMove> moves;
  for (const std::string& line : splitLines(text, crlf, endingsOk)) {
    if (line.rfind("PTP {", 0) != 0 && line.rfind("LIN {", 0) != 0) continue;
    KrlMove m;
    m.line = line;
    m.jointTarget = line.find("{A1 ") != std::string::npos;
    if (m.jointTarget) {
      EXPECT_EQ(line.rfind("PTP ", 0), 0u) << "a joint target is a PTP: " << line;
      for (const char* key : {"{A1 ", ",A2 ", ",A3 ", ",A4 ", ",A5 ", ",A6 "}) {
        m.joints.push_back(valueAfter(line, key));
      }
    } else {
      // A about z (yaw), B about y (pitch), C about x (roll).
      m.tcp =
          poseFromXyzRpy(valueAfter(line, "{X "), valueAfter(line, ",Y "), valueAfter(line, ",Z "),
                         valueAfter(line, ",C "), valueAfter(line, ",B "), valueAfter(line, ",A "));
      EXPECT_NE(line.find(",S "), std::string::npos) << line;
      EXPECT_NE(line.find(",T "), std::string::npos) << line;
    }
    m.e1 = valueAfter(line, ",E1 ");
    m.e2 = valueAfter(line, ",E2 ");
    moves.push_back(m);
  }
  return moves;
}

/// Part-frame point a move states: an E6POS through the table (coordinated) or world frame, an
/// E6AXIS through forward kinematics.
Vec3 partPointOf(const KrlMove& m, const Cell& cell, bool coordinated, double a1, double a2) {
  if (m.jointTarget) return partPointFromJointDegrees(cell, m.joints, a1, a2);
  return coordinated ? partPointFromTable(cell, m.tcp, a1, a2)
                     : partPointFromWorld(cell, m.tcp.translation(), a1, a2);
}

TEST(KrlWriter, PositionsAndExternalAxesLandOnThePlannedPath) {
  const Cell cell = defaultCell();
  const Plan plan = makeConePlan(3, 24);
  const MotionPlan motion = planMotion(plan, cell);
  Cell lf = cell;
  lf.exportOptions.lineEnding = LineEnding::Lf;
  const ExportResult result = KrlWriter().write(motion, lf, {}, {});
  ASSERT_EQ(result.files.size(), 1u);
  EXPECT_EQ(result.files[0].name, "WAAM.src");
  const std::string& text = result.files[0].text;
  bool lfOk = false;
  const std::vector<KrlMove> moves = parseKrlMoves(text, false, &lfOk);
  EXPECT_TRUE(lfOk);
  ASSERT_EQ(moves.size(), motion.points.size());
  EXPECT_EQ(moves[0].line.rfind("PTP ", 0), 0u) << "first motion must be PTP";
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const double a1 = cell.positioner.tilt.sign * moves[i].e1 * kDegT;
    const double a2 = cell.positioner.rotation.sign * moves[i].e2 * kDegT;
    EXPECT_NEAR(a1, motion.points[i].a1, 1e-6);
    EXPECT_NEAR(a2, motion.points[i].a2, 1e-6);
    const Vec3 p = partPointOf(moves[i], placedCell(cell, motion), true, a1, a2);
    EXPECT_LT((p - motion.points[i].position).norm(), 0.01) << moves[i].line;
    // the home pose as a joint target (PTP E6AXIS), every other move linear
    const bool home = motion.points[i].kind == MoveKind::Home;
    EXPECT_EQ(moves[i].jointTarget, home) << moves[i].line;
    if (i > 0 && !home) {
      EXPECT_EQ(moves[i].line.rfind("LIN ", 0), 0u) << moves[i].line;
    }
  }
  EXPECT_NE(text.find("$BASE=EK(MACHINE_DEF[2].ROOT,MACHINE_DEF[2].MECH_TYPE,BASE_DATA[1])"),
            std::string::npos);
  EXPECT_NE(text.find("$ACT_EX_AX=2"), std::string::npos);
  // Arc outputs only through TRIGGER (a plain $OUT stops the advance run), one on/off per path.
  std::size_t on = 0, off = 0, plain = 0, pos = 0;
  while ((pos = text.find("$OUT[", pos)) != std::string::npos) {
    const std::size_t lineStart = text.rfind('\n', pos) + 1;
    const std::string line = text.substr(lineStart, text.find('\n', pos) - lineStart);
    if (line.rfind("TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[1]=TRUE", 0) == 0) {
      ++on;
    } else if (line.rfind("TRIGGER WHEN DISTANCE=1 DELAY=0 DO $OUT[1]=FALSE", 0) == 0) {
      ++off;
    } else {
      ++plain;
    }
    pos += 5;
  }
  EXPECT_EQ(on, plan.pathCount());
  EXPECT_EQ(off, plan.pathCount());
  EXPECT_EQ(plain, 0u);
}

TEST(KrlWriter, WorldPositionsWithoutCoordination) {
  Cell cell = defaultCell();
  cell.exportOptions.coordinated = false;
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  const std::string text = KrlWriter().write(motion, cell, {}, {}).files[0].text;
  EXPECT_NE(text.find("$BASE=$NULLFRAME"), std::string::npos);
  bool ok = false;
  const auto moves = parseKrlMoves(text, true, &ok);
  EXPECT_TRUE(ok);  // the cell's CRLF
  ASSERT_EQ(moves.size(), motion.points.size());
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const double a1 = moves[i].e1 * kDegT, a2 = moves[i].e2 * kDegT;
    const Vec3 p = partPointOf(moves[i], placedCell(cell, motion), false, a1, a2);
    EXPECT_LT((p - motion.points[i].position).norm(), 0.01) << moves[i].line;
  }
  EXPECT_THROW(KrlWriter().write(MotionPlan{}, cell, {}, {}), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
