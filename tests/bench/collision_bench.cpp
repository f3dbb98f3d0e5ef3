// Collision check throughput (robot/collision.hpp): the torch envelope against the deposit so far
// and the positioner table, for every weld move and every arc-off move, on a synthetic motion of
// stacked concentric rings (rings 3.7 mm apart from 20 to 100 mm radius, 2 mm point spacing,
// layers 1.5 mm apart: about 4,150 points per layer), a vertical torch, retract and approach
// points 12 mm above each ring's end and start. The motion is built outside the timing (no
// inverse kinematics: the check reads the TCP poses in the part frame).
//
// Benchmarks (one timed call each, wall clock):
//   collision/check/<path points>   checkMotionCollisions on the whole motion
// Counter: points_per_s (path points per second), collisions (must be 0: nothing collides).
// Run: collision_bench --benchmark_filter='collision/' (1 M points needs about 600 MB).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstddef>

#include "curvedslicer/robot/collision.hpp"

namespace {

using namespace curvedslicer;
using Clock = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;

MotionPoint benchPoint(MoveKind kind, const Vec3& position, int layer, int path, int index) {
  MotionPoint m;
  m.kind = kind;
  m.layer = layer;
  m.path = path;
  m.index = index;
  m.position = position;
  m.toolInPart = Pose::Identity();
  m.toolInPart.linear() = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();  // tool z down
  m.toolInPart.translation() = position;
  return m;
}

/// Stacked rings with at least `target` path points.
MotionPlan makeRings(std::size_t target) {
  MotionPlan motion;
  motion.points.reserve(target + target / 50);
  std::size_t pathPoints = 0;
  for (int layer = 0; pathPoints < target; ++layer) {
    const double z = 1.5 * (layer + 1);
    int path = 0;
    for (double radius = 20.0; radius <= 100.0 + 1e-9; radius += 3.7, ++path) {
      const int n = static_cast<int>(std::ceil(2.0 * kPi * radius / 2.0));
      auto at = [&](int k) {
        const double t = 2.0 * kPi * k / n;
        return Vec3(radius * std::cos(t), radius * std::sin(t), z);
      };
      motion.points.push_back(
          benchPoint(MoveKind::Approach, at(0) + Vec3(0, 0, 12), layer, path, -1));
      MotionPathSpan span{layer, path, motion.points.size(), 0, {}};
      for (int k = 0; k <= n; ++k) {  // closed: point 0 again at the end
        MotionPoint m = benchPoint(MoveKind::Path, at(k % n), layer, path, k);
        m.pathStart = k == 0;
        m.pathEnd = k == n;
        m.arcOn = k > 0;
        motion.points.push_back(m);
      }
      span.end = motion.points.size();
      motion.paths.push_back(span);
      pathPoints += static_cast<std::size_t>(n + 1);
      motion.points.push_back(
          benchPoint(MoveKind::Retract, at(0) + Vec3(0, 0, 12), layer, path, -1));
    }
  }
  return motion;
}

void collisionCheck(benchmark::State& state) {
  MotionPlan motion = makeRings(static_cast<std::size_t>(state.range(0)));
  std::size_t pathPoints = 0;
  for (const MotionPathSpan& span : motion.paths) pathPoints += span.end - span.begin;
  Cell cell = defaultCell();
  PlanParameters parameters;
  parameters.beadSpacing = 3.7;
  const double beadRadius = depositBeadRadius(parameters);
  MotionOptions options;
  options.allowCollisions = true;
  for (auto _ : state) {
    const auto begin = Clock::now();
    checkMotionCollisions(motion, cell, collisionGeometryOf(cell), beadRadius, options);
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - begin).count());
  }
  state.counters["points_per_s"] =
      benchmark::Counter(static_cast<double>(pathPoints) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
  state.counters["path_points"] = static_cast<double>(pathPoints);
  state.counters["collisions"] = static_cast<double>(motion.collisions.size());
}

BENCHMARK(collisionCheck)
    ->Name("collision/check")
    ->Arg(100000)
    ->Arg(1000000)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(false);

}  // namespace

BENCHMARK_MAIN();
