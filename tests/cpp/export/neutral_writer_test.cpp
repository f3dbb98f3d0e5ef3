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

/// `v`: the 34 numeric columns; `kind`: the 35th. `cellWireFeed`: the cell's process wire feed.
void expectRow(const std::vector<double>& v, const std::string& kind, const MotionPoint& p,
               double cellWireFeed) {
  ASSERT_EQ(v.size(), 34u);
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
  EXPECT_EQ(v[24], p.time);
  EXPECT_EQ(v[25], p.residual * (180.0 / kPiT));
  EXPECT_EQ(v[26], p.flags);
  // wire feed of the move: the point's, else the cell's; 0 with the arc off
  EXPECT_EQ(v[27], p.arcOn ? (p.wireFeed > 0.0 ? p.wireFeed : cellWireFeed) : 0.0);
  EXPECT_EQ(v[28], p.weldSchedule);
  EXPECT_EQ(v[29], p.beadWidth);
  EXPECT_EQ(v[30], p.torchAngle * (180.0 / kPiT));
  EXPECT_EQ(v[31], p.travelAngle * (180.0 / kPiT));
  EXPECT_EQ(v[32], p.workAngle * (180.0 / kPiT));
  EXPECT_EQ(v[33], p.residual * (180.0 / kPiT));
  EXPECT_EQ(kind, toString(p.kind));
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
  EXPECT_EQ(
      lines[0].substr(lines[0].rfind(",time_s")),
      ",time_s,residual_deg,flags,wire_feed_m_min,weld_schedule,bead_width_mm,torch_angle_deg,"
      "travel_angle_deg,work_angle_deg,gravity_deviation_deg,kind");
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    std::vector<std::string> fields = splitFields(lines[i + 1], ',');
    ASSERT_EQ(fields.size(), 35u);
    std::vector<double> v;
    for (std::size_t k = 0; k + 1 < fields.size(); ++k) {
      char* end = nullptr;
      v.push_back(std::strtod(fields[k].c_str(), &end));
      EXPECT_EQ(*end, '\0') << "not a number: " << fields[k];
    }
    expectRow(v, fields.back(), motion.points[i], cell.process.wireFeed);
  }
}

TEST(NeutralWriter, JsonHoldsTheSameRowsAndJointNames) {
  const Cell cell = defaultCell();
  const MotionPlan motion = planMotion(makeSmallPlan(), cell);
  const ExportResult result = NeutralWriter(ExportFormat::Json).write(motion, cell, {}, {});
  const auto doc = nlohmann::json::parse(result.files[0].text);
  EXPECT_EQ(doc.at("format"), "curvedslicer-motion");
  EXPECT_EQ(doc.at("version"), 4);
  EXPECT_EQ(doc.at("cell"), cell.name);
  EXPECT_EQ(doc.at("columns").size(), 35u);
  EXPECT_EQ(doc.at("columns").back(), "kind");
  EXPECT_EQ(doc.at("joint_names").size(), 8u);
  ASSERT_EQ(doc.at("points").size(), motion.points.size());
  for (std::size_t i = 0; i < motion.points.size(); ++i) {
    const auto& row = doc.at("points")[i];
    ASSERT_EQ(row.size(), 35u);
    std::vector<double> v;
    for (std::size_t k = 0; k + 1 < row.size(); ++k) v.push_back(row[k].get<double>());
    expectRow(v, row.back().get<std::string>(), motion.points[i], cell.process.wireFeed);
  }
  EXPECT_THROW(NeutralWriter(ExportFormat::Json).write(MotionPlan{}, cell, {}, {}), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
