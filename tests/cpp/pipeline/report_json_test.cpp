// Unit tests of pipeline/report_json.hpp on a hand-made job result.
#include "curvedslicer/pipeline/report_json.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

using Json = nlohmann::ordered_json;
using Names = std::vector<std::string>;

Names keysOf(const Json& object) {
  Names keys;
  for (auto it = object.begin(); it != object.end(); ++it) keys.push_back(it.key());
  return keys;
}

LayerJobResult makeResult() {
  LayerJobResult r;
  r.clean.mergedVertices = 30;
  r.clean.degenerateTriangles = 2;
  r.clean.weldTolerance = 1e-4;
  r.meshReport.vertices = 8;
  r.meshReport.triangles = 12;
  r.meshReport.volume = 1000.0;
  r.meshReport.area = 600.0;
  r.meshReport.components = 1;
  r.meshReport.bounds.extend(Vec3(0, 0, 0));
  r.meshReport.bounds.extend(Vec3(10, 10, 10));
  r.startDescription = "plane z=0 mm";
  r.source.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  r.source.triangles = {Vec3i(0, 1, 2)};
  GridGeometry& g = r.voxelization.grid.geometry;
  g.voxelSize = 0.5;
  g.dims = Vec3i(24, 24, 24);
  g.corner = Vec3(-1, -1, -1);
  r.voxelization.grid.insideCount = 8000;
  r.voxelization.stats.columns = 576;
  r.voxelization.stats.oddColumns = 3;
  r.voxelization.stats.resolvedVoxels = 40;
  r.field.seedCount = 400;
  r.field.reachedCount = 7990;
  r.field.unreached.count = 10;
  r.field.unreached.components = 1;
  r.field.unreached.bounds.extend(Vec3(5, 5, 9));
  r.field.unreached.example = Vec3(5, 5, 9);
  r.field.maxDistance = 9.75;
  r.field.lineOfSightTests = 12345;
  for (int i = 1; i <= 2; ++i) {
    LayerSurface s;
    s.index = i;
    s.level = 4.0 * i;
    s.mesh.vertices = {Vec3(0, 0, 4.0 * i), Vec3(1, 0, 4.0 * i), Vec3(0, 1, 4.0 * i)};
    s.mesh.triangles = {Vec3i(0, 1, 2)};
    s.area = 0.5;
    s.components = 1;
    if (i == 2) s.thicknessToPrevious = {3, 3.9, 4.0, 4.1};
    r.layers.surfaces.push_back(s);
    r.layers.voxelSets.push_back({i, 4.0 * i, std::vector<std::size_t>(100u * i, 0)});
  }
  r.layers.stats.simplificationTolerance = 0.025;
  r.layers.stats.fullResolutionTriangles = 40;
  r.layers.stats.simplifiedTriangles = 2;
  r.layers.stats.simplificationSeconds = 0.25;
  r.stageTimes = {{"clean", 0.01}, {"voxelize", 0.5}, {"field", 2.0}};
  r.totalSeconds = 2.6;
  r.peakMemoryBytes = 123456789;
  return r;
}

LayerReportInputs makeInputs() {
  LayerReportInputs in;
  in.modelPath = "part.stl";
  in.modelFileTriangles = 14;
  in.startSpec = "plane:bottom";
  in.layerFiles = {"layer_0001.ply", "layer_0002.ply"};
  in.voxelSetsFile = "voxel_sets.ply";
  return in;
}

LayerJobOptions makeOptions() {
  LayerJobOptions o;
  o.layers.layerThickness = 4.0;
  o.voxelize.voxelSize = 0.5;
  return o;
}

TEST(LayerReport, TopLevelKeysInAStableOrder) {
  const Json report = makeLayerReport(makeInputs(), makeOptions(), makeResult());
  EXPECT_EQ(keysOf(report),
            (Names{"report", "format_version", "inputs", "mesh", "start_surface", "grid", "field",
                   "warnings", "timing", "peak_memory_bytes", "peak_memory_bytes_per_cell",
                   "outputs", "layer_simplification", "layers"}));
  EXPECT_EQ(keysOf(report["inputs"]),
            (Names{"model", "start_surface", "layer_thickness_mm", "voxel_size_mm", "method",
                   "grid_alignment", "cap_holes", "memory_budget_bytes", "full_resolution_layers",
                   "layer_tolerance_mm", "layer_format", "version"}));
  // Same input, same text.
  EXPECT_EQ(formatLayerReport(report),
            formatLayerReport(makeLayerReport(makeInputs(), makeOptions(), makeResult())));
  EXPECT_EQ(formatLayerReport(report).back(), '\n');
}

