// Bead model: bilinear interpolation against closed form, the inverse (WFS and TS for
// a width at a height) round trip, clamping with its shortfall, table errors naming the cell
// field, and planMotion filling wire feed, bead width and weld speed per point from it.
#include "common/test_constants.hpp"
#include "curvedslicer/robot/bead_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;

/// A table sampled from bilinear functions of (f, t), which bilinear interpolation reproduces
/// exactly on any grid: width = 1 + 0.8 f − 0.1 t − 0.01 f t, height = 2 + 0.1 f − 0.1 t
/// (one-to-one on the table: the Jacobian determinant −0.07 + 0.001 (f + t) stays negative).
double closedWidth(double f, double t) {
  return 1.0 + 0.8 * f - 0.1 * t - 0.01 * f * t;
}
double closedHeight(double f, double t) {
  return 2.0 + 0.3 * f - 0.04 * t;
}

BeadModel bilinearModel() {
  BeadModel m;
  m.wireFeeds = {2.0, 3.0, 5.0, 8.0};
  m.travelSpeeds = {4.0, 7.0, 12.0};
  for (double f : m.wireFeeds) {
    std::vector<double> w, h;
    for (double t : m.travelSpeeds) {
      w.push_back(closedWidth(f, t));
      h.push_back(closedHeight(f, t));
    }
    m.width.push_back(w);
    m.height.push_back(h);
  }
  return m;
}

TEST(BeadModel, InterpolationMatchesClosedFormOnABilinearTable) {
  const BeadModel m = bilinearModel();
  EXPECT_NO_THROW(validateBeadModel(m));
  for (double f : {2.0, 2.4, 3.0, 4.1, 6.7, 8.0}) {
    for (double t : {4.0, 5.5, 9.3, 12.0}) {
      const BeadGeometry g = evaluateBeadModel(m, f, t);
      EXPECT_NEAR(g.width, closedWidth(f, t), 1e-12) << f << " " << t;
      EXPECT_NEAR(g.height, closedHeight(f, t), 1e-12) << f << " " << t;
    }
  }
  // Outside the table: clamped to its edge.
  const BeadGeometry low = evaluateBeadModel(m, 1.0, 20.0);
  EXPECT_NEAR(low.width, closedWidth(2.0, 12.0), 1e-12);
  EXPECT_NEAR(low.height, closedHeight(2.0, 12.0), 1e-12);
}

TEST(BeadModel, InverseRoundTrip) {
  const BeadModel m = bilinearModel();
  for (double f : {2.2, 3.5, 4.9, 7.3}) {
    for (double t : {4.5, 6.1, 10.0}) {
      const BeadSetting s = solveBeadSetting(m, closedWidth(f, t), closedHeight(f, t), 1e-6);
      EXPECT_TRUE(s.reached) << f << " " << t;
      EXPECT_NEAR(s.wireFeed, f, 1e-6);
      EXPECT_NEAR(s.travelSpeed, t, 1e-6);
    }
  }
  // The example table of the paper's cell: 3.71 × 1.5 mm is its node (3.5 m/min, 16 mm/s).
  const BeadModel& example = defaultCell().process.beadModel;
  ASSERT_FALSE(example.empty());
  const BeadSetting node = solveBeadSetting(example, 3.71, 1.5, 1e-9);
  EXPECT_TRUE(node.reached);
  EXPECT_NEAR(node.wireFeed, 3.5, 1e-6);
  EXPECT_NEAR(node.travelSpeed, 16.0, 1e-6);
  const BeadSetting mid = solveBeadSetting(example, 4.2, 1.6);
  EXPECT_TRUE(mid.reached);
  const BeadGeometry back = evaluateBeadModel(example, mid.wireFeed, mid.travelSpeed);
  EXPECT_NEAR(back.width, 4.2, 1e-3);
  EXPECT_NEAR(back.height, 1.6, 1e-3);
}

TEST(BeadModel, OutOfTheTableIsClampedWithItsShortfall) {
  const BeadModel m = bilinearModel();
  // Wider than any bead of the table (the widest and highest: 8 m/min, 4 mm/s, 6.68 × 2.4 mm).
  const BeadSetting s = solveBeadSetting(m, 12.0, closedHeight(8.0, 4.0));
  EXPECT_FALSE(s.reached);
  EXPECT_GE(s.wireFeed, 2.0);
  EXPECT_LE(s.wireFeed, 8.0);
  EXPECT_GE(s.travelSpeed, 4.0);
  EXPECT_LE(s.travelSpeed, 12.0);
  EXPECT_LT(s.achieved.width, 12.0);
  EXPECT_NEAR(s.wireFeed, 8.0, 1e-9);  // the widest bead, at the wanted height
  EXPECT_NEAR(s.travelSpeed, 4.0, 1e-9);
  EXPECT_NEAR(s.achieved.width, closedWidth(8.0, 4.0), 1e-9);
  EXPECT_NEAR(s.achieved.height, closedHeight(8.0, 4.0), 1e-9);
  EXPECT_THROW(solveBeadSetting(m, 0.0, 1.5), InvalidInput);
  EXPECT_THROW(solveBeadSetting(m, 3.0, std::nan("")), InvalidInput);
}

void expectInvalid(const BeadModel& m, const std::vector<std::string>& needles) {
  try {
    validateBeadModel(m);
    ADD_FAILURE() << "no error for " << needles.front();
  } catch (const InvalidInput& e) {
    for (const std::string& needle : needles) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  }
}

