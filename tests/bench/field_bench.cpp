// Geodesic field methods side by side on the closed-form cases of tests/cpp/common/analytic_cases:
// speed (inside voxels per wall-clock second) and error against the closed form (mean / max
// |error| in units of L over the reached inside voxels, measureFieldError).
//
// Methods:
//   paper     computeGeodesicField(grid, source, {.method = GeodesicMethod::Paper}) — the paper's
//             optimised search (§2.2.2), parallel over both cores where it evaluates eq. 8;
//   anyangle  computeGeodesicField(grid, model, source) — the default, with the model surface
//             (exact line of sight, sub-voxel pivots on reflex edges).
// Each benchmark is one call, timed by wall clock (manual time; counter voxels_per_s = inside
// voxels / wall seconds) and by process CPU time of all threads (counter cpu_s); the case (grid,
// meshes) is built outside the timing. Benchmarks are named field/<case>/<cells>/<method>, <case>
// one of slab, shell, lshape, ubend, <cells> the cells along the case's longest side.
//
// Export mode, for the scikit-fmm comparison (tests/bench/field_vs_skfmm.py):
//   field_bench --export DIR [--cells 128,256] [--cases slab,shell,lshape,ubend]
// writes DIR/<case>_<cells>/ with NumPy files, all of shape (nx, ny, nz), C order = the grid's
// index order:
//   inside.npy    uint8, 1 for inside cells;
//   phi_band.npy  float64, signed distance (mm) to the start surface in the seed band √3·L, NaN
//                 elsewhere: +d on the seed voxels (inside cells within the band — the voxels and
//                 exact values the C++ methods seed with), −d on the outside cells behind the start
//                 surface (closest source point a perpendicular foot, so not beside its rim). The
//                 start surfaces lie on the solid's boundary: without those negative cells skfmm
//                 would see no zero level set;
//   exact.npy     float64, closed-form distance at inside cell centres, NaN outside; mm;
//   anyangle.npy  float32, the default method's field (mm, +inf unreached), so the script can check
//                 that its error metric reproduces measureFieldError;
//   meta.json     voxel size, dims, counts, and measureFieldError of anyangle.npy.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/analytic_cases.hpp"
#include "common/npy_export.hpp"
#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/field/geodesic_field.hpp"

