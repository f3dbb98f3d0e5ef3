// Plan file I/O: byte-identical JSON round trip, schema conformance, CSV layout, and the reader's
// specific error for each kind of bad file.
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "json_schema_subset.hpp"

namespace curvedslicer {
namespace {

/// A small plan with awkward numbers (thirds, tiny and large magnitudes, negative zero).
Plan makeSamplePlan() {
  Plan plan;
  plan.model = "resources/models/bunny \"closed\".stl";
  plan.start = "plane:bottom";
  plan.parameters = {
      1.5,      0.5,  3.7, 2.0, 0.05, "anyangle", "accurate", "boundary", "centre_bead",
      "growth", 22.5, {},  {},  {},   {},         {},         {},         {}};
  plan.parameters.minFeatureWidth = 1.85;
  plan.parameters.beadWidthRange = std::array<double, 2>{0.7, 1.3};
  plan.parameters.connectInsets = true;
  plan.parameters.fillGaps = false;
  plan.parameters.minGapArea = 2.25;
  plan.parameters.cornerOverdeposit = 0.925;
  plan.parameters.cornerFillAngle = 85.0;
  for (int l = 0; l < 2; ++l) {
    PlanLayer layer;
    layer.index = l;
    layer.height = 1.5 * (l + 1) + 1.0 / 3.0;
    layer.surface = "layer_000" + std::to_string(l + 1) + ".ply";
    if (l == 1) layer.warnings.push_back("2 path piece(s) shorter than 3.7 mm not deposited");
    for (int p = 0; p < 2; ++p) {
      PlanPath path;
      path.layer = l;
      path.index = p;
      path.closed = p == 0;
      for (int i = 0; i < 4; ++i) {
        PathPoint q;
        const double a = 0.1 * i + p + l / 7.0;
        q.position = Vec3(std::cos(a) * 12.345678901234567, std::sin(a) * 1e-7, 1e5 / 3.0 + i);
        q.normal = Vec3(std::sin(a), 0.0, std::cos(a)).normalized();
        q.deposition = Vec3(-0.0, -std::sin(a), -std::cos(a)).normalized();
        q.width = l == 1 ? 2.6 + i / 3.0 : 0.0;  // layer 0: "the bead spacing"
        path.points.push_back(q);
      }
      path.length = 10.0 / 3.0;
      if (l == 1 && p == 1) path.dwell = 0.75;
      layer.paths.push_back(path);
    }
    if (l == 0) {
      layer.coverage.measured = true;
      layer.coverage.area = 1234.5;
      layer.coverage.voidShare = 1.0 / 3.0;
      layer.coverage.overlapShare = 0.0125;
      layer.coverage.beadWidth = 3.7;
      layer.coverage.arcStarts = 2;
      layer.coverage.voids = {{400.0, Vec3(1.0 / 7.0, -2.5, 1e5 / 3.0), 12.25},
                              {11.5, Vec3(3, 4, 5), 3.0}};
    }
    plan.layers.push_back(layer);
  }
  plan.layers.push_back(PlanLayer{2, 4.5, "", {}, {"no room for a bead"}, {}});
  plan.layers[2].coverage.measured = true;  // measured without voids: a fully covered layer
  plan.layers[2].coverage.area = 10.0;
  return plan;
}

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Expects parsePlanJson(text) to throw InvalidInput whose message contains `needle`.
void expectReadError(const std::string& text, const std::string& needle) {
  try {
    parsePlanJson(text, "plan.json");
    FAIL() << "no error; expected one containing: " << needle;
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

/// The sample plan's JSON with `edit` applied to the parsed document.
template <typename F>
std::string editedJson(F&& edit) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(formatPlanJson(makeSamplePlan()));
  edit(doc);
  return doc.dump();
}

TEST(PlanIo, JsonRoundTripIsByteIdentical) {
  const Plan plan = makeSamplePlan();
  const std::string first = formatPlanJson(plan);
  const Plan read = parsePlanJson(first);
  const std::string second = formatPlanJson(read);
  EXPECT_EQ(first, second);
  // Values survive exactly (shortest round-trip numbers).
  ASSERT_EQ(read.layers.size(), plan.layers.size());
  EXPECT_EQ(read.layers[1].paths[1].points[3].position, plan.layers[1].paths[1].points[3].position);
  EXPECT_EQ(read.layers[0].height, plan.layers[0].height);
  EXPECT_EQ(read.model, plan.model);
  EXPECT_EQ(read.layers[2].warnings, plan.layers[2].warnings);
  EXPECT_EQ(read.layers[0].paths[0].closed, true);
  EXPECT_EQ(read.parameters.initialCurve, "boundary");
  // Version 2: widths (0 = the bead spacing is written as the bead spacing), dwell, coverage, the
  // bead coverage parameters.
  EXPECT_NE(first.find("\"version\": 2,"), std::string::npos);
  EXPECT_EQ(read.layers[0].paths[0].points[0].width, 3.7);
  EXPECT_EQ(read.layers[1].paths[1].points[2].width, plan.layers[1].paths[1].points[2].width);
  EXPECT_EQ(read.layers[1].paths[1].dwell, 0.75);
  EXPECT_EQ(read.layers[1].paths[0].dwell, 0.0);
  EXPECT_EQ(first.find("\"dwell_s\""), first.rfind("\"dwell_s\""));  // only where > 0
  EXPECT_TRUE(read.layers[0].coverage.measured);
  EXPECT_EQ(read.layers[0].coverage.voidShare, 1.0 / 3.0);
  EXPECT_EQ(read.layers[0].coverage.arcStarts, 2u);
  ASSERT_EQ(read.layers[0].coverage.voids.size(), 2u);
  EXPECT_EQ(read.layers[0].coverage.voids[0].centre, plan.layers[0].coverage.voids[0].centre);
  EXPECT_FALSE(read.layers[1].coverage.measured);
  EXPECT_TRUE(read.layers[2].coverage.measured);
  EXPECT_EQ(read.parameters.minFeatureWidth, 1.85);
  EXPECT_EQ(read.parameters.beadWidthRange, (std::array<double, 2>{0.7, 1.3}));
  EXPECT_EQ(read.parameters.connectInsets, true);
  EXPECT_EQ(read.parameters.fillGaps, false);
  EXPECT_EQ(read.parameters.minGapArea, 2.25);
  EXPECT_EQ(read.parameters.cornerOverdeposit, 0.925);
  EXPECT_EQ(read.parameters.cornerFillAngle, 85.0);
}

/// A version-1 plan as `curvedslicer plan` wrote it before version 2 (no widths, no coverage).
const char* const kVersion1Plan = R"({
  "format": "curvedslicer-plan",
  "version": 1,
  "model": "m.stl",
  "start": "plane:bottom",
  "parameters": {
    "layer_thickness_mm": 1.5,
    "voxel_size_mm": 0.5,
    "bead_spacing_mm": 3.7,
    "point_spacing_mm": 2,
    "fit_tolerance_mm": 0.05,
    "field_method": "anyangle",
    "surface_method": "accurate",
    "initial_curve": "boundary",
    "narrow_strips": "centre_bead",
    "corner_angle_deg": 30
  },
  "point_fields": ["x", "y", "z", "nx", "ny", "nz", "vx", "vy", "vz"],
  "layers": [
    {
      "index": 0,
      "height_mm": 1.5,
      "surface": "layer_0001.ply",
      "warnings": [],
      "paths": [
        {
          "layer": 0,
          "index": 0,
          "closed": false,
          "length_mm": 1,
          "points": [
            [0, 0, 1.5, 0, 0, 1, 0, 0, -1],
            [1, 0, 1.5, 0, 0, 1, 0, 0, -1]
          ]
        }
      ]
    }
  ]
}
)";

TEST(PlanIo, Version1PlanIsMigrated) {
  // Width = the bead spacing, coverage not measured, no bead coverage parameters; written back as
  // version 2, which then round-trips byte-identically.
  const Plan plan = parsePlanJson(kVersion1Plan, "old.json");
  ASSERT_EQ(plan.layers.size(), 1u);
  for (const PathPoint& q : plan.layers[0].paths[0].points) EXPECT_EQ(q.width, 3.7);
  EXPECT_EQ(plan.layers[0].paths[0].dwell, 0.0);
  EXPECT_FALSE(plan.layers[0].coverage.measured);
  EXPECT_FALSE(plan.parameters.minFeatureWidth.has_value());
  EXPECT_FALSE(plan.parameters.beadWidthRange.has_value());
  EXPECT_FALSE(plan.parameters.connectInsets.has_value());
  EXPECT_FALSE(plan.parameters.fillGaps.has_value());
  const std::string v2 = formatPlanJson(plan);
  EXPECT_NE(v2.find("\"version\": 2,"), std::string::npos);
  EXPECT_NE(v2.find("[0, 0, 1.5, 0, 0, 1, 0, 0, -1, 3.7]"), std::string::npos) << v2;
  EXPECT_EQ(v2.find("coverage"), std::string::npos);
  EXPECT_EQ(formatPlanJson(parsePlanJson(v2)), v2);
}

TEST(PlanIo, Version1PlanKeepsItsOwnLayout) {
  // A version-1 file with a width column or a version-2 key is refused, naming the location.
  std::string tenNumbers = kVersion1Plan;
  tenNumbers.replace(tenNumbers.find("0, 0, -1]"), 9, "0, 0, -1, 3.7]");
  expectReadError(tenNumbers, "/layers/0/paths/0/points/0 has 10 numbers: expected 9");
  std::string coverage = kVersion1Plan;
  coverage.replace(coverage.find("\"warnings\": [],"), 16, "\"warnings\": [], \"coverage\": {},");
  expectReadError(coverage, "/layers/0 has an unknown key \"coverage\"");
}

TEST(PlanIo, Version2RejectsBadCoverageWidthAndDwell) {
  expectReadError(editedJson([](auto& d) { d["layers"][0]["coverage"]["void_share"] = 1.5; }),
                  "/layers/0/coverage/void_share is 1.5: expected a share in [0, 1]");
  expectReadError(editedJson([](auto& d) { d["layers"][0]["coverage"].erase("voids"); }),
                  "/layers/0/coverage lacks the key \"voids\"");
  expectReadError(editedJson([](auto& d) {
                    d["layers"][0]["coverage"]["voids"][1]["centre_mm"] = {1, 2};
                  }),
                  "/layers/0/coverage/voids/1/centre_mm must be an array of 3 numbers");
  expectReadError(editedJson([](auto& d) { d["layers"][1]["paths"][0]["points"][1][9] = -1; }),
                  "/layers/1/paths/0/points/1/9 must not be negative");
  expectReadError(editedJson([](auto& d) { d["layers"][1]["paths"][1]["dwell_s"] = -2; }),
                  "/layers/1/paths/1/dwell_s must not be negative");
  expectReadError(editedJson([](auto& d) {
                    d["parameters"]["bead_width_range"] = {1.1, 1.3};
                  }),
                  "/parameters/bead_width_range is [1.1,1.3]: expected [min, max] fractions");
  expectReadError(editedJson([](auto& d) { d["parameters"]["min_feature_width_mm"] = 0; }),
                  "/parameters/min_feature_width_mm is 0: expected a width > 0 mm");
  expectReadError(editedJson([](auto& d) { d["parameters"]["connect_insets"] = 1; }),
                  "/parameters/connect_insets must be true or false");
  expectReadError(editedJson([](auto& d) { d["parameters"]["fill_gaps"] = "yes"; }),
                  "/parameters/fill_gaps must be true or false");
  expectReadError(editedJson([](auto& d) { d["parameters"]["min_gap_area_mm2"] = -1; }),
                  "/parameters/min_gap_area_mm2 is -1: expected an area > 0 mm²");
  // The writer refuses what the reader would refuse.
  Plan bad = makeSamplePlan();
  bad.layers[0].coverage.overlapShare = std::nan("");
  EXPECT_THROW(formatPlanJson(bad), InvalidInput);
  bad = makeSamplePlan();
  bad.layers[1].paths[0].points[0].width = -1.0;
  EXPECT_THROW(formatPlanJson(bad), InvalidInput);
}

TEST(PlanIo, FileRoundTripIsByteIdentical) {
  const auto dir = testing::freshTempDir("plan_io_file");
  writePlanJson(dir / "a.json", makeSamplePlan());
  const Plan read = readPlanJson(dir / "a.json");
  writePlanJson(dir / "b.json", read);
  EXPECT_EQ(readText(dir / "a.json"), readText(dir / "b.json"));
  std::ostringstream stream;
  writePlanJson(stream, read);
  EXPECT_EQ(stream.str(), readText(dir / "a.json"));
}

TEST(PlanIo, JsonValidatesAgainstSchema) {
  std::ifstream in(std::filesystem::path(CURVEDSLICER_SOURCE_DIR) / "resources" / "schema" /
                   "plan.schema.json");
  ASSERT_TRUE(in) << "schema missing";
  const testing::SchemaSubsetValidator validator(nlohmann::json::parse(in));
  const auto errors = validator.validate(nlohmann::json::parse(formatPlanJson(makeSamplePlan())));
  EXPECT_TRUE(errors.empty()) << (errors.empty() ? "" : errors.front());
  // The validator is not vacuous: a broken document fails it.
  auto broken = nlohmann::json::parse(formatPlanJson(makeSamplePlan()));
  broken["layers"][0]["paths"][0]["points"][1].erase(9);
  broken["layers"][0]["paths"][0]["points"][1].erase(8);
  broken["layers"][1]["paths"][0]["closed"] = "yes";
  broken["extra"] = 1;
  EXPECT_EQ(validator.validate(broken).size(), 3u);
}

TEST(PlanIo, NarrowStripModeIsOptionalAndChecked) {
  // Written when set, read back; a plan without it (thin wall, or written before the option
  // existed) round-trips without it; another value is refused with its location.
  EXPECT_EQ(parsePlanJson(formatPlanJson(makeSamplePlan())).parameters.narrowStrips, "centre_bead");
  Plan older = makeSamplePlan();
  older.parameters.narrowStrips.clear();
  const std::string text = formatPlanJson(older);
  EXPECT_EQ(text.find("narrow_strips"), std::string::npos);
  EXPECT_EQ(formatPlanJson(parsePlanJson(text)), text);
  expectReadError(editedJson([](auto& d) { d["parameters"]["narrow_strips"] = "merge"; }),
                  "/parameters/narrow_strips is \"merge\": expected \"centre_bead\" or "
                  "\"overlap\"");
}

TEST(PlanIo, CornerAngleIsOptionalAndChecked) {
  // Written when set, read back; a plan written before the option existed round-trips without
  // it; a value outside (0, 180] or not a number is refused with its location.
  EXPECT_EQ(parsePlanJson(formatPlanJson(makeSamplePlan())).parameters.cornerAngle, 22.5);
  Plan older = makeSamplePlan();
  older.parameters.cornerAngle.reset();
  const std::string text = formatPlanJson(older);
  EXPECT_EQ(text.find("corner_angle_deg"), std::string::npos);
  EXPECT_FALSE(parsePlanJson(text).parameters.cornerAngle.has_value());
  EXPECT_EQ(formatPlanJson(parsePlanJson(text)), text);
  expectReadError(editedJson([](auto& d) { d["parameters"]["corner_angle_deg"] = 0; }),
                  "/parameters/corner_angle_deg is 0: expected an angle in (0, 180] degrees");
  expectReadError(editedJson([](auto& d) { d["parameters"]["corner_angle_deg"] = 190.5; }),
                  "/parameters/corner_angle_deg is 190.5: expected an angle in (0, 180] degrees");
  expectReadError(editedJson([](auto& d) { d["parameters"]["corner_angle_deg"] = "sharp"; }),
                  "/parameters/corner_angle_deg must be a number");
}

TEST(PlanIo, EmptyPlanRoundTrips) {
  Plan plan;
  const std::string text = formatPlanJson(plan);
  EXPECT_EQ(formatPlanJson(parsePlanJson(text)), text);
}

TEST(PlanIo, CsvHasOneRowPerPoint) {
  const Plan plan = makeSamplePlan();
  const std::string csv = formatPlanCsv(plan);
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "layer,path,point,closed,x_mm,y_mm,z_mm,nx,ny,nz,vx,vy,vz,w_mm");
  std::size_t rows = 0;
  std::string first;
  while (std::getline(lines, line)) {
    if (rows == 0) first = line;
    ++rows;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 13) << line;
  }
  EXPECT_EQ(rows, plan.pointCount());
  EXPECT_EQ(first.rfind("0,0,0,1,", 0), 0u) << first;
  // Numbers read back exactly.
  std::istringstream cells(first);
  std::string cell;
  for (int i = 0; i < 5; ++i) std::getline(cells, cell, ',');
  EXPECT_EQ(std::stod(cell), plan.layers[0].paths[0].points[0].position.x());
  // The last column is the width: the bead spacing where the point's width is 0.
  EXPECT_EQ(first.substr(first.rfind(',') + 1), "3.7");
}

