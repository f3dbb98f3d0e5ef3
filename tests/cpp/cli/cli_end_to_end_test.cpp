// The `curvedslicer layers` binary end to end on the bundled models: exit code, the files it
// writes (layer surfaces and the voxel-set cloud parse and agree with report.json), re-runs into
// the same folder, --quiet, and interruption by SIGINT, SIGTERM or SIGHUP.
#include <gtest/gtest.h>

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"
#include "common/sanitized_build.hpp"
#include "common/test_paths.hpp"
#include "common/text_assertions.hpp"
#include "curvedslicer/layers/layer_simplification.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::CliRun;
using testing::freshTempDir;
using testing::listFolder;
using testing::modelPath;
using testing::runCli;
using Args = std::vector<std::string>;

// The build's own flag (common/sanitized_build.hpp), not a compiler's macro: clang does not
// define __SANITIZE_ADDRESS__.
constexpr bool kSanitized = testing::sanitizedBuild();
/// Cells on the longest side of a model's box: ~120 as in a real run, fewer under ASan (slow).
constexpr double kCellsOnLongestSide = kSanitized ? 48.0 : 120.0;

using testing::contains;

std::string numberArg(double value) {
  std::ostringstream s;
  s.precision(6);
  s << value;
  return s.str();
}

/// Voxel size for about kCellsOnLongestSide cells on the longest side of the model's box.
double voxelSizeFor(const fs::path& model) {
  const Vec3 size = readMesh(model).bounds().size();
  return std::stod(numberArg(size.maxCoeff() / kCellsOnLongestSide));
}

json readReport(const fs::path& dir) {
  return json::parse(testing::readWholeFile(dir / "report.json"));
}

