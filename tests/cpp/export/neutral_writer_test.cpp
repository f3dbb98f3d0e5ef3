// Tests of export/neutral_writer.hpp: CSV and JSON rows read back to exactly the motion plan's
// numbers (shortest round-trip form).
#include "curvedslicer/export/neutral_writer.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "curvedslicer/core/error.hpp"
#include "export_test_support.hpp"

namespace curvedslicer {
namespace {

using namespace testing;

void expectRow(const std::vector<double>& v, const MotionPoint& p) {
  ASSERT_EQ(v.size(), 27u);
  EXPECT_EQ(v[0], p.layer);
  EXPECT_EQ(v[1], p.path);
  EXPECT_EQ(v[2], p.index);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(v[3 + k], p.position[k]);
    EXPECT_EQ(v[6 + k], p.normal[k]);
    EXPECT_EQ(v[9 + k], p.deposition[k]);
  }
  EXPECT_EQ(v[12], p.a1 * (180.0 / kPiT));
  EXPECT_EQ(v[13], p.a2 * (180.0 / kPiT));
  for (int j = 0; j < 6; ++j) EXPECT_EQ(v[14 + j], p.joints[j] * (180.0 / kPiT));
  EXPECT_EQ(v[20], p.speed);
  EXPECT_EQ(v[21], p.arcOn ? 1 : 0);
  EXPECT_EQ(v[22], p.pathStart ? 1 : 0);
  EXPECT_EQ(v[23], p.pathEnd ? 1 : 0);
  EXPECT_EQ(v[26], p.flags);
}

TEST(NeutralWriter, CsvRowsReadBackExactly) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeConePlan(2, 12), cell);
  const ExportResult result = NeutralWriter(ExportFormat::Csv).write(motion, cell, {}, {});
  EXPECT_EQ(result.files[0].name, "WAAM.csv");
  bool lf = false;
  const auto lines = splitLines(result.files[0].text, false, &lf);
  EXPECT_TRUE(lf);
  ASSERT_EQ(lines.size(), motion.points.size() + 1);
  EXPECT_EQ(lines[0].rfind("layer,path,index,x_mm,y_mm,z_mm,nx,ny,nz,vx,vy,vz,a1_deg,a2_deg", 0),
            0u);
  double lastTime = -1.0;
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    std::vector<double> v;
    for (const auto& f : splitFields(lines[i + 1], ','))
      v.push_back(std::strtod(f.c_str(), nullptr));
    expectRow(v, motion.points[i]);
    EXPECT_GE(v[24], lastTime);
    lastTime = v[24];
  }
}

TEST(NeutralWriter, JsonHoldsTheSameRowsAndJointNames) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  const ExportResult result = NeutralWriter(ExportFormat::Json).write(motion, cell, {}, {});
  const auto doc = nlohmann::json::parse(result.files[0].text);
  EXPECT_EQ(doc.at("format"), "curvedslicer-motion");
  EXPECT_EQ(doc.at("version"), 1);
  EXPECT_EQ(doc.at("cell"), cell.name);
  EXPECT_EQ(doc.at("columns").size(), 27u);
  EXPECT_EQ(doc.at("joint_names").size(), 8u);
  ASSERT_EQ(doc.at("points").size(), motion.points.size());
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    expectRow(doc.at("points")[i].get<std::vector<double>>(), motion.points[i]);
  }
  EXPECT_THROW(NeutralWriter(ExportFormat::Json).write(MotionPlan{}, cell, {}, {}), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