TEST(PlanIo, RejectsNonJson) {
  expectReadError("{\"format\": ", "plan.json is not valid JSON");
}

TEST(PlanIo, RejectsOtherFormat) {
  expectReadError(R"({"format": "something-else", "version": 1})", "not a CurvedSlicer plan");
}

TEST(PlanIo, RejectsNewerVersion) {
  expectReadError(editedJson([](auto& d) { d["version"] = 3; }),
                  "plan format version not supported: 3 (this build reads up to 2)");
}

TEST(PlanIo, RejectsUnknownKey) {
  expectReadError(editedJson([](auto& d) { d["layers"][0]["colour"] = "red"; }),
                  "/layers/0 has an unknown key \"colour\"");
}

TEST(PlanIo, RejectsMissingKey) {
  expectReadError(editedJson([](auto& d) { d["parameters"].erase("bead_spacing_mm"); }),
                  "/parameters lacks the key \"bead_spacing_mm\"");
}

TEST(PlanIo, RejectsShortPointRow) {
  expectReadError(editedJson([](auto& d) { d["layers"][1]["paths"][0]["points"][2].erase(8); }),
                  "/layers/1/paths/0/points/2 has 9 numbers: expected 10 (x y z nx ny nz vx vy vz "
                  "w)");
}

TEST(PlanIo, RejectsNonUnitNormal) {
  expectReadError(editedJson([](auto& d) { d["layers"][0]["paths"][1]["points"][0][5] = 2.0; }),
                  "/layers/0/paths/1/points/0 normal is not a unit vector");
}

