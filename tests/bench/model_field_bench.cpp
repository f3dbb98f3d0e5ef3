// The geodesic field on the bundled real models. Each model is cleaned, voxelized (PCA frame, as
// the pipeline does) and its field computed from the build plate under it (the default start
// surface) by the exact method (`anyangle`, alias `exact`, the default) and, with `--compare`,
// by another method; printed per model: wall and process CPU seconds of each call, the exact
// method's line-of-sight failures and edge pivots, and mean / max |other − exact| over the inside
// voxels in units of L with the worst voxel's centre (part frame, mm).
//
//   model_field_bench [--voxel 0.5] [--compare paper] [--export DIR] [--json] MODEL...
//
// --export DIR writes DIR/<model stem>/ for the scikit-fmm peer (model_vs_skfmm.py), as
// field_bench --export does (C order, shape = grid dims): inside.npy (uint8), source_distance.npy
// (float64 mm, straight distance from the inside cell centres to the start surface up to 3·√3·L,
// NaN elsewhere: the seeds are the cells within √3·L), exact.npy (float64 mm, the exact method's
// field, NaN outside or unreached) and meta.json. --json prints one JSON object per model instead
// of the text line.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/npy_export.hpp"
#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/field/start_surface.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace {

using namespace curvedslicer;

struct Settings {
  double voxel = 0.5;
  std::string compare;  // empty: the exact method alone
  std::string exportDir;
  bool json = false;
};

struct Timed {
  GeodesicResult result;
  double seconds = 0.0;
  double cpuSeconds = 0.0;
};

Timed timeField(const VoxelGrid& grid, const TriMesh& model, const TriMesh& source,
                GeodesicMethod method) {
  GeodesicOptions options;
  options.method = method;
  Timed t;
  const std::clock_t cpu0 = std::clock();
  const auto t0 = std::chrono::steady_clock::now();
  t.result = method == GeodesicMethod::Paper ? computeGeodesicField(grid, source, options)
                                             : computeGeodesicField(grid, model, source, options);
  t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t.cpuSeconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  return t;
}

/// |other − exact| in units of L over the inside voxels the exact field reaches.
nlohmann::json compareFields(const VoxelGrid& grid, const DistanceField& exact,
                             const DistanceField& other) {
  const GridGeometry& g = grid.geometry;
  const double L = g.voxelSize;
  double sum = 0.0, worst = 0.0, over = 0.0, under = 0.0;
  std::size_t count = 0, worstIndex = 0, beyond = 0;
  for (std::size_t n = 0; n < g.cellCount(); ++n) {
    if (!grid.inside[n] || !exact.reached(n)) continue;
    const double d = (static_cast<double>(other.at(n)) - exact.at(n)) / L;
    sum += std::abs(d);
    ++count;
    over = std::max(over, d);
    under = std::min(under, d);
    beyond += std::abs(d) > 0.1;
    if (std::abs(d) > worst) {
      worst = std::abs(d);
      worstIndex = n;
    }
  }
  const Vec3 at = g.centerInPart(worstIndex);
  return {{"mean_L", count ? sum / static_cast<double>(count) : 0.0},
          {"max_L", worst},
          {"max_at_mm", {at.x(), at.y(), at.z()}},
          {"max_over_L", over},
          {"max_under_L", under},
          {"voxels_beyond_0.1L", beyond}};
}

void exportModel(const std::filesystem::path& dir, const VoxelGrid& grid, const TriMesh& source,
                 const DistanceField& exact, nlohmann::json meta) {
  const GridGeometry& g = grid.geometry;
  const std::size_t N = g.cellCount();
  ensureDirectory(dir);
  testing::writeNpy(dir / "inside.npy", "|u1", g.dims, grid.inside.data(), N);
  const std::vector<double> near =
      testing::insideSourceDistances(grid, source, 3.0 * std::sqrt(3.0) * g.voxelSize);
  testing::writeNpy(dir / "source_distance.npy", "<f8", g.dims, near.data(), N * sizeof(double));
  std::vector<double> field(N, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t n = 0; n < N; ++n)
    if (grid.inside[n] && exact.reached(n)) field[n] = exact.at(n);
  testing::writeNpy(dir / "exact.npy", "<f8", g.dims, field.data(), N * sizeof(double));
  meta["dims"] = {g.dims.x(), g.dims.y(), g.dims.z()};
  writeTextFileAtomically(dir / "meta.json", meta.dump(2) + "\n");
}

