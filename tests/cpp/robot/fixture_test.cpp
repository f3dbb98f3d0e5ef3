// The fixture between the table and the part (FixtureGeometry: a riser and a substrate plate):
// read from and written to the cell file with clear errors for impossible sizes; the placement
// rest puts the part on the plate; the collision check finds the torch in the riser and in the
// plate with the depth in closed form; the placement auto raises a riser until the torch clears
// the table, checked by an independent sampling of the torch cone against the table and riser.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/test_constants.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/collision.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/placement.hpp"

namespace curvedslicer {
namespace {

using testing::kPi;

/// The default cell's file with `fixture` as positioner/fixture.
std::string cellWithFixture(const nlohmann::json& fixture) {
  nlohmann::json cell = nlohmann::json::parse(writeCellJson(defaultCell()));
  cell["positioner"]["fixture"] = fixture;
  return cell.dump();
}

/// The InvalidInput message of parsing `text` (empty, and a test failure, if it parses).
std::string fixtureError(const std::string& text) {
  try {
    parseCell(text, "fixture.json");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  ADD_FAILURE() << "parsed: " << text;
  return {};
}

void expectMentions(const std::string& text, const std::string& needle) {
  EXPECT_NE(text.find(needle), std::string::npos)
      << "\"" << text << "\" lacks \"" << needle << "\"";
}

TEST(Fixture, CellFileReadsAndWritesTheRiserAndThePlate) {
  const Cell cell = parseCell(cellWithFixture({{"riser_height_mm", 80},
                                               {"riser_diameter_mm", 150},
                                               {"substrate_thickness_mm", 12},
                                               {"substrate_size_mm", 200}}),
                              "fixture.json");
  const FixtureGeometry& f = cell.positioner.fixture;
  EXPECT_EQ(f.riserHeight, 80.0);
  EXPECT_EQ(f.riserDiameter, 150.0);
  EXPECT_EQ(f.substrateThickness, 12.0);
  EXPECT_EQ(f.substrateSize, 200.0);
  EXPECT_EQ(f.top(), 92.0);
  const Cell back = parseCell(writeCellJson(cell), "written");
  EXPECT_EQ(back.positioner.fixture.top(), 92.0);
  EXPECT_EQ(back.positioner.fixture.substrateSize, 200.0);
  // absent: the bare table
  EXPECT_EQ(defaultCell().positioner.fixture.top(), 0.0);
  EXPECT_EQ(nlohmann::json::parse(writeCellJson(defaultCell()))["positioner"].count("fixture"), 0u);
}

TEST(Fixture, ImpossibleSizesNameTheField) {
  std::string m = fixtureError(cellWithFixture({{"riser_height_mm", -5}}));
  expectMentions(m, "/positioner/fixture/riser_height_mm");
  expectMentions(m, "-5");
  m = fixtureError(cellWithFixture({{"riser_height_mm", 50}}));
  expectMentions(m, "riser_diameter_mm must be positive with a riser");
  m = fixtureError(cellWithFixture({{"substrate_thickness_mm", 10}}));
  expectMentions(m, "substrate_size_mm must be positive with a substrate plate");
  m = fixtureError(cellWithFixture({{"riser_height_mm", 50}, {"riser_diameter_mm", 700}}));
  expectMentions(m, "riser_diameter_mm is wider than the table (diameter 600 mm): 700 mm");
  m = fixtureError(cellWithFixture({{"substrate_thickness_mm", 10}, {"substrate_size_mm", 600}}));
  expectMentions(m, "substrate_size_mm puts the plate's corners outside the working volume");
  m = fixtureError(cellWithFixture({{"riser_height_mm", 495},
                                    {"riser_diameter_mm", 100},
                                    {"substrate_thickness_mm", 10},
                                    {"substrate_size_mm", 100}}));
  expectMentions(m, "leave no room in the working volume (height 500 mm, fixture top 505 mm)");
  m = fixtureError(cellWithFixture({{"riser_hight_mm", 5}}));
  expectMentions(m, "riser_hight_mm is not a known field");
}

/// One flat ring of radius 30 mm at part z = 0, layer thickness 1.5 mm, bead spacing 4 mm.
Plan flatRing() {
  Plan plan;
  plan.parameters.layerThickness = 1.5;
  plan.parameters.beadSpacing = 4.0;
  PlanLayer layer;
  PlanPath path;
  path.closed = true;
  for (int i = 0; i < 36; ++i) {
    const double phi = 2 * kPi * i / 36;
    PathPoint p;
    p.position = Vec3(30 * std::cos(phi), 30 * std::sin(phi), 0.0);
    p.deposition = -Vec3::UnitZ();
    p.normal = Vec3::UnitZ();
    path.points.push_back(p);
  }
  layer.paths.push_back(path);
  plan.layers.push_back(layer);
  return plan;
}

TEST(Fixture, RestPutsThePartOnThePlate) {
  Cell cell = defaultCell();
  cell.positioner.fixture = FixtureGeometry{60.0, 120.0, 10.0, 100.0};
  const Plan plan = flatRing();
  const PartPlacementResult r = placePart(plan, cell, PartPlacement::Rest);
  // the bead bottom, one layer thickness below the flat ring, on the plate's top at z = 70
  EXPECT_NEAR(r.tableToPart.translation().z(), 71.5, 1e-9);
  expectMentions(r.note,
                 "the substrate plate's top (70.000 mm above the table, on a riser of "
                 "60.000 mm)");
  Cell placed = cell;
  placed.positioner.tableToPart = r.tableToPart;
  EXPECT_NO_THROW(checkPartPlacement(plan, placed.positioner));
  // where the cell puts it (on the table top), the weld points lie inside the fixture
  const std::string m = [&] {
    try {
      checkPartPlacement(plan, cell.positioner);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  expectMentions(m, "weld points below the fixture's top (70.000 mm above the table");
  expectMentions(m, "70.000 mm below the fixture's top");
}

/// One straight path along x at part (x, 50, z), V = −z (the torch vertical above it).
Plan straightWeld(double z) {
  Plan plan;
  plan.parameters.beadSpacing = 3.7;
  PlanLayer layer;
  PlanPath path;
  for (int i = 0; i <= 40; ++i) {
    PathPoint p;
    p.position = Vec3(-20.0 + i, 50.0, z);
    p.normal = Vec3::UnitZ();
    p.deposition = -Vec3::UnitZ();
    path.points.push_back(p);
  }
  path.length = 40.0;
  layer.paths.push_back(path);
  plan.layers.push_back(layer);
  return plan;
}

/// The weld moves' collisions of the torch on a path at table z `weldZ` (planned where the
/// default cell puts the part, part frame = table frame) against `fixture`.
std::vector<CollisionReport> weldHitsOn(const FixtureGeometry& fixture, double weldZ) {
  const Plan plan = straightWeld(weldZ);
  MotionOptions options;
  options.placement = PartPlacement::Cell;
  MotionPlan motion = planMotion(plan, defaultCell(), options);
  Cell cell = defaultCell();
  cell.positioner.fixture = fixture;
  options.allowCollisions = true;
  checkMotionCollisions(motion, cell, collisionGeometryOf(cell), depositBeadRadius(plan.parameters),
                        options);
  const MotionPathSpan& weld = motion.paths.front();
  std::vector<CollisionReport> hits;
  for (const CollisionReport& c : motion.collisions) {
    if (c.point > weld.begin && c.point < weld.end) hits.push_back(c);
  }
  EXPECT_EQ(hits.size(), weld.end - weld.begin - 1);
  return hits;
}

TEST(Fixture, TorchInTheRiserOrThePlateByTheClosedFormDepth) {
  // The default cone's lowest capsule (radius 15.625 mm, its round end at the nozzle, 15 mm
  // above the TCP) above a weld 20 mm below the riser's top (100 mm): it reaches 5 mm into it.
  for (const CollisionReport& c : weldHitsOn(FixtureGeometry{100.0, 200.0, 0.0, 0.0}, 80.0)) {
    EXPECT_EQ(c.obstacle, CollisionObstacle::Riser);
    EXPECT_EQ(c.what, "torch vs riser");
    EXPECT_NEAR(c.depth, 5.0, 1e-9);
  }
  // a 10 mm plate on the riser: a weld 20 mm below its top, 5 mm into the plate
  for (const CollisionReport& c : weldHitsOn(FixtureGeometry{100.0, 200.0, 10.0, 150.0}, 90.0)) {
    EXPECT_EQ(c.obstacle, CollisionObstacle::Substrate);
    EXPECT_EQ(c.what, "torch vs substrate plate");
    EXPECT_NEAR(c.depth, 5.0, 1e-9);
  }
}

TEST(Fixture, TorchBesideANarrowRiserIsFree) {
  // the same weld 20 mm below the top of a riser only 60 mm across (the path 50 mm off the
  // axis, the torch's lowest capsule 15.625 mm round it): nothing on the weld moves
  const Plan plan = straightWeld(80.0);
  MotionOptions options;
  options.placement = PartPlacement::Cell;
  MotionPlan motion = planMotion(plan, defaultCell(), options);
  Cell cell = defaultCell();
  cell.positioner.fixture = FixtureGeometry{100.0, 60.0, 0.0, 0.0};
  options.allowCollisions = true;
  checkMotionCollisions(motion, cell, collisionGeometryOf(cell), depositBeadRadius(plan.parameters),
                        options);
  const MotionPathSpan& weld = motion.paths.front();
  for (const CollisionReport& c : motion.collisions) {
    EXPECT_FALSE(c.point > weld.begin && c.point < weld.end) << c.what << " " << c.depth;
  }
}

/// One ring of radius 40 mm at part z = 0 deposited inwards and 10° up (V = −cos10° r̂ +
/// sin10° z): a part's first layer meeting the table steeply, its torch lying 10° below the
/// table's plane outwards, so that no torch angle within the default torch and gravity
/// deviation windows (25° together) lifts it above the table. Layer thickness 1.5 mm, bead
/// spacing 3.7 mm.
Plan steepRing() {
  Plan plan;
  plan.parameters.layerThickness = 1.5;
  plan.parameters.beadSpacing = 3.7;
  const double tilt = -10.0 * kPi / 180.0;
  PlanLayer layer;
  PlanPath path;
  path.closed = true;
  for (int i = 0; i < 72; ++i) {
    const double phi = 2 * kPi * i / 72;
    const Vec3 radial(std::cos(phi), std::sin(phi), 0.0);
    PathPoint p;
    p.position = 40.0 * radial;
    p.deposition = -std::cos(tilt) * radial - std::sin(tilt) * Vec3::UnitZ();
    p.normal = -p.deposition;
    path.points.push_back(p);
  }
  layer.paths.push_back(path);
  plan.layers.push_back(layer);
  return plan;
}

/// Smallest clearance (mm) over every weld move of `motion` between the cell's torch cone
/// (sampled every 0.5 mm along its axis, each sample's disc across the axis) and the table top
/// and the riser of `fixture`; negative: the cone is inside one of them. Computed from the TCP
/// poses alone, not with the planner's capsules.
double coneClearance(const MotionPlan& motion, const TorchEnvelope& torch,
                     const FixtureGeometry& fixture, double tableRadius) {
  double clearance = kInf;
  for (const MotionPoint& m : motion.points) {
    if (!m.arcOn) continue;
    const Pose toolInTable = motion.tableToPart * m.toolInPart;
    const Vec3 tip = toolInTable.translation();
    const Vec3 up = -toolInTable.linear().col(2);
    const double acrossZ = std::sqrt(std::max(0.0, 1.0 - up.z() * up.z()));
    for (double d = torch.stickout; d <= torch.stickout + torch.length; d += 0.5) {
      const double r =
          torch.radius + (torch.topRadius - torch.radius) * (d - torch.stickout) / torch.length;
      const Vec3 x = tip + d * up;
      const double radial = std::hypot(x.x(), x.y());
      const double lowest = x.z() - r * acrossZ;  // lowest point of the sample's disc
      if (radial - r <= tableRadius) clearance = std::min(clearance, lowest);
      if (fixture.hasRiser() && radial - r <= 0.5 * fixture.riserDiameter) {
        clearance = std::min(clearance, lowest - fixture.riserHeight);
      }
    }
  }
  return clearance;
}

TEST(Fixture, AutoRaisesTheLowestRiserThatClearsTheTable) {
  // the torch held along the deposition direction (torch and gravity deviation windows 0: with
  // the default 25° together the torch clears the table here by leaning), so only a riser clears
  Cell cell = defaultCell();
  cell.process.maxTorchAngle = 0.0;
  cell.process.maxGravityDeviation = 0.0;
  const Plan plan = steepRing();
  // resting on the table, the torch reaches into it
  MotionOptions rest;
  rest.allowCollisions = true;
  const MotionPlan onTable = planMotion(plan, cell, rest);
  double tableDepth = 0.0;
  for (const CollisionReport& c : onTable.collisions) {
    if (c.obstacle == CollisionObstacle::Table) tableDepth = std::max(tableDepth, c.depth);
  }
  ASSERT_GT(tableDepth, 1.0);
  EXPECT_LT(coneClearance(onTable, cell.tool.envelope, onTable.fixture,
                          cell.positioner.geometry.tableRadius),
            0.0);
  rest.allowCollisions = false;
  EXPECT_THROW(planMotion(plan, cell, rest), InvalidInput);
  // auto: a riser as wide as the ring plus a bead, as high as the deepest reach plus 2 mm
  MotionOptions automatic;
  automatic.placement = PartPlacement::Auto;
  const MotionPlan raised = planMotion(plan, cell, automatic);
  EXPECT_TRUE(raised.collisions.empty());
  EXPECT_NEAR(raised.fixture.riserDiameter, 83.7, 1e-6);
  EXPECT_GE(raised.fixture.riserHeight, tableDepth);
  EXPECT_LE(raised.fixture.riserHeight, tableDepth + 2.0 + 1e-9);
  const std::string note = raised.notes.back();
  expectMentions(note, "part placement auto: a riser of ");
  expectMentions(note, "83.7 mm across");
  // independently: the cone clears the table and the riser on every weld move
  EXPECT_GT(coneClearance(raised, cell.tool.envelope, raised.fixture,
                          cell.positioner.geometry.tableRadius),
            0.0);
  // the part rests on the riser's top
  EXPECT_NEAR(raised.tableToPart.translation().z() - onTable.tableToPart.translation().z(),
              raised.fixture.riserHeight, 1e-9);
}

/// A closed ring of `radius` mm at part height `z` (V down), for the support diameter below.
PlanPath ringAt(double radius, double z) {
  PlanPath path;
  path.closed = true;
  for (int i = 0; i < 36; ++i) {
    const double phi = 2 * kPi * i / 36;
    PathPoint p;
    p.position = Vec3(radius * std::cos(phi), radius * std::sin(phi), z);
    p.deposition = -Vec3::UnitZ();
    p.normal = Vec3::UnitZ();
    path.points.push_back(p);
  }
  return path;
}

TEST(Fixture, TheRiserCarriesTheBeadsLaidOnIt) {
  // the first layer's beads within one layer thickness (1.5 mm) of its lowest lie on the riser
  // top; those higher up rest on a raised start surface (a mandrel): 2 x 30 mm + a 4 mm bead
  Plan plan = flatRing();
  EXPECT_NEAR(supportDiameterFor(plan, Pose::Identity()), 64.0, 1e-9);
  plan.layers[0].paths.push_back(ringAt(45.0, 1.4));   // on the riser too
  plan.layers[0].paths.push_back(ringAt(60.0, 10.0));  // on the mandrel
  EXPECT_NEAR(supportDiameterFor(plan, Pose::Identity()), 94.0, 1e-9);
  // about the table's rotation axis, where the part stands (moved 5 mm off it)
  Pose moved = Pose::Identity();
  moved.translation() = Vec3(5.0, 0.0, 0.0);
  EXPECT_NEAR(supportDiameterFor(plan, moved), 104.0, 1e-9);
  // an empty first layer: the next carries the part; no points at all: nothing to carry
  Plan later = flatRing();
  later.layers.insert(later.layers.begin(), PlanLayer{});
  EXPECT_NEAR(supportDiameterFor(later, Pose::Identity()), 64.0, 1e-9);
  EXPECT_EQ(supportDiameterFor(Plan{}, Pose::Identity()), 0.0);
}

TEST(Fixture, AutoKeepsTheCellsFixtureWhenNothingCollides) {
  Cell cell = defaultCell();
  cell.positioner.fixture = FixtureGeometry{0.0, 0.0, 10.0, 100.0};
  MotionOptions automatic;
  automatic.placement = PartPlacement::Auto;
  const MotionPlan motion = planMotion(flatRing(), cell, automatic);
  EXPECT_EQ(motion.fixture.riserHeight, 0.0);
  EXPECT_EQ(motion.fixture.substrateThickness, 10.0);
  expectMentions(motion.notes.back(), "without raising the cell's riser (0.0 mm)");
  EXPECT_EQ(parsePartPlacement("auto"), PartPlacement::Auto);
  EXPECT_EQ(toString(PartPlacement::Auto), "auto");
}

}  // namespace
}  // namespace curvedslicer