TEST(BeadModel, BadTablesNameTheField) {
  BeadModel m = bilinearModel();
  m.width.pop_back();
  expectInvalid(m, {"/process/bead_model/width_mm", "3 rows, expected 4"});
  m = bilinearModel();
  m.height[2].push_back(1.0);
  expectInvalid(m, {"/process/bead_model/height_mm/2", "4 values, expected 3"});
  m = bilinearModel();
  m.travelSpeeds = {4.0, 4.0, 12.0};
  expectInvalid(m, {"/process/bead_model/travel_speed_mm_s", "ascending"});
  m = bilinearModel();
  m.wireFeeds = {3.0};
  expectInvalid(m, {"/process/bead_model/wire_feed_m_min", "at least 2"});
  m = bilinearModel();
  m.width[1][1] = -1.0;
  expectInvalid(m, {"/process/bead_model/width_mm/1", "positive"});
}

TEST(BeadModel, CellReadsWritesAndRejectsTheSection) {
  const Cell cell = defaultCell();
  const Cell back = parseCell(writeCellJson(cell), "round trip");
  EXPECT_EQ(back.process.beadModel.width, cell.process.beadModel.width);
  EXPECT_EQ(back.process.beadModel.travelSpeeds, cell.process.beadModel.travelSpeeds);
  nlohmann::json j = nlohmann::json::parse(writeCellJson(cell));
  j["process"]["bead_model"].erase("height_mm");
  try {
    parseCell(j.dump(), "test.json");
    ADD_FAILURE() << "no error for a missing height table";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("/process/bead_model/height_mm"), std::string::npos)
        << e.what();
  }
  j = nlohmann::json::parse(writeCellJson(cell));
  j["process"]["bead_model"]["width_mm"].erase(0);
  try {
    parseCell(j.dump(), "test.json");
    ADD_FAILURE() << "no error for a short width table";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("test.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("width_mm has 4 rows, expected 5"), std::string::npos)
        << e.what();
  }
  // Without the section: no model.
  j = nlohmann::json::parse(writeCellJson(cell));
  j["process"].erase("bead_model");
  EXPECT_TRUE(parseCell(j.dump(), "test.json").process.beadModel.empty());
}

/// Two flat rings (r = 40 mm) at z = 1.5, deposition straight down; bead width `width` on every
/// point (0 = the bead spacing), layer thickness 1.5 mm, bead spacing 3.7 mm.
Plan ringPlan(double width) {
  Plan plan;
  plan.parameters.beadSpacing = 3.7;
  plan.parameters.layerThickness = 1.5;
  PlanLayer layer;
  for (int r = 0; r < 2; ++r) {
    PlanPath path;
    path.index = r;
    path.closed = true;
    for (int i = 0; i < 60; ++i) {
      const double phi = 2 * kPi * i / 60;
      PathPoint p;
      p.position = Vec3((40.0 + 3.7 * r) * std::cos(phi), (40.0 + 3.7 * r) * std::sin(phi), 1.5);
      p.deposition = -Vec3::UnitZ();
      p.normal = Vec3::UnitZ();
      p.width = width;
      path.points.push_back(p);
    }
    layer.paths.push_back(path);
  }
  plan.layers.push_back(layer);
  return plan;
}

TEST(BeadModel, MotionTakesWireFeedAndSpeedFromTheModel) {
  const Cell cell = defaultCell();
  // Fixed width (0 = the bead spacing): the cell's wire feed and weld speed.
  const MotionPlan fixed = planMotion(ringPlan(0.0), cell);
  std::size_t welds = 0;
  for (const MotionPoint& m : fixed.points) {
    if (m.kind != MoveKind::Path) continue;
    EXPECT_DOUBLE_EQ(m.beadWidth, 3.7);
    if (!m.arcOn) continue;
    ++welds;
    EXPECT_DOUBLE_EQ(m.wireFeed, cell.process.wireFeed);
    if (!(m.flags & kMotionSpeedReduced)) {
      EXPECT_DOUBLE_EQ(m.speed, cell.process.weldSpeed);
    }
  }
  EXPECT_GT(welds, 100u);
  // Width 4.2 mm: the model's WFS and TS for 4.2 × 1.5 mm.
  const BeadSetting want = solveBeadSetting(cell.process.beadModel, 4.2, 1.5);
  ASSERT_TRUE(want.reached);
  const MotionPlan adaptive = planMotion(ringPlan(4.2), cell);
  for (const MotionPoint& m : adaptive.points) {
    if (m.kind != MoveKind::Path || !m.arcOn) continue;
    EXPECT_DOUBLE_EQ(m.beadWidth, 4.2);
    EXPECT_DOUBLE_EQ(m.wireFeed, want.wireFeed);
    if (!(m.flags & kMotionSpeedReduced)) {
      EXPECT_DOUBLE_EQ(m.speed, want.travelSpeed);
    }
  }
  for (const std::string& w : adaptive.warnings) {
    EXPECT_EQ(w.find("bead model cannot"), std::string::npos) << w;
  }
  // Wire fed at the model's feed: the estimate follows it.
  EXPECT_NEAR(adaptive.total.wireLength, want.wireFeed * 1000.0 / 60.0 * adaptive.total.arcTime,
              1e-6 * adaptive.total.wireLength);
  // 2 mm wide at 1.5 mm high is out of the table: clamped, and a warning names the shortfall.
  const MotionPlan narrow = planMotion(ringPlan(2.0), cell);
  bool warned = false;
  for (const std::string& w : narrow.warnings) {
    warned = warned || (w.find("bead model cannot") != std::string::npos &&
                        w.find("wanted 2") != std::string::npos);
  }
  EXPECT_TRUE(warned);
}

}  // namespace
}  // namespace curvedslicer