/// Checks everything a successful run promises about `dir`; returns the report.
json expectConsistentOutput(const fs::path& dir, double L, double h, const std::string& format,
                            const std::vector<std::string>& otherFiles = {}) {
  const json report = readReport(dir);
  const json& layers = report.at("layers");
  const std::size_t n = layers.size();
  EXPECT_GT(n, 0u);
  EXPECT_EQ(report.at("outputs").at("layer_count").get<std::size_t>(), n);
  EXPECT_DOUBLE_EQ(report.at("inputs").at("layer_thickness_mm").get<double>(), h);
  EXPECT_DOUBLE_EQ(report.at("inputs").at("voxel_size_mm").get<double>(), L);
  EXPECT_EQ(report.at("inputs").at("layer_format"), format);

  // Exactly the promised files, no staging folder left behind.
  std::vector<std::string> expectedFiles{"report.json", "voxel_sets.ply"};
  expectedFiles.insert(expectedFiles.end(), otherFiles.begin(), otherFiles.end());
  for (const json& layer : layers) expectedFiles.push_back(layer.at("file"));
  std::sort(expectedFiles.begin(), expectedFiles.end());
  EXPECT_EQ(listFolder(dir), expectedFiles);

  // Grid and field counts agree.
  const json& grid = report.at("grid");
  const auto dims = grid.at("dims").get<std::vector<std::size_t>>();
  EXPECT_EQ(grid.at("cells").get<std::size_t>(), dims.at(0) * dims.at(1) * dims.at(2));
  const auto inside = grid.at("inside_voxels").get<std::size_t>();
  EXPECT_GT(inside, 0u);
  EXPECT_LE(inside, grid.at("cells").get<std::size_t>());
  const json& field = report.at("field");
  EXPECT_EQ(
      field.at("reached").get<std::size_t>() + field.at("unreached").at("count").get<std::size_t>(),
      inside);
  EXPECT_GT(field.at("seeds").get<std::size_t>(), 0u);
  for (const char* stage : {"read", "clean", "analyze", "voxelize", "field", "layers"}) {
    EXPECT_TRUE(report.at("timing").at("stage_seconds").contains(stage)) << stage;
  }
  EXPECT_GT(report.at("peak_memory_bytes").get<double>(), 0.0);

  // Layers: consecutive indices, level i·h, files that parse with the reported counts.
  const auto& bmin = report.at("mesh").at("bounds").at("min_mm");
  const auto& bmax = report.at("mesh").at("bounds").at("max_mm");
  std::map<int, double> levels;
  std::size_t voxelSetTotal = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const json& layer = layers[k];
    const int index = layer.at("index");
    EXPECT_EQ(index, static_cast<int>(k) + 1);
    EXPECT_NEAR(layer.at("level_mm").get<double>(), index * h, 1e-9 * index * h);
    levels[index] = layer.at("level_mm").get<double>();
    voxelSetTotal += layer.at("voxel_set_size").get<std::size_t>();
    const fs::path file = dir / layer.at("file").get<std::string>();
    std::size_t vertices = 0, triangles = 0;
    std::vector<Vec3> points;
    if (format == "ply") {
      const testing::PlyData ply = testing::readBinaryPly(file);
      const auto* v = ply.element("vertex");
      const auto* f = ply.element("face");
      EXPECT_TRUE(v != nullptr && f != nullptr) << file;
      if (v == nullptr || f == nullptr) continue;
      vertices = v->count;
      triangles = f->count;
      for (std::size_t r = 0; r < v->count; ++r) {
        points.emplace_back(v->value(r, 0), v->value(r, 1), v->value(r, 2));
      }
      for (const auto& face : f->lists) {
        EXPECT_EQ(face.size(), 3u);
        for (std::int64_t i : face) EXPECT_TRUE(i >= 0 && static_cast<std::size_t>(i) < vertices);
      }
    } else {
      const TriMesh mesh = readMesh(file);
      vertices = mesh.vertexCount();
      triangles = mesh.triangleCount();
      points = mesh.vertices;
    }
    EXPECT_EQ(vertices, layer.at("vertices").get<std::size_t>()) << file;
    EXPECT_EQ(triangles, layer.at("triangles").get<std::size_t>()) << file;
    EXPECT_GT(triangles, 0u) << file;
    std::size_t strayVertices = 0;  // non-finite or outside the model's box (+ L)
    for (const Vec3& p : points) {
      for (int a = 0; a < 3; ++a) {
        if (!(std::isfinite(p[a]) && p[a] >= bmin[a].get<double>() - L &&
              p[a] <= bmax[a].get<double>() + L)) {
          ++strayVertices;
          break;
        }
      }
    }
    EXPECT_EQ(strayVertices, 0u) << file;
  }

  // The voxel sets of eq. 13: every point of S_i has |t − i·h| ≤ L/2.
  const testing::PlyData cloud = testing::readBinaryPly(dir / "voxel_sets.ply");
  const auto* v = cloud.element("vertex");
  EXPECT_TRUE(v != nullptr);
  if (v == nullptr) return report;
  EXPECT_EQ(v->count, report.at("outputs").at("voxel_set_points").get<std::size_t>());
  EXPECT_EQ(v->count, voxelSetTotal);
  std::size_t outside = 0;
  for (std::size_t r = 0; r < v->count; ++r) {
    const int layer = static_cast<int>(v->value(r, 3));
    const double t = v->value(r, 4);
    const auto it = levels.find(layer);
    if (it == levels.end() || std::abs(t - it->second) > 0.5 * L + 1e-4 * (1.0 + t)) ++outside;
  }
  EXPECT_EQ(outside, 0u) << "voxel-set points violating eq. 13";
  return report;
}

