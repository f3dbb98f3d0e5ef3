// Part placement: rest puts the lowest bead bottom on the table top (keeping the cell's rotation
// and xy), cell keeps the cell's table_to_part, and weld points below the table or outside the
// working volume are InvalidInput naming the point, the amount and the hint.
#include "common/test_constants.hpp"
#include "curvedslicer/robot/placement.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/positioner.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;

/// Two flat layers of one ring each (radius 30 mm about the part origin), layer thickness
/// 1.5 mm, bead spacing 4 mm; the first layer's weld points at z = `z0` (part frame), the lowest at
/// point 9 of layer 0 (0.25 mm lower than the rest).
Plan twoRings(double z0) {
  Plan plan;
  plan.parameters.layerThickness = 1.5;
  plan.parameters.beadSpacing = 4.0;
  for (int l = 0; l < 2; ++l) {
    PlanLayer layer;
    layer.index = l;
    PlanPath path;
    path.layer = l;
    path.closed = true;
    for (int i = 0; i < 36; ++i) {
      const double phi = 2 * kPi * i / 36;
      PathPoint p;
      p.position = Vec3(30 * std::cos(phi), 30 * std::sin(phi), z0 + 1.5 * l);
      if (l == 0 && i == 9) p.position.z() -= 0.25;
      p.deposition = -Vec3::UnitZ();
      p.normal = Vec3::UnitZ();
      path.points.push_back(p);
    }
    layer.paths.push_back(path);
    plan.layers.push_back(layer);
  }
  return plan;
}

/// Runs f and returns the InvalidInput message (fails the test if nothing is thrown).
template <class F>
std::string invalidInputMessage(F&& f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InvalidInput";
  return {};
}

void expectContains(const std::string& text, const std::string& needle) {
  EXPECT_NE(text.find(needle), std::string::npos)
      << "\"" << text << "\" lacks \"" << needle << "\"";
}

TEST(Placement, NamesParseAndPrint) {
  for (PartPlacement p : {PartPlacement::Rest, PartPlacement::Cell}) {
    EXPECT_EQ(parsePartPlacement(toString(p)), p);
  }
  EXPECT_EQ(MotionOptions{}.placement, PartPlacement::Rest);
  const std::string message = invalidInputMessage([] { parsePartPlacement("floor"); });
  expectContains(message, "'floor'");
  expectContains(message, "rest");
  expectContains(message, "cell");
}

TEST(Placement, RestPutsTheLowestBeadBottomOnTheTableTop) {
  Cell cell = defaultCell();
  const Pose given = makePose(Vec3(5, -7, 40), Vec3(0, 0, 0.5));  // xy, yaw kept; z replaced
  cell.positioner.tableToPart = given;
  const Plan plan = twoRings(-12.0);
  const PartPlacementResult r = placePart(plan, cell, PartPlacement::Rest);
  // lowest weld point: z = -12.25 in the part, 40 - 12.25 in the table; bottom 1.5 mm below.
  EXPECT_NEAR(r.lift, -(40.0 - 12.25 - 1.5), 1e-9);
  EXPECT_NEAR(r.tableToPart.translation().z(), 12.25 + 1.5, 1e-9);
  EXPECT_NEAR(r.tableToPart.translation().x(), 5.0, 1e-12);
  EXPECT_NEAR(r.tableToPart.translation().y(), -7.0, 1e-12);
  EXPECT_TRUE(r.tableToPart.rotation().isApprox(given.rotation(), 1e-15));
  double lowest = 1e9;
  for (const auto& layer : plan.layers) {
    for (const auto& p : layer.paths[0].points) {
      lowest = std::min(lowest, (r.tableToPart * p.position).z());
    }
  }
  EXPECT_NEAR(lowest - plan.parameters.layerThickness, 0.0, 1e-9);
  expectContains(r.note, "part placement rest");
  expectContains(r.note, "layer 0 path 0 point 9");
  expectContains(r.note, "table_to_part z = 13.750 mm");
  // Deterministic, and a part already resting stays where it is.
  Cell resting = cell;
  resting.positioner.tableToPart = r.tableToPart;
  const PartPlacementResult again = placePart(plan, resting, PartPlacement::Rest);
  EXPECT_NEAR(again.lift, 0.0, 1e-9);
  EXPECT_NO_THROW(checkPartPlacement(plan, resting.positioner));
  // Resting to within 1e-6 mm (rounding of the plan's coordinates): the cell's placement as is.
  Cell almost = defaultCell();
  const Plan rounded = twoRings(1.75 + 1e-11);  // lowest point at h + 1e-11 = 1.5 + 1e-11 mm
  const PartPlacementResult kept = placePart(rounded, almost, PartPlacement::Rest);
  EXPECT_EQ(kept.lift, 0.0);
  EXPECT_TRUE(kept.tableToPart.isApprox(almost.positioner.tableToPart, 0.0));
  EXPECT_TRUE(kept.tableToPart.matrix() == almost.positioner.tableToPart.matrix());
}

