// Surface geodesic distance (GDTC) on real layer meshes: our fast marching (accurate) and the
// paper's eq. 15 Dijkstra against CGAL's Heat_method_3 (intrinsic Delaunay) and, on a subset,
// CGAL's exact Surface_mesh_shortest_path (Xin–Wang window propagation). Not a test.
//
// Usage: paths_geodesic_bench LAYER_DIR [EXACT_MAX_FACES=50000] [LAYER ...]
//   LAYER_DIR holds layer_NNNN.obj files from `curvedslicer layers ... --format obj -o LAYER_DIR`.
//   Each listed layer (default: 1 20 50 80 110 140) is welded into a CGAL Surface_mesh (faces that
//   would make it non-manifold are dropped and counted; every method then runs on the same mesh)
//   and measured from all its boundary vertices as sources (CGAL's exact solver takes point sources
//   only, so all methods use the same vertex set). Errors are against the exact solver where it
//   ran (layers with at most EXACT_MAX_FACES faces), in mm, over the vertices it reached.
//   Times are wall and process CPU seconds (the machine is shared: compare the CPU columns and the
//   ratios of the same run). For our method the row also gives where its largest error sits: the
//   exact distance there and the smallest corner angle of the triangles around that vertex.
// Results are recorded in tests/bench/README.md ("Paths") and tests/bench/PLAN-BUNNY.md.
#ifndef CGAL_EIGEN3_ENABLED
#define CGAL_EIGEN3_ENABLED  // Heat_method_3 solves with Eigen
#endif
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Heat_method_3/Surface_mesh_geodesic_distances_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_shortest_path.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/paths/surface_geodesic.hpp"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// CPU seconds of the whole process (all threads) so far.
double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Wall and CPU time of one call.
struct Timing {
  double wall = 0.0, cpu = 0.0;
};

template <typename F>
Timing timeCall(F&& f) {
  const auto t0 = Clock::now();
  const double c0 = processCpuSeconds();
  f();
  return {secondsSince(t0), processCpuSeconds() - c0};
}

struct ErrorStats {
  double mean = 0.0, max = 0.0;
  std::size_t count = 0;
  std::size_t argMax = 0;  ///< vertex of the largest error
};

ErrorStats compare(const std::vector<double>& a, const std::vector<double>& exact) {
  ErrorStats s;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(exact[i]) || !std::isfinite(a[i])) continue;
    const double e = std::abs(a[i] - exact[i]);
    s.mean += e;
    if (e > s.max) {
      s.max = e;
      s.argMax = i;
    }
    ++s.count;
  }
  if (s.count) s.mean /= static_cast<double>(s.count);
  return s;
}