Args layersArgs(const fs::path& model, double L, double h, const fs::path& out,
                const Args& extra = {}) {
  Args args{"layers",     model.string(), "--layer-thickness", numberArg(h), "--voxel",
            numberArg(L), "-o",           out.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

class CliEndToEnd : public ::testing::TestWithParam<std::string> {};

TEST_P(CliEndToEnd, BundledModelFromTheBuildPlate) {
  const fs::path model = modelPath(GetParam());
  const double L = voxelSizeFor(model);
  const double h = std::stod(numberArg(5.0 * L));
  const fs::path out = freshTempDir() / "out";
  const CliRun run = runCli(layersArgs(model, L, h, out));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const json report = expectConsistentOutput(out, L, h, "ply");
  EXPECT_TRUE(report.at("mesh").at("closed").get<bool>());
  // Grown from the plate under a part standing on it, the layers reach up to its height.
  const double height = report.at("mesh").at("bounds").at("max_mm")[2].get<double>() -
                        report.at("mesh").at("bounds").at("min_mm")[2].get<double>();
  const double maxDistance = report.at("field").at("max_distance_mm").get<double>();
  const auto unreached = report.at("field").at("unreached").at("count").get<std::size_t>();
  // At ~120 cells every bundled part is one connected solid; the coarse sanitizer grid may cut
  // thin branches off (they are then reported as unreached, not layered).
  if (!kSanitized) {
    EXPECT_EQ(unreached, 0u);
  }
  if (unreached == 0) {
    EXPECT_GE(maxDistance, height - 2.0 * L);
  }
  const auto layers = report.at("layers").size();
  EXPECT_LE(layers, static_cast<std::size_t>(std::floor(maxDistance / h)));
  EXPECT_GE(layers + 1, static_cast<std::size_t>(std::floor(maxDistance / h)));
  EXPECT_TRUE(contains(run.out, "curvedslicer: wrote " + std::to_string(layers) + " layers"));
}

std::string modelTestName(const ::testing::TestParamInfo<std::string>& model) {
  return model.param.substr(0, model.param.find('.'));
}

INSTANTIATE_TEST_SUITE_P(
    BundledStl, CliEndToEnd,
    ::testing::Values("branches_70_closed_low_res.stl", "bunny_closed_low_res.stl",
                      "distorted_v_closed_mid_res.stl", "overhang_coin_closed_low_res.stl",
                      "simple_box_closed_low_res.stl", "simple_cylinder_closed_mid_res.stl"),
    modelTestName);

TEST(CliEndToEndCases, BundledStlModelsAreAllCovered) {
  std::vector<std::string> stl;
  for (const auto& e : fs::directory_iterator(modelPath(""))) {
    if (e.path().extension() == ".stl") stl.push_back(e.path().filename().string());
  }
  std::sort(stl.begin(), stl.end());
  EXPECT_EQ(stl, (std::vector<std::string>{
                     "branches_70_closed_low_res.stl", "bunny_closed_low_res.stl",
                     "distorted_v_closed_mid_res.stl", "overhang_coin_closed_low_res.stl",
                     "simple_box_closed_low_res.stl", "simple_cylinder_closed_mid_res.stl"}))
      << "a model was added or removed: update the INSTANTIATE_TEST_SUITE_P list";
}

TEST(CliEndToEndCases, CurvedBasePair) {
  const fs::path model = modelPath("custom_base_geom_to_slice.obj");
  const fs::path base = modelPath("custom_base_surface.obj");
  const double L = voxelSizeFor(model);
  const double h = std::stod(numberArg(5.0 * L));
  const fs::path out = freshTempDir() / "out";
  // The part is an open tube: its bottom rim sits on the base, its top is a slanted cut.
  const CliRun run =
      runCli(layersArgs(model, L, h, out, {"--start", "mesh:" + base.string(), "--cap-holes"}));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const json report = expectConsistentOutput(out, L, h, "ply");
  EXPECT_EQ(report.at("inputs").at("start_surface").at("spec"), "mesh:" + base.string());
  EXPECT_TRUE(report.at("inputs").at("cap_holes").get<bool>());
  const json& repair = report.at("mesh").at("repair");
  EXPECT_EQ(repair.at("holes"), 2);
  EXPECT_EQ(repair.at("capped_holes"), 2);
  EXPECT_EQ(repair.at("holes_capped_on_start_surface"), 1);
  EXPECT_TRUE(report.at("mesh").at("closed").get<bool>());
  EXPECT_EQ(report.at("grid").at("unresolved_voxels"), 0);
  EXPECT_EQ(report.at("field").at("unreached").at("count"), 0);
  EXPECT_GT(report.at("start_surface").at("triangles").get<std::size_t>(), 0u);
  // The tube reaches about 90 mm above the base: one layer per h up to there, each about h thick.
  const double maxDistance = report.at("field").at("max_distance_mm").get<double>();
  EXPECT_GT(maxDistance, 80.0);
  const auto layers = report.at("layers").size();
  EXPECT_LE(layers, static_cast<std::size_t>(std::floor(maxDistance / h)));
  EXPECT_GE(layers + 1, static_cast<std::size_t>(std::floor(maxDistance / h)));
  for (const json& layer : report.at("layers")) {
    if (layer.at("thickness_mm").at("samples").get<std::size_t>() == 0) continue;
    EXPECT_NEAR(layer.at("thickness_mm").at("mean").get<double>(), h, 0.5 * L)
        << "layer " << layer.at("index");
  }
}

TEST(CliEndToEndCases, SimplifyAndFullResolutionFlagsAndTheDefault) {
  const fs::path model = modelPath("simple_cylinder_closed_mid_res.stl");
  const double L = voxelSizeFor(model);
  const double h = std::stod(numberArg(5.0 * L));
  const fs::path byDefault = freshTempDir("default");
  const fs::path asked = freshTempDir("asked");
  const fs::path full = freshTempDir("full");
  ASSERT_EQ(runCli(layersArgs(model, L, h, byDefault, {"-q"})).exitCode, 0);
  ASSERT_EQ(runCli(layersArgs(model, L, h, asked, {"-q", "--simplify-layers"})).exitCode, 0);
  ASSERT_EQ(runCli(layersArgs(model, L, h, full, {"-q", "--full-resolution-layers"})).exitCode, 0);
  const json simplified = expectConsistentOutput(asked, L, h, "ply");
  const json fullResolution = expectConsistentOutput(full, L, h, "ply");
  EXPECT_FALSE(simplified.at("inputs").at("full_resolution_layers").get<bool>());
  EXPECT_DOUBLE_EQ(simplified.at("inputs").at("layer_tolerance_mm").get<double>(), 0.05 * L);
  EXPECT_TRUE(fullResolution.at("inputs").at("full_resolution_layers").get<bool>());
  EXPECT_TRUE(fullResolution.at("inputs").at("layer_tolerance_mm").is_null());
  const json& s = simplified.at("layer_simplification");
  const json& f = fullResolution.at("layer_simplification");
  EXPECT_EQ(s.at("full_resolution_triangles"), f.at("triangles"));
  EXPECT_EQ(f.at("full_resolution_triangles"), f.at("triangles"));
  EXPECT_LT(s.at("triangles").get<std::size_t>(), f.at("triangles").get<std::size_t>() / 3);
  // No flag: the layers of LayerSimplificationOptions{}, file for file.
  const fs::path expected = LayerSimplificationOptions{}.enabled ? asked : full;
  ASSERT_EQ(listFolder(byDefault), listFolder(expected));
  for (const json& layer : simplified.at("layers")) {
    const std::string file = layer.at("file");
    EXPECT_EQ(testing::readWholeFile(byDefault / file), testing::readWholeFile(expected / file))
        << file;
  }
}

TEST(CliEndToEndCases, FacesOfTheModelAsStartSurface) {
  // The bottom triangles of the box, given by their positions in the file, give the same layers
  // as the build plate.
  const fs::path model = modelPath("simple_box_closed_low_res.stl");
  const TriMesh mesh = readMesh(model);
  const double zmin = mesh.bounds().min.z();
  std::string ids;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.corner(t, 0).z() == zmin && mesh.corner(t, 1).z() == zmin &&
        mesh.corner(t, 2).z() == zmin) {
      if (!ids.empty()) ids += ',';
      ids += std::to_string(mesh.faceIds[t]);
    }
  }
  ASSERT_FALSE(ids.empty());
  const double L = 5.0, h = 20.0;
  const fs::path outFaces = freshTempDir("faces");
  const fs::path outPlate = freshTempDir("plate");
  const CliRun faces = runCli(layersArgs(model, L, h, outFaces, {"--start", "faces:" + ids}));
  ASSERT_EQ(faces.exitCode, 0) << faces.err;
  const CliRun plate = runCli(layersArgs(model, L, h, outPlate));
  ASSERT_EQ(plate.exitCode, 0) << plate.err;
  const json a = expectConsistentOutput(outFaces, L, h, "ply");
  const json b = expectConsistentOutput(outPlate, L, h, "ply");
  ASSERT_EQ(a.at("layers").size(), b.at("layers").size());
  for (std::size_t k = 0; k < a.at("layers").size(); ++k) {
    EXPECT_NEAR(a["layers"][k]["area_mm2"].get<double>(), b["layers"][k]["area_mm2"].get<double>(),
                0.01 * b["layers"][k]["area_mm2"].get<double>());
  }
}