TEST(PlanIo, RejectsWrongPathLayer) {
  expectReadError(editedJson([](auto& d) { d["layers"][1]["paths"][0]["layer"] = 0; }),
                  "/layers/1/paths/0/layer is 0: expected the layer's index 1");
}

TEST(PlanIo, RejectsWrongType) {
  expectReadError(editedJson([](auto& d) { d["layers"][0]["height_mm"] = "high"; }),
                  "/layers/0/height_mm must be a number, found string");
}

TEST(PlanIo, RejectsSinglePointPath) {
  expectReadError(editedJson([](auto& d) {
                    auto& pts = d["layers"][0]["paths"][0]["points"];
                    pts.erase(pts.begin() + 1, pts.end());
                  }),
                  "/layers/0/paths/0 has 1 point(s): a path needs at least 2");
}

TEST(PlanIo, WriterRefusesPlanThatWouldNotReadBack) {
  Plan plan = makeSamplePlan();
  plan.layers[1].paths[0].points[0].deposition = Vec3(0, 0, 0);
  EXPECT_THROW(formatPlanJson(plan), InvalidInput);
  plan = makeSamplePlan();
  plan.layers[0].paths[1].index = 5;
  EXPECT_THROW(formatPlanCsv(plan), InvalidInput);
}

TEST(PlanIo, MissingFileIsIoError) {
  EXPECT_THROW(readPlanJson(std::filesystem::path("/nonexistent/plan.json")), IoError);
}

}  // namespace
}  // namespace curvedslicer
