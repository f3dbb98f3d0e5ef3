// Motion planning + JBI export throughput: positioner angles (eq. 16), robot inverse kinematics
// (planMotion) and the Yaskawa JBI writer for a turbine-base-like cone plan (closed circles up a
// cone's side, V towards the previous bead) in the default cell (Motoman HP20D + tilt-rotate
// positioner, Cartesian positions, 2000-line jobs).
//
// Benchmarks (one timed call each, wall clock, plan built outside the timing):
//   export/motion/<points>      planMotion only
//   export/jbi/<points>         JbiWriter only (motion plan prepared outside the timing)
//   export/motion+jbi/<points>  both, the figure quoted in tests/bench/README.md
// Counters: points_per_s, bytes (total size of all job files), files (jobs incl. the main job).
// Run: export_bench --benchmark_filter='export/' (1 M points needs about 1 GB of memory).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstddef>

#include "curvedslicer/export/jbi_writer.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "export/export_test_support.hpp"

namespace {

using namespace curvedslicer;
using Clock = std::chrono::steady_clock;

/// A cone plan with about `points` points: 4000 points per circle.
Plan makeBenchPlan(std::size_t points) {
  const int perCircle = 4000;
  const int circles = static_cast<int>((points + perCircle - 1) / perCircle);
  return curvedslicer::testing::makeConePlan(circles, perCircle);
}

void runStages(benchmark::State& state, bool motionStage, bool exportStage) {
  const Plan plan = makeBenchPlan(static_cast<std::size_t>(state.range(0)));
  const Cell cell = defaultCell();
  MotionPlan prepared;
  if (!motionStage) prepared = planMotion(plan, cell);
  std::size_t bytes = 0, files = 0;
  for (auto _ : state) {
    const auto begin = Clock::now();
    MotionPlan motion = motionStage ? planMotion(plan, cell) : MotionPlan{};
    const MotionPlan& used = motionStage ? motion : prepared;
    if (exportStage) {
      const ExportResult result = JbiWriter().write(used, cell, {}, {});
      bytes = result.totalBytes();
      files = result.files.size();
      benchmark::DoNotOptimize(result.files.data());
    }
    benchmark::DoNotOptimize(used.points.data());
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - begin).count());
  }
  const double points = static_cast<double>(plan.pointCount());
  state.counters["points"] = points;
  state.counters["points_per_s"] = benchmark::Counter(
      points * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  if (exportStage) {
    state.counters["bytes"] = static_cast<double>(bytes);
    state.counters["files"] = static_cast<double>(files);
  }
}

void motionOnly(benchmark::State& state) {
  runStages(state, true, false);
}
void jbiOnly(benchmark::State& state) {
  runStages(state, false, true);
}
void motionAndJbi(benchmark::State& state) {
  runStages(state, true, true);
}

BENCHMARK(motionOnly)
    ->Name("export/motion")
    ->Arg(100000)
    ->Arg(1000000)
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(jbiOnly)
    ->Name("export/jbi")
    ->Arg(100000)
    ->Arg(1000000)
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(motionAndJbi)
    ->Name("export/motion+jbi")
    ->Arg(100000)
    ->Arg(1000000)
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