TEST(CliEndToEndCases, ObjFormatPaperMethodModelGrid) {
  const fs::path model = modelPath("overhang_coin_closed_low_res.stl");
  const double L = 4.0, h = 12.0;
  const fs::path out = freshTempDir();
  const CliRun run = runCli(
      layersArgs(model, L, h, out, {"--format", "obj", "--method", "paper", "--grid", "model"}));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const json report = expectConsistentOutput(out, L, h, "obj");
  EXPECT_EQ(report.at("inputs").at("method"), "paper");
  EXPECT_EQ(report.at("field").at("method"), "paper");
  EXPECT_EQ(report.at("inputs").at("grid_alignment"), "model");
  // Model-aligned grid: the frame axes are the model axes.
  EXPECT_EQ(report.at("grid").at("frame").at("axes")[0], json::array({1.0, 0.0, 0.0}));
}

TEST(CliEndToEndCases, RerunReplacesLayersAndFailureKeepsThem) {
  const fs::path model = modelPath("simple_box_closed_low_res.stl");
  const fs::path out = freshTempDir();
  std::ofstream(out / "notes.txt") << "keep me";
  const double L = 5.0;
  ASSERT_EQ(runCli(layersArgs(model, L, 20.0, out)).exitCode, 0);
  const json first = readReport(out);
  ASSERT_EQ(runCli(layersArgs(model, L, 40.0, out)).exitCode, 0);
  // Old layer files are gone, other files stay.
  const json second = expectConsistentOutput(out, L, 40.0, "ply", {"notes.txt"});
  EXPECT_LT(second.at("layers").size(), first.at("layers").size());
  EXPECT_EQ(testing::readWholeFile(out / "notes.txt"), "keep me");
  // A failing run changes nothing.
  std::vector<std::string> before = listFolder(out);
  const std::string report = testing::readWholeFile(out / "report.json");
  const CliRun bad = runCli(layersArgs(model, L, 40.0, out, {"--start", "plane:z=-1000"}));
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_EQ(listFolder(out), before);
  EXPECT_EQ(testing::readWholeFile(out / "report.json"), report);
}

