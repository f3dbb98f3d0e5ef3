// Deposition-plan benchmark: all paths of bunny_closed_low_res.stl at L = 0.5 mm,
// h = 1.5 mm, s = 3.7 mm — time per planner stage (initial curves, surface geodesic, iso-lines,
// fit, order, deposition) after the layer job. One iteration (the job takes minutes); the layer
// job itself is timed as a counter too.
//
// Wall time per stage is the planner's own (PlanStats::stageTimes, steady clock). CPU time per
// stage is measured through the progress callback: the process CPU clock is read at every
// progress report, and the CPU used between two reports goes to the group of the earlier report
// (the planner is single-threaded, so the reports are the only stage boundaries it shows):
//   "curves+geodesic" (initial curves, boundary vertices, surface geodesic — small layers report
//   no geodesic progress, so the two cannot be told apart), "iso+fit" (iso-lines and the fit
//   alternate per iso-value), "order", "deposition", and "between layers" (the planner's untimed
//   per-layer set-up: the layer's triangle BVH and vertex normals). A stage's CPU estimate is its
//   wall time times its group's CPU/wall. The printed table gives both.
//
// Environment (all optional):
//   CURVEDSLICER_BENCH_VOXEL (mm, default 0.5), CURVEDSLICER_BENCH_LAYER (mm, 1.5),
//   CURVEDSLICER_BENCH_SPACING (mm, 3.7), CURVEDSLICER_BENCH_SURFACE_METHOD (accurate | paper),
//   CURVEDSLICER_BENCH_FIT_TOLERANCE (mm, the planner's default 0.05),
//   CURVEDSLICER_BENCH_WRITE_LAYERS=DIR writes some layer surfaces as DIR/layer_NNNN.obj (the
//   names and format of `curvedslicer layers --format obj`) for paths_geodesic_bench, outside
//   the timed call; CURVEDSLICER_BENCH_WRITE_INDICES="1,20,50" picks the layers (1-based; default
//   1, 11, 21, ...).
//
// Fit diagnostic (registered only when CURVEDSLICER_BENCH_FIT_LAYERS=DIR is set; run it alone with
// --benchmark_filter=FitLayers): for every DIR/layer_*.obj, the planner's steps up to the fit done
// by hand with the public functions (boundary vertices, accurate surface geodesic, iso-values
// (k + ½)·s, iso-lines, fitPath with the planner's defaults on every line the planner would fit),
// each fitPath call timed on the thread CPU clock; prints the CPU time by fit rounds with the
// lines' sharpest turn (corners), the slowest lines, and the raw iso-line spacing (where the fit's
// time goes).
// Results and commands: tests/bench/README.md, section "Plan" (and tests/bench/PLAN-BUNNY.md).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <benchmark/benchmark.h>

#include "common/test_paths.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/paths/iso_lines.hpp"
#include "curvedslicer/paths/path_fit.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/paths/polyline.hpp"
#include "curvedslicer/paths/surface_curves.hpp"
#include "curvedslicer/paths/surface_geodesic.hpp"
#include "curvedslicer/pipeline/layer_output.hpp"
#include "curvedslicer/pipeline/layer_pipeline.hpp"

namespace {

using namespace curvedslicer;
using Clock = std::chrono::steady_clock;

double envNumber(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::stod(v) : fallback;
}

/// CPU seconds of the whole process (all threads) so far.
double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// The CPU group a progress report opens (see the file comment).
std::string groupOf(std::string_view stage, std::string_view previous) {
  if (stage == "iso-lines") return "iso+fit";
  if (stage == "order") return "order";
  if (stage == "deposition") {
    // The planner reports "deposition" when the stage starts and again when the layer ends; what
    // follows the second report is the next layer's untimed set-up.
    return previous == "deposition" ? "between layers" : "deposition";
  }
  return "curves+geodesic";  // "initial curves", "propagating surface distance", insertion
}

/// Wall and CPU seconds per group, accumulated from progress reports.
class CpuByGroup {
 public:
  void start() {
    group_ = "between layers";
    lastStage_.clear();
    wall_ = Clock::now();
    cpu_ = processCpuSeconds();
  }
  void onReport(std::string_view stage) {
    close();
    group_ = groupOf(stage, lastStage_);
    lastStage_.assign(stage);
  }
  void finish() { close(); }
  const std::map<std::string, std::pair<double, double>>& totals() const { return totals_; }
  /// CPU/wall of a group (1 where it used no wall time).
  double share(const std::string& group) const {
    const auto it = totals_.find(group);
    if (it == totals_.end() || it->second.first <= 0.0) return 1.0;
    return it->second.second / it->second.first;
  }

