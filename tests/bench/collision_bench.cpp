// Collision check throughput (robot/collision.hpp): the torch envelope against the deposit so far
// and the positioner table, for every weld move and every arc-off move, on a synthetic motion of
// stacked concentric rings (rings 3.7 mm apart from 20 to 100 mm radius, 2 mm point spacing,
// layers 1.5 mm apart: about 4,150 points per layer), a vertical torch, retract and approach
// points 12 mm above each ring's end and start. The motion is built outside the timing (no
// inverse kinematics: the check reads the TCP poses in the part frame).
//
// Benchmarks (one timed call each, wall clock):
//   collision/check/<path points>   checkMotionCollisions on the whole motion
//   motion/avoidance/<path points>  planMotion of a plan of such rings beside a tube wall 60 mm
//                                   high (radius 8 mm, built first): the rings nearest the wall
//                                   need the torch tilted (torch angle) to clear it; the stage
//                                   times come from planMotion's progress reports
// Counters: points_per_s (path points per second), collisions (must be 0: nothing collides);
// avoidance: avoid_points_per_s / check_points_per_s (path points per second of the "torch
// angles" / "collisions" stage), avoid_share / check_share (of planMotion's time), tilted (path
// points with the torch tilted). Collisions are not allowed: one would stop the benchmark.
// Run: collision_bench --benchmark_filter='collision/|motion/' (1 M points needs about 600 MB
// for the check, a few GB for the whole motion plan).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstddef>
#include <map>
#include <string>

#include "curvedslicer/robot/collision.hpp"
#include "curvedslicer/robot/motion.hpp"

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
  // second argument 0: the torch alone (a version-2 cell without the arm's capsules and the
  // positioner's body), the peer of the whole-cell check (1)
  if (state.range(1) == 0) {
    cell.robot.links = ArmEnvelope{};
    cell.positioner.geometry.bodyRadius = 0.0;
  }
  PlanParameters parameters;
  parameters.beadSpacing = 3.7;
  const double beadRadius = depositBeadRadius(parameters);
  const MotionOptions options;  // nothing collides: a collision would stop the benchmark
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

/// A closed ring path of `radius` at height `z` (points about 2 mm apart), V down, normal up.
PlanPath benchRing(double radius, double z) {
  PlanPath path;
  const int n = static_cast<int>(std::ceil(2.0 * kPi * radius / 2.0));
  for (int k = 0; k <= n; ++k) {
    const double t = 2.0 * kPi * (k % n) / n;
    PathPoint p;
    p.position = Vec3(radius * std::cos(t), radius * std::sin(t), z);
    p.normal = Vec3::UnitZ();
    p.deposition = -Vec3::UnitZ();
    path.points.push_back(p);
  }
  path.length = 2.0 * kPi * radius;
  return path;
}

/// A tube wall (radius 8 mm, 40 layers of 1.5 mm) first, then layers of rings from 20 to 100 mm
/// radius beside it until the plan has at least `target` path points.
Plan makeRingsBesideAWall(std::size_t target) {
  Plan plan;
  plan.parameters.beadSpacing = 3.7;
  plan.parameters.layerThickness = 1.5;
  std::size_t points = 0;
  const auto addLayer = [&](std::vector<PlanPath> paths) {
    PlanLayer layer;
    layer.index = static_cast<int>(plan.layers.size());
    for (PlanPath& path : paths) {
      path.layer = layer.index;
      points += path.points.size();
      layer.paths.push_back(std::move(path));
    }
    plan.layers.push_back(std::move(layer));
  };
  for (int l = 0; l < 40; ++l) addLayer({benchRing(8.0, 1.5 * (l + 1))});
  for (int l = 0; points < target; ++l) {
    std::vector<PlanPath> rings;
    for (double radius = 20.0; radius <= 100.0 + 1e-9; radius += 3.7) {
      rings.push_back(benchRing(radius, 1.5 * (l + 1)));
    }
    addLayer(std::move(rings));
  }
  return plan;
}

void motionAvoidance(benchmark::State& state) {
  const Plan plan = makeRingsBesideAWall(static_cast<std::size_t>(state.range(0)));
  const Cell cell = defaultCell();
  MotionOptions options;
  options.unreachable = UnreachablePolicy::Warn;
  std::map<std::string, double> stageSeconds;
  MotionPlan motion;
  for (auto _ : state) {
    stageSeconds.clear();
    auto last = Clock::now();
    const Progress progress([&](double, std::string_view name) {
      const auto now = Clock::now();
      // the time since the last report went into the stage reported now
      stageSeconds[std::string(name)] += std::chrono::duration<double>(now - last).count();
      last = now;
      return true;
    });
    const auto begin = Clock::now();
    motion = planMotion(plan, cell, options, progress);
    state.SetIterationTime(std::chrono::duration<double>(Clock::now() - begin).count());
  }
  std::size_t pathPoints = 0, tilted = 0;
  for (const MotionPathSpan& span : motion.paths) pathPoints += span.end - span.begin;
  for (const MotionPoint& m : motion.points) tilted += (m.flags & kMotionTorchTilted) != 0;
  double total = 0.0;
  for (const auto& [name, seconds] : stageSeconds) total += seconds;
  const double avoid = stageSeconds["torch angles"], check = stageSeconds["collisions"];
  state.counters["path_points"] = static_cast<double>(pathPoints);
  state.counters["avoid_points_per_s"] =
      avoid > 0.0 ? static_cast<double>(pathPoints) / avoid : 0.0;
  state.counters["check_points_per_s"] =
      check > 0.0 ? static_cast<double>(pathPoints) / check : 0.0;
  state.counters["avoid_share"] = total > 0.0 ? avoid / total : 0.0;
  state.counters["check_share"] = total > 0.0 ? check / total : 0.0;
  state.counters["tilted"] = static_cast<double>(tilted);
  state.counters["collisions"] = static_cast<double>(motion.collisions.size());
  if (!motion.collisions.empty()) {
    const CollisionReport& c = motion.collisions.front();
    state.SetLabel(describeMove(motion, c.point) + ": " + c.what);
  }
}

BENCHMARK(motionAvoidance)
    ->Name("motion/avoidance")
    ->Arg(100000)
    ->Arg(1000000)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(1);

BENCHMARK(collisionCheck)
    ->Name("collision/check")
    ->Args({100000, 1})
    ->Args({1000000, 0})
    ->Args({1000000, 1})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(false);

}  // namespace

BENCHMARK_MAIN();
