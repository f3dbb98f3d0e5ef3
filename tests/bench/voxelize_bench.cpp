// Voxelization throughput (target: >= 300 M grid cells/s) on bunny_closed_low_res.stl at
// L = 0.5 mm and 0.25 mm, PCA grid as the pipeline uses it.
//
// One benchmark per voxel size: `voxelize(mesh, {.voxelSize = L})` timed by wall clock (manual
// time), with counters
//   cells_per_s       grid cells (the whole PCA box, padding included) / wall second — the target;
//   cells_per_cpu_s   the same per process CPU second of all threads (the machine is shared, so
//                     this is the load-independent figure; both cores work on the columns);
//   cells, inside     grid cells and inside voxels;
//   odd_columns       columns with an odd hit count (0 for this watertight model).
// The mesh is read and welded outside the timing; the grid's memory (1 byte per cell) is
// allocated inside it, as in the pipeline.
#include <benchmark/benchmark.h>

#include <chrono>
#include <ctime>

#include "common/test_paths.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/voxel/voxelize.hpp"

namespace {

using namespace curvedslicer;

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void bmVoxelizeBunny(benchmark::State& state) {
  static const TriMesh model = readMesh(testing::modelPath("bunny_closed_low_res.stl"));
  VoxelizeOptions options;
  options.voxelSize = static_cast<double>(state.range(0)) / 1000.0;  // range: micrometres
  double wall = 0.0, cpu = 0.0;
  std::size_t cells = 0, inside = 0, odd = 0;
  for (auto _ : state) {
    const double cpu0 = processCpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    VoxelizeResult result = voxelize(model, options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    cpu += processCpuSeconds() - cpu0;
    wall += seconds;
    state.SetIterationTime(seconds);
    cells = result.grid.geometry.cellCount();
    inside = 0;
    for (const std::uint8_t v : result.grid.inside) inside += v;
    odd = result.stats.oddColumns;
    benchmark::DoNotOptimize(result.grid.inside.data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["cells"] = static_cast<double>(cells);
  state.counters["inside"] = static_cast<double>(inside);
  state.counters["odd_columns"] = static_cast<double>(odd);
  state.counters["cells_per_s"] = static_cast<double>(cells) * n / wall;
  state.counters["cells_per_cpu_s"] = static_cast<double>(cells) * n / cpu;
}

BENCHMARK(bmVoxelizeBunny)
    ->Name("voxelize/bunny")
    ->Arg(500)
    ->Arg(250)
    ->ArgName("L_um")
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