 private:
  void close() {
    const auto now = Clock::now();
    const double cpu = processCpuSeconds();
    auto& t = totals_[group_];
    t.first += std::chrono::duration<double>(now - wall_).count();
    t.second += cpu - cpu_;
    wall_ = now;
    cpu_ = cpu;
  }
  std::string group_;
  std::string lastStage_;
  Clock::time_point wall_;
  double cpu_ = 0.0;
  std::map<std::string, std::pair<double, double>> totals_;  // group -> (wall s, CPU s)
};

std::string groupOfPlannerStage(const std::string& name) {
  if (name == "initial curves" || name == "surface geodesic") return "curves+geodesic";
  if (name == "iso-lines" || name == "fit") return "iso+fit";
  return name;  // "order", "deposition"
}

double peakMegabytes() {
  return static_cast<double>(peakResidentMemoryBytes()) / 1e6;
}

/// Layer indices from a comma-separated list such as "1,20,50".
std::vector<int> parseIndices(const char* text) {
  std::vector<int> indices;
  std::string item;
  for (const char* c = text;; ++c) {
    if (*c == ',' || *c == '\0') {
      if (!item.empty()) indices.push_back(std::stoi(item));
      item.clear();
      if (*c == '\0') break;
    } else {
      item += *c;
    }
  }
  return indices;
}

void writeSomeLayers(const LayersResult& layers) {
  const char* dir = std::getenv("CURVEDSLICER_BENCH_WRITE_LAYERS");
  if (!dir) return;
  const char* list = std::getenv("CURVEDSLICER_BENCH_WRITE_INDICES");
  std::vector<int> indices;
  if (list) {
    indices = parseIndices(list);
  } else {
    for (int i = 1; i <= static_cast<int>(layers.surfaces.size()); i += 10) indices.push_back(i);
  }
  std::filesystem::create_directories(dir);
  int written = 0;
  for (const LayerSurface& surface : layers.surfaces) {
    if (std::find(indices.begin(), indices.end(), surface.index) == indices.end() ||
        surface.mesh.empty())
      continue;
    const std::string name =
        layerFileName(surface.index, layers.surfaces.size(), LayerFileFormat::Obj);
    writeMesh(std::filesystem::path(dir) / name, surface.mesh, MeshFormat::Obj);
    ++written;
  }
  std::printf("wrote %d layer surfaces to %s\n", written, dir);
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
  const auto jobBegin = Clock::now();
  const double jobCpuBegin = processCpuSeconds();
  const LayerJobResult layers = runLayerJob(model, job);
  const double jobSeconds = secondsSince(jobBegin);
  const double jobCpuSeconds = processCpuSeconds() - jobCpuBegin;
  const double jobPeakMb = peakMegabytes();
  std::size_t triangles = 0, vertices = 0;
  for (const LayerSurface& surface : layers.layers.surfaces) {
    triangles += surface.mesh.triangleCount();
    vertices += surface.mesh.vertexCount();
  }
  std::printf("layer job: %.1f s wall, %.1f s CPU, peak %.1f MB\n", jobSeconds, jobCpuSeconds,
              jobPeakMb);
  writeSomeLayers(layers.layers);

  PlannerOptions options;
  options.beadSpacing = s;
  options.fitTolerance = envNumber("CURVEDSLICER_BENCH_FIT_TOLERANCE", options.fitTolerance);
  if (method && std::string(method) == "paper") {
    options.geodesic.method = SurfaceGeodesicMethod::Paper;
  }
  PlanResult result;
  CpuByGroup groups;
  double planSeconds = 0.0, planCpuSeconds = 0.0;
  for (auto _ : state) {
    groups = CpuByGroup();
    const Progress progress([&groups](double, std::string_view stage) {
      groups.onReport(stage);
      return true;
    });
    const auto begin = Clock::now();
    const double cpuBegin = processCpuSeconds();
    groups.start();
    result = planLayers(layers.layers.surfaces, layers.source, options, progress);
    groups.finish();
    planCpuSeconds = processCpuSeconds() - cpuBegin;
    planSeconds = secondsSince(begin);
    benchmark::DoNotOptimize(result.plan.layers.data());
  }
  const double planPeakMb = peakMegabytes();
  state.counters["layer_job_s"] = jobSeconds;
  state.counters["layer_job_cpu_s"] = jobCpuSeconds;
  state.counters["plan_cpu_s"] = planCpuSeconds;
  state.counters["peak_job_MB"] = jobPeakMb;
  state.counters["peak_MB"] = planPeakMb;
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
      "L = %g mm, h = %g mm, s = %g mm: %zu layers (%zu triangles, %zu vertices), %zu paths, %zu "
      "points, %.1f m arc-on, %.1f m travel, largest fit deviation %.4f mm, %zu layers without "
      "paths\n",
      L, h, s, layers.layers.surfaces.size(), triangles, vertices, result.plan.pathCount(),
      result.plan.pointCount(), result.stats.arcLength / 1000.0, result.stats.travel / 1000.0,
      result.stats.maxFitDeviation, result.stats.layersWithoutPaths);
  std::printf("%-22s %10s %10s %8s\n", "planner stage", "wall s", "CPU s (est)", "share");
  double stageWall = 0.0, stageCpu = 0.0;
  for (const PlanStageTime& t : result.stats.stageTimes) {
    const double cpu = t.seconds * groups.share(groupOfPlannerStage(t.name));
    stageWall += t.seconds;
    stageCpu += cpu;
    std::printf("%-22s %10.2f %10.2f %7.1f%%\n", t.name.c_str(), t.seconds, cpu,
                planSeconds > 0.0 ? 100.0 * t.seconds / planSeconds : 0.0);
  }
  std::printf("%-22s %10.2f %10.2f %7.1f%%\n", "untimed by planner", planSeconds - stageWall,
              (planSeconds - stageWall) * groups.share("between layers"),
              planSeconds > 0.0 ? 100.0 * (planSeconds - stageWall) / planSeconds : 0.0);
  std::printf("%-22s %10.2f %10.2f (measured CPU %.2f s, %.0f%% of one core)\n", "planLayers total",
              planSeconds, stageCpu + (planSeconds - stageWall) * groups.share("between layers"),
              planCpuSeconds, planSeconds > 0.0 ? 100.0 * planCpuSeconds / planSeconds : 0.0);
  std::printf("%-22s %10s %10s %8s\n", "progress group", "wall s", "CPU s", "CPU/wall");
  for (const auto& [name, t] : groups.totals()) {
    std::printf("%-22s %10.2f %10.2f %8.2f\n", name.c_str(), t.first, t.second,
                t.first > 0.0 ? t.second / t.first : 0.0);
  }
  std::printf("peak resident memory: %.1f MB after the layer job, %.1f MB after planLayers\n",
              jobPeakMb, planPeakMb);
  std::fflush(stdout);
}
BENCHMARK(BM_PlanBunny)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