/// Smallest corner angle (degrees) of the triangles around vertex `v`.
double smallestCornerAngle(const curvedslicer::TriMesh& mesh, std::size_t v) {
  double best = 180.0;
  for (const curvedslicer::Vec3i& t : mesh.triangles) {
    if (static_cast<std::size_t>(t[0]) != v && static_cast<std::size_t>(t[1]) != v &&
        static_cast<std::size_t>(t[2]) != v)
      continue;
    for (int k = 0; k < 3; ++k) {
      const curvedslicer::Vec3 a = mesh.vertices[t[(k + 1) % 3]] - mesh.vertices[t[k]];
      const curvedslicer::Vec3 b = mesh.vertices[t[(k + 2) % 3]] - mesh.vertices[t[k]];
      const double n = a.norm() * b.norm();
      if (n > 0.0)
        best = std::min(best, std::acos(std::clamp(a.dot(b) / n, -1.0, 1.0)) * 180.0 / M_PI);
    }
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace curvedslicer;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s LAYER_DIR [EXACT_MAX_FACES] [LAYER ...]\n", argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  const std::size_t exactMaxFaces = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 50000;
  std::vector<int> layers;
  for (int i = 3; i < argc; ++i) layers.push_back(std::atoi(argv[i]));
  if (layers.empty()) layers = {1, 20, 50, 80, 110, 140};

  std::printf(
      "%-6s %8s %7s %7s | %-13s %-13s %-13s %-13s %-13s | %9s %9s | %-15s %-15s %-15s %-15s | "
      "%s\n",
      "layer", "faces", "dropped", "sources", "ours wall/CPU", "1st wall/CPU", "paper wall/CPU",
      "heat wall/CPU", "exact wall/CPU", "heat/ours", "exact/ours", "ours mean/max", "1st mean/max",
      "paper mean/max", "heat mean/max", "ours max at: exact d, min angle");
  for (const int layer : layers) {
    char name[64];
    std::snprintf(name, sizeof name, "layer_%04d.obj", layer);
    const TriMesh raw = readMesh(dir / name);
    // Weld into a Surface_mesh; faces that would break manifoldness are dropped.
    SurfaceMesh sm;
    std::vector<VertexIndex> vmap;
    vmap.reserve(raw.vertexCount());
    for (const Vec3& v : raw.vertices)
      vmap.push_back(sm.add_vertex(Kernel::Point_3(v.x(), v.y(), v.z())));
    std::size_t dropped = 0;
    for (const Vec3i& t : raw.triangles) {
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] ||
          sm.add_face(vmap[t[0]], vmap[t[1]], vmap[t[2]]) == SurfaceMesh::null_face()) {
        ++dropped;
      }
    }
    // The same mesh for our solver (isolated vertices stay, unreached).
    TriMesh mesh;
    mesh.vertices = raw.vertices;
    for (const auto f : sm.faces()) {
      Vec3i tri;
      int k = 0;
      for (const auto v : CGAL::vertices_around_face(sm.halfedge(f), sm))
        tri[k++] = static_cast<int>(v.idx());
      mesh.triangles.push_back(tri);
    }
    std::vector<std::int32_t> sources;
    for (const auto v : sm.vertices()) {
      if (!sm.is_isolated(v) && sm.is_border(v, false))
        sources.push_back(static_cast<std::int32_t>(v.idx()));
    }
    if (sources.empty()) {
      std::printf("%-6d no boundary vertex, skipped\n", layer);
      continue;
    }

    SurfaceGeodesicResult ours, firstOrder, paper;
    const Timing oursTime =
        timeCall([&] { ours = computeSurfaceGeodesicFromVertices(mesh, sources); });
    SurfaceGeodesicOptions firstOrderOptions;
    firstOrderOptions.secondOrder = false;
    const Timing firstOrderTime = timeCall([&] {
      firstOrder = computeSurfaceGeodesicFromVertices(mesh, sources, {}, firstOrderOptions);
    });
    SurfaceGeodesicOptions paperOptions;
    paperOptions.method = SurfaceGeodesicMethod::Paper;
    const Timing paperTime = timeCall(
        [&] { paper = computeSurfaceGeodesicFromVertices(mesh, sources, {}, paperOptions); });

    auto heatMap = sm.add_property_map<VertexIndex, double>("v:heat", 0.0).first;
    const Timing heatTime = timeCall([&] {
      CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<
          SurfaceMesh, CGAL::Heat_method_3::Intrinsic_Delaunay>
          heat(sm);
      for (const std::int32_t s : sources) heat.add_source(VertexIndex(s));
      heat.estimate_geodesic_distances(heatMap);
    });
    std::vector<double> heatValues(mesh.vertexCount(), kInf);
    for (const auto v : sm.vertices()) {
      if (!sm.is_isolated(v)) heatValues[v.idx()] = heatMap[v];
    }

    Timing exactTime{std::nan(""), std::nan("")};
    std::vector<double> exact;
    if (sm.number_of_faces() <= exactMaxFaces) {
      using Traits = CGAL::Surface_mesh_shortest_path_traits<Kernel, SurfaceMesh>;
      exactTime = timeCall([&] {
        CGAL::Surface_mesh_shortest_path<Traits> shortest(sm);
        for (const std::int32_t s : sources) shortest.add_source_point(VertexIndex(s));
        shortest.build_sequence_tree();
        exact.assign(mesh.vertexCount(), kInf);
        for (const auto v : sm.vertices()) {
          if (sm.is_isolated(v)) continue;
          const double d = shortest.shortest_distance_to_source_points(v).first;
          if (d >= 0.0) exact[v.idx()] = d;
        }
      });
    }
    char oursErr[32] = "-", paperErr[32] = "-", heatErr[32] = "-", firstErr[32] = "-";
    char where[64] = "-";
    if (!exact.empty()) {
      const ErrorStats a = compare(ours.distance, exact), b = compare(paper.distance, exact),
                       c = compare(heatValues, exact);
      std::snprintf(oursErr, sizeof oursErr, "%.4f/%.3f", a.mean, a.max);
      std::snprintf(paperErr, sizeof paperErr, "%.4f/%.3f", b.mean, b.max);
      std::snprintf(heatErr, sizeof heatErr, "%.4f/%.3f", c.mean, c.max);
      const ErrorStats f = compare(firstOrder.distance, exact);
      std::snprintf(firstErr, sizeof firstErr, "%.4f/%.3f", f.mean, f.max);
      if (a.count) {
        std::snprintf(where, sizeof where, "%.2f mm, %.1f deg", exact[a.argMax],
                      smallestCornerAngle(mesh, a.argMax));
      }
    }
    const auto pair = [](const Timing& t) {
      char text[32];
      std::snprintf(text, sizeof text, "%.3f/%.3f", t.wall, t.cpu);
      return std::string(text);
    };
    std::printf(
        "%-6d %8zu %7zu %7zu | %-13s %-13s %-13s %-13s %-13s | %9.1f %9.1f | %-15s %-15s %-15s "
        "%-15s | %s\n",
        layer, static_cast<std::size_t>(sm.number_of_faces()), dropped, sources.size(),
        pair(oursTime).c_str(), pair(firstOrderTime).c_str(), pair(paperTime).c_str(),
        pair(heatTime).c_str(), pair(exactTime).c_str(), heatTime.cpu / oursTime.cpu,
        exactTime.cpu / oursTime.cpu, oursErr, firstErr, paperErr, heatErr, where);
    std::fflush(stdout);
  }
  return 0;
}