namespace {

using namespace curvedslicer;
using curvedslicer::testing::AnalyticCase;

struct CaseKind {
  const char* slug;
  AnalyticCase (*make)(int);
};

const CaseKind kCases[] = {{"slab", &testing::makeTiltedSlabCase},
                           {"shell", &testing::makeSphericalShellCase},
                           {"lshape", &testing::makeLShapeCase},
                           {"ubend", &testing::makeUBendCase}};

const CaseKind& caseKind(const std::string& slug) {
  for (const CaseKind& k : kCases)
    if (slug == k.slug) return k;
  throw InvalidInput("unknown case: '" + slug + "'; choose slab, shell, lshape or ubend");
}

/// The most recently built case (benchmarks of one case run back to back; one slot bounds memory).
const AnalyticCase& analyticCase(const std::string& slug, int cells) {
  static std::string key;
  static std::unique_ptr<AnalyticCase> cached;
  const std::string want = slug + "/" + std::to_string(cells);
  if (!cached || key != want) {
    cached.reset();
    cached = std::make_unique<AnalyticCase>(caseKind(slug).make(cells));
    key = want;
  }
  return *cached;
}

// ---- benchmarks
// -----------------------------------------------------------------------------------

void benchmarkField(benchmark::State& state, const std::string& slug, int cells,
                    GeodesicMethod method) {
  const AnalyticCase& c = analyticCase(slug, cells);
  GeodesicOptions options;
  options.method = method;
  GeodesicResult result;
  for (auto _ : state) {
    const std::clock_t cpu0 = std::clock();
    const auto t0 = std::chrono::steady_clock::now();
    result = method == GeodesicMethod::Paper ? computeGeodesicField(c.grid, c.source, options)
                                             : computeGeodesicField(c.grid, c.model, c.source);
    const auto t1 = std::chrono::steady_clock::now();
    const std::clock_t cpu1 = std::clock();
    const double seconds = std::chrono::duration<double>(t1 - t0).count();
    state.SetIterationTime(seconds);
    state.counters["voxels_per_s"] = static_cast<double>(c.grid.insideCount) / seconds;
    // Process CPU time, all threads (std::clock on Linux): less sensitive to other processes
    // than the wall clock on a loaded machine.
    state.counters["cpu_s"] = static_cast<double>(cpu1 - cpu0) / CLOCKS_PER_SEC;
  }
  const testing::FieldError e = testing::measureFieldError(c, result.field);
  state.counters["inside"] = static_cast<double>(c.grid.insideCount);
  state.counters["mean_err_L"] = e.mean;
  state.counters["max_err_L"] = e.max;
  state.counters["unreached"] = static_cast<double>(e.unreached);
  state.counters["seeds"] = static_cast<double>(result.seedCount);
  if (method == GeodesicMethod::AnyAngle) {
    state.counters["los_tests"] = static_cast<double>(result.lineOfSightTests);
    state.counters["los_failures"] = static_cast<double>(result.lineOfSightFailures);
    state.counters["edge_pivots"] = static_cast<double>(result.edgePivots);
  }
}

void registerBenchmarks(const std::vector<std::string>& cases, const std::vector<int>& cellList) {
  for (const std::string& slug : cases) {
    for (int cells : cellList) {
      for (GeodesicMethod method : {GeodesicMethod::Paper, GeodesicMethod::AnyAngle}) {
        const std::string name =
            "field/" + slug + "/" + std::to_string(cells) + "/" + std::string(toString(method));
        benchmark::RegisterBenchmark(name.c_str(),
                                     [slug, cells, method](benchmark::State& st) {
                                       benchmarkField(st, slug, cells, method);
                                     })
            ->UseManualTime()
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
      }
    }
  }
}

// ---- export
// -----------------------------------------------------------------------------------------

void exportCase(const std::filesystem::path& root, const std::string& slug, int cells) {
  const AnalyticCase c = caseKind(slug).make(cells);
  const GridGeometry& g = c.grid.geometry;
  const std::filesystem::path dir = root / (slug + "_" + std::to_string(cells));
  ensureDirectory(dir);
  const std::size_t N = g.cellCount();

  testing::writeNpy(dir / "inside.npy", "|u1", g.dims, c.grid.inside.data(), N);
  const std::vector<double> phi = testing::signedBandDistances(c.grid, c.source);
  testing::writeNpy(dir / "phi_band.npy", "<f8", g.dims, phi.data(), N * sizeof(double));
  std::vector<double> exact(N, std::nan(""));
  for (std::size_t n = 0; n < N; ++n)
    if (c.grid.inside[n]) exact[n] = c.exact(g.centerInPart(n));
  testing::writeNpy(dir / "exact.npy", "<f8", g.dims, exact.data(), N * sizeof(double));

  const GeodesicResult any = computeGeodesicField(c.grid, c.model, c.source);
  testing::writeNpy(dir / "anyangle.npy", "<f4", g.dims, any.field.distance.data(),
                    N * sizeof(float));
  const testing::FieldError e = testing::measureFieldError(c, any.field);

  std::size_t seeds = 0, behind = 0;
  for (double d : phi) {
    seeds += d >= 0.0;
    behind += d < 0.0;
  }
  nlohmann::json meta = {
      {"case", slug},
      {"name", c.name},
      {"cells", cells},
      {"voxel_size_mm", g.voxelSize},
      {"dims", {g.dims.x(), g.dims.y(), g.dims.z()}},
      {"inside", c.grid.insideCount},
      {"seeds", seeds},
      {"band_cells_behind_source", behind},
      {"anyangle_seeds", any.seedCount},
      {"anyangle_error", {{"mean", e.mean}, {"max", e.max}, {"voxels", e.voxels}}},
  };
  writeTextFileAtomically(dir / "meta.json", meta.dump(2) + "\n");
  std::printf(
      "exported %s: dims %d x %d x %d, L = %.4f mm, %zu inside, %zu seeds (%zu in the C++ field), "
      "%zu band cells behind the start surface\n",
      dir.string().c_str(), g.dims.x(), g.dims.y(), g.dims.z(), g.voxelSize, c.grid.insideCount,
      seeds, any.seedCount, behind);
}

// ---- command line
// -----------------------------------------------------------------------------------

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

/// Takes `--name VALUE` or `--name=VALUE` out of argv; returns true if it was there.
bool takeFlag(int& argc, char** argv, const std::string& name, std::string& value) {
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    int used = 0;
    if (arg == name && a + 1 < argc) {
      value = argv[a + 1];
      used = 2;
    } else if (arg.rfind(name + "=", 0) == 0) {
      value = arg.substr(name.size() + 1);
      used = 1;
    }
    if (used) {
      for (int b = a; b + used < argc; ++b) argv[b] = argv[b + used];
      argc -= used;
      return true;
    }
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string exportDir, cellsArg = "128,256", casesArg = "slab,shell,lshape,ubend";
    const bool exporting = takeFlag(argc, argv, "--export", exportDir);
    takeFlag(argc, argv, "--cells", cellsArg);
    takeFlag(argc, argv, "--cases", casesArg);
    std::vector<int> cells;
    for (const std::string& s : splitList(cellsArg)) {
      const int n = std::stoi(s);
      if (n < 8) throw InvalidInput("cells along the longest side must be >= 8: " + s);
      cells.push_back(n);
    }
    const std::vector<std::string> cases = splitList(casesArg);
    for (const std::string& slug : cases) caseKind(slug);  // validates
    if (exporting) {
      for (const std::string& slug : cases)
        for (int n : cells) exportCase(exportDir, slug, n);
      return 0;
    }
    registerBenchmarks(cases, cells);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "field_bench: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