/// CPU seconds of the calling thread so far.
double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// The largest angle (degrees) between the chord from arc length t − 0.5 mm to t and the chord from
/// t to t + 0.5 mm, over the raw points t of a line (open lines: where both chords fit): corners
/// show as large angles, point-to-point zigzag below 0.5 mm hardly at all.
double sharpestTurnDegrees(const Polyline& line) {
  constexpr double kHalf = 0.5;  // mm
  const std::vector<double> at = computeCumulativeLengths(line);
  const double total = at.back();
  double worst = 0.0;
  for (std::size_t i = 0; i < line.points.size(); ++i) {
    const double t = at[i];
    if (!line.closed && (t < kHalf || t > total - kHalf)) continue;
    const Vec3 a = line.points[i] - evaluatePolylineAt(line, t - kHalf);
    const Vec3 b = evaluatePolylineAt(line, t + kHalf) - line.points[i];
    const double n = a.norm() * b.norm();
    if (n > 0.0) worst = std::max(worst, std::acos(std::clamp(a.dot(b) / n, -1.0, 1.0)));
  }
  return worst * 180.0 / M_PI;
}

struct FitRecord {
  int layer = 0;
  std::size_t rawPoints = 0;
  double length = 0.0;           ///< mm
  double shortestSegment = 0.0;  ///< mm
  bool closed = false;
  double sharpestTurn = 0.0;  ///< degrees, between the chords 0.5 mm before and after a point
  int rounds = 0;
  double deviation = 0.0;  ///< mm
  std::size_t outPoints = 0;
  double cpu = 0.0;  ///< s
};