/// V of every point of `plan` in the table frame of `tableToPart` is straight down.
void expectDepositedDownwards(const Plan& plan, const Pose& tableToPart) {
  for (const PlanLayer& layer : plan.layers) {
    for (const PlanPath& path : layer.paths) {
      for (const PathPoint& p : path.points) {
        EXPECT_NEAR((tableToPart.linear() * p.deposition).z(), -1.0, 1e-9);
      }
    }
  }
}

TEST(Placement, RestFollowsATiltedPlacementWithinThirtyDegrees) {
  Cell cell = defaultCell();
  cell.positioner.tableToPart = makePose(Vec3(0, 0, 0), Vec3(kPi / 9, 0, 0));  // 20 deg
  const Plan plan = twoRings(0.0);
  const PartPlacementResult r = placePart(plan, cell, PartPlacement::Rest);
  // The rings stay tilted by 20 deg (the cell's rotation kept) and rest on the table.
  EXPECT_TRUE(r.tableToPart.linear().isApprox(cell.positioner.tableToPart.linear(), 1e-12));
  Cell placed = cell;
  placed.positioner.tableToPart = r.tableToPart;
  EXPECT_NEAR(placePart(plan, placed, PartPlacement::Rest).lift, 0.0, 1e-9);
  EXPECT_NO_THROW(checkPartPlacement(plan, placed.positioner));
}

TEST(Placement, RestTurnsAStartSurfaceFacingSidewaysOntoTheTable) {
  Cell cell = defaultCell();
  cell.positioner.tableToPart = makePose(Vec3(0, 0, 0), Vec3(kPi / 2, 0, 0));  // part y up
  const Plan plan = twoRings(0.0);
  const PartPlacementResult r = placePart(plan, cell, PartPlacement::Rest);
  // The rings would stand on edge (V horizontal, the torch across the table): turned back flat,
  // centred on the rotation axis, the lowest weld point one layer thickness above the table.
  expectDepositedDownwards(plan, r.tableToPart);
  expectContains(r.note, "turned by 90.0 deg");
  Cell placed = cell;
  placed.positioner.tableToPart = r.tableToPart;
  EXPECT_NEAR(placePart(plan, placed, PartPlacement::Rest).lift, 0.0, 1e-9);
  EXPECT_NO_THROW(checkPartPlacement(plan, placed.positioner));
}

/// A 30 x 12 mm (y, z) block grown sideways along +x from the plane x = 0 in layers of 5 mm:
/// every layer one contour-parallel rectangle s/2 = 2 mm inside the block's section, as the
/// planner puts the outer bead's edge on the part's edge.
Plan sidewaysBlock() {
  Plan plan;
  plan.parameters.layerThickness = 5.0;
  plan.parameters.beadSpacing = 4.0;
  for (int l = 0; l < 2; ++l) {
    PlanLayer layer;
    PlanPath path;
    path.layer = l;
    path.closed = true;
    const double x = 5.0 * (l + 1);
    const Vec3 corners[4] = {Vec3(x, 2, 2), Vec3(x, 28, 2), Vec3(x, 28, 10), Vec3(x, 2, 10)};
    for (int c = 0; c < 4; ++c) {
      for (int i = 0; i < 8; ++i) {
        PathPoint p;
        p.position = corners[c] + (corners[(c + 1) % 4] - corners[c]) * (i / 8.0);
        p.normal = Vec3::UnitX();
        p.deposition = -Vec3::UnitX();
        path.points.push_back(p);
      }
    }
    layer.paths.push_back(path);
    plan.layers.push_back(layer);
  }
  return plan;
}

TEST(Placement, RestPutsTheStartFaceOfSidewaysLayersOnTheTable) {
  Cell cell = defaultCell();
  cell.positioner.tableToPart = makePose(Vec3(0, 0, 20), Vec3::Zero());
  const Plan plan = sidewaysBlock();
  const PartPlacementResult r = placePart(plan, cell, PartPlacement::Rest);
  // Layers grown along +x from the face x = 0: the part is turned so that face lies on the table
  // (V straight down) and the first layer's beads, 5 mm up, reach the table top.
  expectDepositedDownwards(plan, r.tableToPart);
  double lowest = kInf;
  for (const PathPoint& p : plan.layers[0].paths[0].points) {
    lowest = std::min(lowest, (r.tableToPart * p.position).z());
  }
  EXPECT_NEAR(lowest, 5.0, 1e-9);
  expectContains(r.note, "start surface on the table");
}

