// Plan file I/O: byte-identical JSON round trip, schema conformance, CSV layout, and the reader's
// specific error for each kind of bad file.
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
  plan.parameters = {1.5,        0.5,        3.7,        2.0,           0.05,
                     "anyangle", "accurate", "boundary", "centre_bead", 22.5};
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
        path.points.push_back(q);
      }
      path.length = 10.0 / 3.0;
      layer.paths.push_back(path);
    }
    plan.layers.push_back(layer);
  }
  plan.layers.push_back(PlanLayer{2, 4.5, "", {}, {"no room for a bead"}});
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
  EXPECT_EQ(line, "layer,path,point,closed,x_mm,y_mm,z_mm,nx,ny,nz,vx,vy,vz");
  std::size_t rows = 0;
  std::string first;
  while (std::getline(lines, line)) {
    if (rows == 0) first = line;
    ++rows;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 12) << line;
  }
  EXPECT_EQ(rows, plan.pointCount());
  EXPECT_EQ(first.rfind("0,0,0,1,", 0), 0u) << first;
  // Numbers read back exactly.
  std::istringstream cells(first);
  std::string cell;
  for (int i = 0; i < 5; ++i) std::getline(cells, cell, ',');
  EXPECT_EQ(std::stod(cell), plan.layers[0].paths[0].points[0].position.x());
}

TEST(PlanIo, RejectsNonJson) {
  expectReadError("{\"format\": ", "plan.json is not valid JSON");
}

TEST(PlanIo, RejectsOtherFormat) {
  expectReadError(R"({"format": "something-else", "version": 1})", "not a CurvedSlicer plan");
}

TEST(PlanIo, RejectsNewerVersion) {
  expectReadError(editedJson([](auto& d) { d["version"] = 2; }),
                  "plan format version not supported: 2");
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
                  "/layers/1/paths/0/points/2 has 8 numbers: expected 9");
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