void BM_FitLayers(benchmark::State& state) {
  const std::filesystem::path dir = std::getenv("CURVEDSLICER_BENCH_FIT_LAYERS");
  const double s = envNumber("CURVEDSLICER_BENCH_SPACING", 3.7);
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (isLayerFileName(entry.path().filename().string())) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  const PlannerOptions defaults;
  PathFitOptions fit;
  fit.tolerance = envNumber("CURVEDSLICER_BENCH_FIT_TOLERANCE", defaults.fitTolerance);
  fit.pointSpacing = defaults.pointSpacing;
  std::vector<FitRecord> records;
  double geodesicCpu = 0.0, isoCpu = 0.0;
  for (auto _ : state) {
    records.clear();
    for (const std::filesystem::path& file : files) {
      const TriMesh mesh = readMesh(file);
      const int layer = std::stoi(file.stem().string().substr(6));
      double c0 = threadCpuSeconds();
      const SurfaceGeodesicResult field =
          computeSurfaceGeodesicFromVertices(mesh, findBoundary(mesh).vertices);
      geodesicCpu += threadCpuSeconds() - c0;
      double maxDistance = 0.0;
      for (const double d : field.distance) {
        if (std::isfinite(d)) maxDistance = std::max(maxDistance, d);
      }
      for (const double value : computeIsoValues(s, maxDistance, IsoValueStart::Boundary)) {
        c0 = threadCpuSeconds();
        const std::vector<Polyline> lines = extractIsoLines(field.mesh, field.distance, value);
        isoCpu += threadCpuSeconds() - c0;
        for (const Polyline& raw : lines) {
          if (raw.points.size() < (raw.closed ? 3u : 2u) || raw.length() < s) continue;
          FitRecord r;
          r.layer = layer;
          r.rawPoints = raw.points.size();
          r.length = raw.length();
          r.closed = raw.closed;
          r.shortestSegment = kInf;
          for (std::size_t i = 0; i < raw.segmentCount(); ++i) {
            r.shortestSegment =
                std::min(r.shortestSegment, (raw.segmentEnd(i) - raw.segmentStart(i)).norm());
          }
          r.sharpestTurn = sharpestTurnDegrees(raw);
          c0 = threadCpuSeconds();
          const PathFitResult fitted = fitPath(raw, fit);
          r.cpu = threadCpuSeconds() - c0;
          r.rounds = fitted.fitRounds;
          r.deviation = fitted.fitDeviation;
          r.outPoints = fitted.points.points.size();
          records.push_back(r);
        }
      }
    }
  }
  double fitCpu = 0.0;
  std::size_t rawPoints = 0, tinySegments = 0;
  std::map<int, std::pair<std::size_t, double>> byRounds;  // rounds -> (lines, CPU s)
  std::map<int, std::vector<double>> turnsByRounds;        // rounds -> sharpest turns
  for (const FitRecord& r : records) {
    fitCpu += r.cpu;
    rawPoints += r.rawPoints;
    auto& b = byRounds[r.rounds];
    ++b.first;
    b.second += r.cpu;
    turnsByRounds[r.rounds].push_back(r.sharpestTurn);
    if (r.shortestSegment < 1e-3) ++tinySegments;
  }
  double length = 0.0;
  for (const FitRecord& r : records) length += r.length;
  std::printf(
      "fit tolerance %g mm: %zu layer files, %zu fitted lines, %zu raw points (%.3f mm mean raw "
      "spacing), %.1f m; CPU: "
      "geodesic %.2f s, iso-lines %.2f s, fit %.2f s (%.2f ms per line, %.2f us per raw point); "
      "%zu lines have a raw segment shorter than 1 um\n",
      fit.tolerance, files.size(), records.size(), rawPoints, rawPoints ? length / rawPoints : 0.0,
      length / 1000.0, geodesicCpu, isoCpu, fitCpu,
      records.empty() ? 0.0 : 1e3 * fitCpu / records.size(),
      rawPoints ? 1e6 * fitCpu / rawPoints : 0.0, tinySegments);
  std::printf("%-8s %8s %10s %8s %s\n", "rounds", "lines", "CPU s", "share",
              "sharpest turn deg (min/median/max)");
  for (const auto& [rounds, b] : byRounds) {
    std::vector<double>& turns = turnsByRounds[rounds];
    std::sort(turns.begin(), turns.end());
    std::printf("%-8d %8zu %10.3f %7.1f%% %.0f/%.0f/%.0f\n", rounds, b.first, b.second,
                fitCpu > 0.0 ? 100.0 * b.second / fitCpu : 0.0, turns.front(),
                turns[turns.size() / 2], turns.back());
  }
  std::vector<FitRecord> slowest = records;
  std::sort(slowest.begin(), slowest.end(),
            [](const FitRecord& a, const FitRecord& b) { return a.cpu > b.cpu; });
  slowest.resize(std::min<std::size_t>(slowest.size(), 10));
  std::printf("slowest fits:\n%-6s %8s %9s %7s %7s %9s %8s %11s %9s %9s\n", "layer", "raw pts",
              "length mm", "closed", "rounds", "dev mm", "out pts", "min seg mm", "turn deg",
              "CPU ms");
  for (const FitRecord& r : slowest) {
    std::printf("%-6d %8zu %9.1f %7s %7d %9.4f %8zu %11.2e %9.1f %9.2f\n", r.layer, r.rawPoints,
                r.length, r.closed ? "yes" : "no", r.rounds, r.deviation, r.outPoints,
                r.shortestSegment, r.sharpestTurn, 1e3 * r.cpu);
  }
  std::fflush(stdout);
  state.counters["fit_cpu_s"] = fitCpu;
  state.counters["lines"] = static_cast<double>(records.size());
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (std::getenv("CURVEDSLICER_BENCH_FIT_LAYERS")) {
    benchmark::RegisterBenchmark("FitLayers", BM_FitLayers)
        ->Iterations(1)
        ->Unit(benchmark::kSecond)
        ->UseRealTime();
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