TEST(LayerReport, CarriesInputsMeshGridAndField) {
  const Json report = makeLayerReport(makeInputs(), makeOptions(), makeResult());
  EXPECT_EQ(report["inputs"]["model"], "part.stl");
  EXPECT_EQ(report["inputs"]["start_surface"]["spec"], "plane:bottom");
  EXPECT_EQ(report["inputs"]["start_surface"]["description"], "plane z=0 mm");
  EXPECT_EQ(report["inputs"]["layer_thickness_mm"], 4.0);
  EXPECT_EQ(report["inputs"]["method"], "anyangle");
  EXPECT_EQ(report["inputs"]["grid_alignment"], "pca");
  EXPECT_EQ(report["inputs"]["version"], CURVEDSLICER_VERSION);
  EXPECT_EQ(report["mesh"]["file_triangles"], 14);
  EXPECT_EQ(report["mesh"]["repair"]["merged_vertices"], 30);
  EXPECT_EQ(report["mesh"]["bounds"]["max_mm"], Json::array({10.0, 10.0, 10.0}));
  EXPECT_EQ(report["start_surface"]["triangles"], 1);
  EXPECT_DOUBLE_EQ(report["start_surface"]["area_mm2"].get<double>(), 0.5);
  EXPECT_EQ(report["grid"]["dims"], Json::array({24, 24, 24}));
  EXPECT_EQ(report["grid"]["cells"], 24 * 24 * 24);
  EXPECT_EQ(report["grid"]["inside_voxels"], 8000);
  EXPECT_DOUBLE_EQ(report["grid"]["inside_volume_mm3"].get<double>(), 1000.0);
  EXPECT_EQ(report["grid"]["odd_columns"], 3);
  EXPECT_EQ(report["grid"]["frame"]["axes"][2], Json::array({0.0, 0.0, 1.0}));
  EXPECT_EQ(report["field"]["seeds"], 400);
  EXPECT_EQ(report["field"]["reached"], 7990);
  EXPECT_EQ(report["field"]["unreached"]["count"], 10);
  EXPECT_EQ(report["field"]["unreached"]["example_mm"], Json::array({5.0, 5.0, 9.0}));
  EXPECT_EQ(report["field"]["max_distance_mm"], 9.75);
  EXPECT_EQ(report["field"]["diagnostics"]["line_of_sight_tests"], 12345);
  EXPECT_EQ(keysOf(report["timing"]["stage_seconds"]), (Names{"clean", "voxelize", "field"}));
  EXPECT_EQ(report["peak_memory_bytes"], 123456789);
  EXPECT_DOUBLE_EQ(report["peak_memory_bytes_per_cell"].get<double>(),
                   123456789.0 / (24 * 24 * 24));
  EXPECT_EQ(report["outputs"]["layer_count"], 2);
  EXPECT_EQ(report["outputs"]["voxel_set_points"], 300);
}

TEST(LayerReport, RecordsTheLayerSimplification) {
  LayerJobOptions options = makeOptions();
  options.layers.simplification.enabled = true;
  Json report = makeLayerReport(makeInputs(), options, makeResult());
  EXPECT_EQ(report["inputs"]["full_resolution_layers"], false);
  EXPECT_EQ(report["inputs"]["layer_tolerance_mm"], 0.025);
  EXPECT_EQ(report["layer_simplification"]["enabled"], true);
  EXPECT_EQ(report["layer_simplification"]["tolerance_mm"], 0.025);
  EXPECT_EQ(report["layer_simplification"]["full_resolution_triangles"], 40);
  EXPECT_EQ(report["layer_simplification"]["triangles"], 2);
  EXPECT_EQ(report["layer_simplification"]["seconds"], 0.25);
  options.layers.simplification.enabled = false;
  report = makeLayerReport(makeInputs(), options, makeResult());
  EXPECT_EQ(report["inputs"]["full_resolution_layers"], true);
  EXPECT_TRUE(report["inputs"]["layer_tolerance_mm"].is_null());
  EXPECT_TRUE(report["layer_simplification"]["tolerance_mm"].is_null());
}

TEST(LayerReport, OneEntryPerLayer) {
  const Json layers = makeLayerReport(makeInputs(), makeOptions(), makeResult())["layers"];
  ASSERT_EQ(layers.size(), 2u);
  EXPECT_EQ(keysOf(layers[0]), (Names{"index", "level_mm", "file", "vertices", "triangles",
                                      "full_resolution_triangles", "area_mm2", "components",
                                      "thickness_mm", "voxel_set_size"}));
  EXPECT_EQ(layers[1]["index"], 2);
  EXPECT_EQ(layers[1]["level_mm"], 8.0);
  EXPECT_EQ(layers[1]["file"], "layer_0002.ply");
  EXPECT_EQ(layers[1]["vertices"], 3);
  EXPECT_EQ(layers[1]["triangles"], 1);
  EXPECT_EQ(layers[1]["thickness_mm"]["mean"], 4.0);
  EXPECT_EQ(layers[1]["thickness_mm"]["samples"], 3);
  EXPECT_EQ(layers[1]["voxel_set_size"], 200);
  // A layer without thickness samples has null statistics, not zeros.
  EXPECT_TRUE(layers[0]["thickness_mm"]["min"].is_null());
  EXPECT_EQ(layers[0]["thickness_mm"]["samples"], 0);
}

TEST(LayerReport, NonFiniteNumbersAndMissingFilesBecomeNull) {
  LayerJobResult result = makeResult();
  result.field.unreached = {};
  result.field.maxDistance = std::numeric_limits<double>::infinity();
  LayerReportInputs inputs = makeInputs();
  inputs.layerFiles.clear();
  inputs.voxelSetsFile.clear();
  const Json report = makeLayerReport(inputs, makeOptions(), result);
  EXPECT_TRUE(report["field"]["max_distance_mm"].is_null());
  EXPECT_TRUE(report["field"]["unreached"]["bounds"]["min_mm"].is_null());
  EXPECT_TRUE(report["field"]["unreached"]["example_mm"].is_null());
  EXPECT_TRUE(report["layers"][0]["file"].is_null());
  EXPECT_TRUE(report["outputs"]["voxel_sets_file"].is_null());
  // The text is valid JSON that parses back to the same document.
  EXPECT_EQ(Json::parse(formatLayerReport(report)), report);
}

TEST(LayerReport, RejectsFileNamesThatDoNotMatchTheLayers) {
  LayerReportInputs inputs = makeInputs();
  inputs.layerFiles.pop_back();
  EXPECT_THROW(makeLayerReport(inputs, makeOptions(), makeResult()), InvalidInput);
}

}  // namespace
}  // namespace curvedslicer
