// Path spline fit (`fitPath`) on synthetic raw iso-lines of the sizes the planner produces. Not a
// test. Usage: path_fit_bench [--benchmark_repetitions=5 ...] (Google Benchmark flags).
// Cases: a closed ring with small or large zigzag noise (smooth, a few thousand raw points), a
// closed square ring (four sharp corners, like the simple_box layers), an open wavy line, and
// iso-line-like rings of four bulged sides meeting at 53° corners (0.1 mm raw spacing, with and
// without sub-micrometre segments; the bunny's iso-lines have such corners where fronts meet).
// Counters: raw points, fit rounds, resampled points, achieved fit deviation (mm). Results are in
// tests/bench/README.md ("Paths").
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "common/raw_paths.hpp"
#include "curvedslicer/paths/path_fit.hpp"

namespace {

using curvedslicer::Polyline;
using curvedslicer::Vec3;

/// Closed ring of radius r (mm) with n raw points, a 3-lobed radius wave, a z wave and a ±zigzag
/// of `zigzag` mm (the noise of iso-lines marched on a voxel field).
Polyline makeRing(double r, int n, double zigzag) {
  Polyline p;
  p.closed = true;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    const double rr = r * (1.0 + 0.1 * std::sin(3 * a)) + (i % 2 ? zigzag : -zigzag);
    p.points.emplace_back(rr * std::cos(a), rr * std::sin(a), 0.5 * std::sin(2 * a));
  }
  return p;
}

/// Closed square ring of side `side` (mm) with raw points every `step` mm (sharp corners).
Polyline makeSquare(double side, double step) {
  Polyline p;
  p.closed = true;
  const int perSide = static_cast<int>(std::lround(side / step));
  const Vec3 corners[4] = {Vec3(0, 0, 0), Vec3(side, 0, 0), Vec3(side, side, 0), Vec3(0, side, 0)};
  for (int c = 0; c < 4; ++c) {
    const Vec3 a = corners[c], b = corners[(c + 1) % 4];
    for (int i = 0; i < perSide; ++i) p.points.push_back(a + (b - a) * (double(i) / perSide));
  }
  return p;
}

/// Open wavy line, n raw points 0.25 mm apart.
Polyline makeWave(int n) {
  Polyline p;
  for (int i = 0; i < n; ++i) {
    const double x = 0.25 * i;
    p.points.emplace_back(x, 3.0 * std::sin(x / 6.0), 0.2 * std::cos(x / 4.0));
  }
  return p;
}

/// The path-fit tests' cornered ring (testing::makeBulgedSquareRing): sagitta side / 12, raw
/// points 0.1 mm apart, corners of 53°; with `micro`, 0.5 µm twins of every tenth raw point.
Polyline makeCornerRing(double side, bool micro) {
  std::vector<Vec3> corners;
  return curvedslicer::testing::makeBulgedSquareRing(side, side / 12.0, 0.1, micro ? 5e-4 : 0.0,
                                                     corners);
}

void runFit(benchmark::State& state, const Polyline& raw) {
  curvedslicer::PathFitResult fit;
  for (auto _ : state) {
    fit = curvedslicer::fitPath(raw);
    benchmark::DoNotOptimize(fit.points.points.data());
  }
  state.counters["raw"] = static_cast<double>(raw.points.size());
  state.counters["rounds"] = fit.fitRounds;
  state.counters["resampled"] = static_cast<double>(fit.points.points.size());
  state.counters["dev_mm"] = fit.fitDeviation;
}

void BM_FitRing(benchmark::State& state) {
  runFit(state, makeRing(0.1 * static_cast<double>(state.range(0)), state.range(0), 0.01));
}
BENCHMARK(BM_FitRing)->Arg(500)->Arg(2000)->Arg(5000)->Unit(benchmark::kMillisecond);

/// Zigzag of 0.08 mm > the 0.05 mm tolerance: the fit has to follow the raw noise.
void BM_FitNoisyRing(benchmark::State& state) {
  runFit(state, makeRing(0.1 * static_cast<double>(state.range(0)), state.range(0), 0.08));
}
BENCHMARK(BM_FitNoisyRing)->Arg(500)->Arg(2000)->Unit(benchmark::kMillisecond);

void BM_FitSquare(benchmark::State& state) {
  runFit(state, makeSquare(static_cast<double>(state.range(0)), 0.5));
}
BENCHMARK(BM_FitSquare)->Arg(20)->Arg(60)->Unit(benchmark::kMillisecond);

void BM_FitCornerRing(benchmark::State& state) {
  runFit(state, makeCornerRing(static_cast<double>(state.range(0)), state.range(1) != 0));
}
BENCHMARK(BM_FitCornerRing)
    ->Args({40, 0})
    ->Args({120, 0})
    ->Args({120, 1})
    ->Unit(benchmark::kMillisecond);

void BM_FitWave(benchmark::State& state) {
  runFit(state, makeWave(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_FitWave)->Arg(2000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