TEST(CliEndToEndCases, QuietPrintsNothing) {
  const fs::path out = freshTempDir();
  const CliRun run =
      runCli(layersArgs(modelPath("simple_box_closed_low_res.stl"), 5.0, 20.0, out, {"--quiet"}));
  EXPECT_EQ(run.exitCode, 0) << run.err;
  EXPECT_EQ(run.out, "");
  EXPECT_EQ(run.err, "");
  EXPECT_TRUE(fs::exists(out / "report.json"));
  // Without --quiet, stderr (not a terminal here) has plain progress lines per stage.
  const CliRun loud =
      runCli(layersArgs(modelPath("simple_box_closed_low_res.stl"), 5.0, 20.0, freshTempDir("2")));
  EXPECT_EQ(loud.exitCode, 0);
  EXPECT_TRUE(contains(loud.err, "] voxelize\n"));
  EXPECT_TRUE(contains(loud.err, "] field\n"));
  EXPECT_EQ(loud.err.find('\r'), std::string::npos);
}

/// Ctrl+C (SIGINT), a kill (SIGTERM) and the terminal closing (SIGHUP) each cancel a running job:
/// exit code 128 + the signal, nothing written.
class InterruptSignals : public ::testing::TestWithParam<int> {};

INSTANTIATE_TEST_SUITE_P(CliEndToEndCases, InterruptSignals,
                         ::testing::Values(SIGINT, SIGTERM, SIGHUP));

TEST_P(InterruptSignals, CancelWithoutOutput) {
  const int signal = GetParam();
  const fs::path model = modelPath("bunny_closed_low_res.stl");
  const fs::path out = freshTempDir(std::to_string(signal));
  testing::CliProcess process(layersArgs(model, kSanitized ? 1.5 : 0.8, 4.0, out));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  bool started = false;
  while (process.running() && std::chrono::steady_clock::now() < deadline) {
    if (process.currentErr().find("voxelize") != std::string::npos) {
      started = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(started) << "the job ended or never reached the voxelize stage";
  ASSERT_EQ(::kill(process.pid(), signal), 0);
  const CliRun run = process.wait();
  EXPECT_EQ(run.exitCode, 128 + signal) << run.err;
  EXPECT_TRUE(contains(run.err, "curvedslicer: interrupted; nothing was written"));
  EXPECT_TRUE(listFolder(out).empty());
}

}  // namespace
}  // namespace curvedslicer
