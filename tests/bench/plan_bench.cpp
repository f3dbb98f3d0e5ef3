// Deposition-plan benchmark (issue 3): all paths of bunny_closed_low_res.stl at L = 0.5 mm,
// h = 1.5 mm, s = 3.7 mm — time per planner stage (initial curves, surface geodesic, iso-lines,
// fit, order, deposition) after the layer job. One iteration (the job takes minutes); the layer
// job itself is timed as a counter too. Override with environment variables for quicker runs:
//   CURVEDSLICER_BENCH_VOXEL (mm), CURVEDSLICER_BENCH_LAYER (mm), CURVEDSLICER_BENCH_SPACING (mm),
//   CURVEDSLICER_BENCH_SURFACE_METHOD (accurate | paper).
// Results and commands: tests/bench/README.md, section "Plan".
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <benchmark/benchmark.h>

#include "common/test_paths.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/pipeline/layer_pipeline.hpp"

namespace {

using namespace curvedslicer;

double envNumber(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::stod(v) : fallback;
}

void BM_PlanBunny(benchmark::State& state) {
  const double L = envNumber("CURVEDSLICER_BENCH_VOXEL", 0.5);
  const double h = envNumber("CURVEDSLICER_BENCH_LAYER", 1.5);
  const double s = envNumber("CURVEDSLICER_BENCH_SPACING", 3.7);
  const char* method = std::getenv("CURVEDSLICER_BENCH_SURFACE_METHOD");
  const TriMesh model = readMesh(testing::modelPath("bunny_closed_low_res.stl"));
  LayerJobOptions job;
  job.voxelize.voxelSize = L;
  job.layers.layerThickness = h;
  const auto jobBegin = std::chrono::steady_clock::now();
  const LayerJobResult layers = runLayerJob(model, job);
  const double jobSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - jobBegin).count();
  std::size_t triangles = 0;
  for (const LayerSurface& surface : layers.layers.surfaces)
    triangles += surface.mesh.triangleCount();

  PlannerOptions options;
  options.beadSpacing = s;
  if (method && std::string(method) == "paper") {
    options.geodesic.method = SurfaceGeodesicMethod::Paper;
  }
  PlanResult result;
  for (auto _ : state) {
    result = planLayers(layers.layers.surfaces, layers.source, options);
    benchmark::DoNotOptimize(result.plan.layers.data());
  }
  state.counters["layer_job_s"] = jobSeconds;
  state.counters["layers"] = static_cast<double>(layers.layers.surfaces.size());
  state.counters["layer_triangles"] = static_cast<double>(triangles);
  state.counters["paths"] = static_cast<double>(result.plan.pathCount());
  state.counters["points"] = static_cast<double>(result.plan.pointCount());
  state.counters["arc_m"] = result.stats.arcLength / 1000.0;
  state.counters["travel_m"] = result.stats.travel / 1000.0;
  state.counters["layers_without_paths"] = static_cast<double>(result.stats.layersWithoutPaths);
  for (const PlanStageTime& t : result.stats.stageTimes) {
    std::string name = t.name + "_s";
    for (char& c : name) {
      if (c == ' ' || c == '-') c = '_';
    }
    state.counters[name] = t.seconds;
  }
  std::printf(
      "L = %g mm, h = %g mm, s = %g mm: %zu layers (%zu triangles), %zu paths, %zu points\n", L, h,
      s, layers.layers.surfaces.size(), triangles, result.plan.pathCount(),
      result.plan.pointCount());
}
BENCHMARK(BM_PlanBunny)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