TEST(Placement, CellKeepsTheGivenPlacement) {
  Cell cell = defaultCell();
  cell.positioner.tableToPart = makePose(Vec3(1, 2, 3), Vec3(0.1, 0, 0));
  const PartPlacementResult r = placePart(twoRings(-12.0), cell, PartPlacement::Cell);
  EXPECT_TRUE(r.tableToPart.isApprox(cell.positioner.tableToPart, 0.0));
  EXPECT_EQ(r.lift, 0.0);
  EXPECT_TRUE(r.note.empty());
  EXPECT_TRUE(placePart(Plan{}, cell, PartPlacement::Rest)
                  .tableToPart.isApprox(cell.positioner.tableToPart, 0.0));
}

TEST(Placement, PointsBelowTheTableNameTheLowestPointAndTheAmount) {
  const Cell cell = defaultCell();  // table_to_part = identity
  const std::string message =
      invalidInputMessage([&] { checkPartPlacement(twoRings(-12.0), cell.positioner); });
  expectContains(message, "weld points below the table top");
  expectContains(message, "layer 0 path 0 point 9 (part 0.00, 30.00, -12.25 mm)");
  expectContains(message, "12.250 mm below the table");
  expectContains(message, "72 points below it");
  expectContains(message, "positioner/table_to_part");
  expectContains(message, "--placement rest");
  // On the table top exactly is fine.
  EXPECT_NO_THROW(checkPartPlacement(twoRings(0.25), cell.positioner));
}

TEST(Placement, PointsOutsideTheWorkingVolumeNameTheFarthestPoint) {
  Cell cell = defaultCell();
  cell.positioner.geometry.maxPartRadius = 25.0;
  std::string message =
      invalidInputMessage([&] { checkPartPlacement(twoRings(1.5), cell.positioner); });
  expectContains(message, "outside the positioner's working volume");
  expectContains(message, "layer 0 path 0 point 0 (part 30.00, 0.00, 1.50 mm)");
  expectContains(message, "5.000 mm beyond its radius of 25.0 mm");
  expectContains(message, "72 points beyond it");
  // Off the rotation axis by the placement's xy.
  cell = defaultCell();
  cell.positioner.tableToPart = makePose(Vec3(330, 0, 0), Vec3::Zero());
  message = invalidInputMessage([&] { checkPartPlacement(twoRings(1.5), cell.positioner); });
  expectContains(message, "10.000 mm beyond its radius of 350.0 mm");
  // Too tall.
  cell = defaultCell();
  cell.positioner.geometry.maxPartHeight = 2.0;
  message = invalidInputMessage([&] { checkPartPlacement(twoRings(1.5), cell.positioner); });
  expectContains(message, "above the positioner's working volume");
  expectContains(message, "layer 1 path 0 point 0 (part 30.00, 0.00, 3.00 mm)");
  expectContains(message, "1.000 mm above its height of 2.0 mm");
}

TEST(Placement, PlanMotionUsesThePlacementAndReportsIt) {
  const Plan plan = twoRings(-12.0);
  const MotionPlan rest = planMotion(plan, defaultCell());
  EXPECT_NEAR(rest.tableToPart.translation().z(), 12.25 + 1.5, 1e-9);
  ASSERT_FALSE(rest.notes.empty());
  expectContains(rest.notes.back(), "part placement rest");
  // The motion uses the placed part: the weld points' world z is the table top + their height.
  const Pose table = computeTableInWorld(defaultCell().positioner, 0.0, 0.0);
  for (const MotionPoint& m : rest.points) {
    if (m.kind != MoveKind::Path) continue;
    const Vec3 inTable = rest.tableToPart * m.position;
    EXPECT_GE(inTable.z(), 1.5 - 1e-9);
    if (std::abs(m.a1) < 1e-12 && std::abs(m.a2) < 1e-12) {
      EXPECT_NEAR(m.toolInWorld.translation().z(), (table * inTable).z(), 1e-6);
    }
  }
  MotionOptions keep;
  keep.placement = PartPlacement::Cell;
  const std::string message = invalidInputMessage([&] { planMotion(plan, defaultCell(), keep); });
  expectContains(message, "12.250 mm below the table");
}

TEST(Placement, PlanMotionCopiesTheCellNotes) {
  Cell cell = defaultCell();
  cell.notes = {"cell version 1: default torch envelope assumed (...)"};
  MotionOptions options;
  options.placement = PartPlacement::Cell;
  const MotionPlan motion = planMotion(twoRings(1.5), cell, options);
  ASSERT_EQ(motion.notes.size(), 1u);
  EXPECT_EQ(motion.notes[0], cell.notes[0]);
  EXPECT_TRUE(motion.tableToPart.isApprox(cell.positioner.tableToPart, 0.0));
}

}  // namespace
}  // namespace curvedslicer