void runModel(const std::filesystem::path& path, const Settings& s) {
  const TriMesh model = cleanMesh(readMesh(path)).mesh;
  const TriMesh source = resolveStartSurface(model, StartSurface{});
  VoxelizeOptions vo;
  vo.voxelSize = s.voxel;
  const VoxelizeResult vox = voxelize(model, vo);
  const Timed exact = timeField(vox.grid, model, source, GeodesicMethod::AnyAngle);
  nlohmann::json j = {{"model", path.filename().string()},
                      {"voxel_size_mm", s.voxel},
                      {"inside", vox.grid.insideCount},
                      {"seeds", exact.result.seedCount},
                      {"exact_seconds", exact.seconds},
                      {"exact_cpu_s", exact.cpuSeconds},
                      {"los_failures", exact.result.lineOfSightFailures},
                      {"edge_pivots", exact.result.edgePivots}};
  if (!s.compare.empty()) {
    const GeodesicMethod method = parseGeodesicMethod(s.compare);
    const Timed other = timeField(vox.grid, model, source, method);
    j["compare"] = {{"method", std::string(toString(method))},
                    {"seconds", other.seconds},
                    {"cpu_s", other.cpuSeconds},
                    {"error", compareFields(vox.grid, exact.result.field, other.result.field)}};
  }
  if (!s.exportDir.empty())
    exportModel(std::filesystem::path(s.exportDir) / path.stem(), vox.grid, source,
                exact.result.field, j);
  if (s.json) {
    std::printf("%s\n", j.dump().c_str());
  } else {
    std::printf(
        "%-34s L %.3f mm, %zu inside: exact %.3f s (CPU %.2f s; %zu LOS failures, %zu "
        "edge pivots)",
        path.filename().string().c_str(), s.voxel, vox.grid.insideCount, exact.seconds,
        exact.cpuSeconds, exact.result.lineOfSightFailures, exact.result.edgePivots);
    if (j.contains("compare")) {
      const auto& c = j["compare"];
      const auto& e = c["error"];
      std::printf(
          "; %s %.3f s (CPU %.2f s): |%s - exact| mean %.4f L, max %.4f L (over %.3f, "
          "under %.3f), %zu voxels beyond 0.1 L",
          c["method"].get<std::string>().c_str(), c["seconds"].get<double>(),
          c["cpu_s"].get<double>(), c["method"].get<std::string>().c_str(),
          e["mean_L"].get<double>(), e["max_L"].get<double>(), e["max_over_L"].get<double>(),
          e["max_under_L"].get<double>(), e["voxels_beyond_0.1L"].get<std::size_t>());
    }
    std::printf("\n");
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  std::vector<std::string> models;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const bool hasValue = a + 1 < argc;
    if (arg == "--voxel" && hasValue) {
      s.voxel = std::stod(argv[++a]);
    } else if (arg == "--compare" && hasValue) {
      s.compare = argv[++a];
    } else if (arg == "--export" && hasValue) {
      s.exportDir = argv[++a];
    } else if (arg == "--json") {
      s.json = true;
    } else if (arg.rfind("--", 0) == 0) {
      std::fprintf(stderr, "model_field_bench: unknown option: %s; see the file comment\n",
                   arg.c_str());
      return 2;
    } else {
      models.push_back(arg);
    }
  }
  if (models.empty()) {
    std::fprintf(stderr,
                 "usage: model_field_bench [--voxel L] [--compare METHOD] [--export DIR] "
                 "[--json] MODEL...\n");
    return 2;
  }
  try {
    for (const std::string& m : models) runModel(m, s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "model_field_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
