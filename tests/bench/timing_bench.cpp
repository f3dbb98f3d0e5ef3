// Time parameterisation throughput (robot/timing.hpp): parameteriseTime on the motion
// of a turbine-base-like cone plan (closed circles up a cone's side, 4000 points per circle) in
// the default cell, and the whole planMotion (positioner angles with the near-singular band,
// inverse kinematics with the tool roll, time parameterisation) for comparison.
//
// Benchmarks (one timed call each, wall clock, plan and motion built outside the timing):
//   timing/parameterise/<points>  parameteriseTime only: the figure for the target
//                                 (>= 50 k points/s together with the collision check)
//   timing/motion/<points>        planMotion (which ends with parameteriseTime)
// Counters: points (motion points), points_per_s.
// Run: timing_bench --benchmark_filter='timing/' (1 M points needs about 1 GB of memory).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstddef>

#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/timing.hpp"
#include "export/export_test_support.hpp"

namespace {

using namespace curvedslicer;
using Clock = std::chrono::steady_clock;

Plan makeBenchPlan(std::size_t points) {
  const int perCircle = 4000;
  const int circles = static_cast<int>((points + perCircle - 1) / perCircle);
  return curvedslicer::testing::makeConePlan(circles, perCircle);
}

void setCounters(benchmark::State& state, std::size_t points) {
  state.counters["points"] = static_cast<double>(points);
  state.counters["points_per_s"] =
      benchmark::Counter(static_cast<double>(points) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
}

void BM_Parameterise(benchmark::State& state) {
  const Cell cell = defaultCell();
  MotionPlan motion = planMotion(makeBenchPlan(static_cast<std::size_t>(state.range(0))), cell);
  for (auto _ : state) {
    const auto begin = Clock::now();
    parameteriseTime(motion, cell);
    benchmark::DoNotOptimize(motion.points.back().time);
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - begin).count());
  }
  setCounters(state, motion.points.size());
}

void BM_Motion(benchmark::State& state) {
  const Cell cell = defaultCell();
  const Plan plan = makeBenchPlan(static_cast<std::size_t>(state.range(0)));
  std::size_t points = 0;
  for (auto _ : state) {
    const auto begin = Clock::now();
    const MotionPlan motion = planMotion(plan, cell);
    points = motion.points.size();
    benchmark::DoNotOptimize(motion.points.data());
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - begin).count());
  }
  setCounters(state, points);
}

}  // namespace

BENCHMARK(BM_Parameterise)
    ->Name("timing/parameterise")
    ->Arg(100000)
    ->Arg(1000000)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
BENCHMARK(BM_Motion)
    ->Name("timing/motion")
    ->Arg(1000000)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

BENCHMARK_MAIN();
