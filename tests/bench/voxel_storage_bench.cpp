// Voxel storage: the paper's Table 1 (§2.1) reproduced — time of one 26-neighbourhood search in a
// set of about 1 M voxels, for three storage structures:
//   map    std::map (a red-black tree) keyed by the paper's eq. 1 integer (GridGeometry::paperKey);
//          a neighbour's key is the voxel's key plus a fixed key offset (the paper's use of eq. 1),
//          26 finds per search; `map_rows` (not in the paper) uses that keys k−1, k, k+1 are
//          consecutive: 9 lower_bound calls, each followed by an in-order walk of up to 3 nodes;
//   kd     a nanoflann kd-tree over the voxel centres (cell units, float), found either by a
//          radius search just over √3·L (`kd_radius`) or by the 27 nearest points (`kd_knn27`);
//   dense  our storage: a byte mask plus a value array over the whole box, neighbour = index plus
//          one of 26 fixed offsets (GridGeometry::index).
// Each search starts from a voxel's integer cell (i, j, k), visits its 26 neighbours, and adds up
// the integer values stored at the neighbours that are voxels of the set (so every structure does
// the same work and the sums can be compared exactly). One benchmark iteration is 100 k searches
// of voxels drawn uniformly from the set with a fixed seed — the same sequence for every structure.
//
// Voxel sets (both with one empty cell of padding around them):
//   block  a dense 100³ block: exactly 1,000,000 voxels, almost all with 26 neighbours;
//   ball   the cells whose centres lie within 62.035 L of the grid centre: 1,000,000 ± 0.1 %
//          voxels, a solid with a curved boundary (about 3 % of the searches miss some neighbours).
// Before timing, every structure's checksum over the 100 k searches is compared with the dense
// array's; a mismatch aborts the run. Counters: `per_search` (time of one search),
// `bytes_per_voxel` (heap bytes the structure allocated, from mallinfo2, divided by the voxel
// count).
//
// Run: see tests/bench/README.md (--benchmark_enable_random_interleaving, repetitions, ratios).
#include <benchmark/benchmark.h>
#include <malloc.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <nanoflann.hpp>
#include <random>
#include <string>
#include <vector>

#include "curvedslicer/voxel/voxel_grid.hpp"

namespace {

using curvedslicer::GridGeometry;
using curvedslicer::Vec3i;

constexpr int kSearches = 100'000;
constexpr std::uint64_t kSeed = 20240521;

/// Heap bytes in use (glibc), for the memory counter.
std::size_t heapInUse() {
  return mallinfo2().uordblks + mallinfo2().hblkhd;
}

/// A voxel set: its cells, the grid around it, one integer value per voxel, and the search order.
struct VoxelSet {
  GridGeometry geometry;
  std::vector<Vec3i> cells;            ///< the voxels, in index order
  std::vector<std::uint32_t> values;   ///< value of cells[v]
  std::vector<std::uint32_t> queries;  ///< kSearches indices into `cells`
};

std::uint32_t valueOf(const Vec3i& c) {
  // Any deterministic per-voxel integer works; mix the coordinates so sums catch wrong lookups.
  return static_cast<std::uint32_t>(c.x() * 73856093u ^ c.y() * 19349663u ^ c.z() * 83492791u) &
         0xffffu;
}

VoxelSet makeVoxelSet(const std::string& shape) {
  VoxelSet s;
  GridGeometry& g = s.geometry;
  g.voxelSize = 1.0;
  if (shape == "block") {
    g.dims = Vec3i(102, 102, 102);
    for (int i = 1; i <= 100; ++i)
      for (int j = 1; j <= 100; ++j)
        for (int k = 1; k <= 100; ++k) s.cells.emplace_back(i, j, k);
  } else {
    // Radius chosen so that the ball holds about 1 M cell centres (4/3·π·R³ = 10⁶).
    const double R = 62.035;
    const int n = 2 * static_cast<int>(std::ceil(R)) + 2;
    g.dims = Vec3i(n, n, n);
    const double c = 0.5 * n;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          const double x = i + 0.5 - c, y = j + 0.5 - c, z = k + 0.5 - c;
          if (x * x + y * y + z * z <= R * R) s.cells.emplace_back(i, j, k);
        }
  }
  s.values.reserve(s.cells.size());
  for (const Vec3i& c : s.cells) s.values.push_back(valueOf(c));
  std::mt19937_64 rng(kSeed);
  std::uniform_int_distribution<std::uint32_t> pick(0,
                                                    static_cast<std::uint32_t>(s.cells.size() - 1));
  s.queries.resize(kSearches);
  for (auto& q : s.queries) q = pick(rng);
  return s;
}

const VoxelSet& voxelSet(const std::string& shape) {
  static std::map<std::string, std::unique_ptr<VoxelSet>> sets;
  auto& slot = sets[shape];
  if (!slot) slot = std::make_unique<VoxelSet>(makeVoxelSet(shape));
  return *slot;
}

/// Result of a run of searches: neighbours found and the sum of their values.
struct Checksum {
  std::uint64_t found = 0;
  std::uint64_t sum = 0;
  bool operator==(const Checksum&) const = default;
};

// ---- (a) std::map keyed by eq. 1 ----------------------------------------------------------------

struct MapStorage {
  const GridGeometry* g;
  std::map<std::uint64_t, std::uint32_t> voxels;
  std::array<std::int64_t, 26> keyOffsets{};

  explicit MapStorage(const VoxelSet& s) : g(&s.geometry) {
    for (std::size_t v = 0; v < s.cells.size(); ++v) {
      const Vec3i& c = s.cells[v];
      voxels.emplace(g->paperKey(c.x(), c.y(), c.z()), s.values[v]);
    }
    // Eq. 1 is linear in (i, j, k), so a neighbour's key is the key plus a constant (no wrap:
    // the padding keeps every neighbour index within [0, M)).
    const auto& offsets = curvedslicer::neighbourOffsets26();
    const auto origin = static_cast<std::int64_t>(g->paperKey(1, 1, 1));
    for (int o = 0; o < 26; ++o) {
      const Vec3i d = offsets[o];
      keyOffsets[o] =
          static_cast<std::int64_t>(g->paperKey(1 + d.x(), 1 + d.y(), 1 + d.z())) - origin;
    }
  }
  void search(const Vec3i& c, Checksum& out) const {
    const auto key = static_cast<std::int64_t>(g->paperKey(c.x(), c.y(), c.z()));
    for (std::int64_t off : keyOffsets) {
      const auto it = voxels.find(static_cast<std::uint64_t>(key + off));
      if (it != voxels.end()) {
        ++out.found;
        out.sum += it->second;
      }
    }
  }
  /// Variant not in the paper: keys k−1, k, k+1 are consecutive integers, so each of the 9 rows
  /// of the neighbourhood takes one lower_bound and then walks the tree in order.
  void searchRows(const Vec3i& c, Checksum& out) const {
    const auto key = static_cast<std::int64_t>(g->paperKey(c.x(), c.y(), c.z()));
    const auto M = static_cast<std::int64_t>(g->dims.maxCoeff()) + 1;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        const std::int64_t rowKey = key + dx * M * M + dy * M;
        const auto last = static_cast<std::uint64_t>(rowKey + 1);
        for (auto it = voxels.lower_bound(static_cast<std::uint64_t>(rowKey - 1));
             it != voxels.end() && it->first <= last; ++it) {
          if (dx == 0 && dy == 0 && it->first == static_cast<std::uint64_t>(rowKey)) continue;
          ++out.found;
          out.sum += it->second;
        }
      }
  }
};

// ---- (b) kd-tree over voxel centres
// ---------------------------------------------------------------

struct CentreCloud {
  std::vector<std::array<float, 3>> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  float kdtree_get_pt(std::size_t idx, std::size_t dim) const { return points[idx][dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CentreCloud>,
                                                   CentreCloud, 3, std::uint32_t>;

/// Collects the points within the radius (reused between searches, no sorting). The result-set
/// interface of nanoflann's findNeighbors (1.5+ also needs the two types and sort()).
class NeighbourCollector {
 public:
  using DistanceType = float;
  using IndexType = std::uint32_t;
  explicit NeighbourCollector(float radiusSquared) : radiusSquared_(radiusSquared) {
    found_.reserve(32);
  }
  void init() { found_.clear(); }
  std::size_t size() const { return found_.size(); }
  bool full() const { return true; }
  float worstDist() const { return radiusSquared_; }
  bool addPoint(float dist, std::uint32_t index) {
    if (dist < radiusSquared_) found_.push_back(index);
    return true;
  }
  void sort() {}  // the caller needs no order
  const std::vector<std::uint32_t>& found() const { return found_; }

 private:
  float radiusSquared_;
  std::vector<std::uint32_t> found_;
};

/// Search parameters without sorting: nanoflann 1.5 replaced SearchParams(checks, eps, sorted)
/// by SearchParameters(eps, sorted). NANOFLANN_VERSION is 0x142 for 1.4.2, 0x150 for 1.5.0 and
/// 0x010C01 for 1.12.1 (the later encoding compares larger too).
inline auto unsortedSearch() {
#if NANOFLANN_VERSION >= 0x150
  return nanoflann::SearchParameters(0.0f, false);
#else
  return nanoflann::SearchParams(32, 0.0f, false);
#endif
}

struct KdStorage {
  CentreCloud cloud;
  std::vector<std::uint32_t> values;
  std::unique_ptr<KdTree> tree;
  // Neighbours lie at squared distances 1, 2, 3 (cell units); the next shell is at 4.
  static constexpr float kRadiusSquared = 3.0f * 1.01f * 1.01f;

  explicit KdStorage(const VoxelSet& s) : values(s.values) {
    cloud.points.reserve(s.cells.size());
    for (const Vec3i& c : s.cells)
      cloud.points.push_back({c.x() + 0.5f, c.y() + 0.5f, c.z() + 0.5f});
    tree = std::make_unique<KdTree>(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree->buildIndex();
  }
  static std::array<float, 3> centre(const Vec3i& c) {
    return {c.x() + 0.5f, c.y() + 0.5f, c.z() + 0.5f};
  }
  void searchRadius(const Vec3i& c, NeighbourCollector& collector, Checksum& out) const {
    const auto q = centre(c);
    collector.init();
    tree->findNeighbors(collector, q.data(), unsortedSearch());
    for (std::uint32_t idx : collector.found()) {
      if (cloud.points[idx] == q) continue;  // the voxel itself
      ++out.found;
      out.sum += values[idx];
    }
  }
  void searchKnn(const Vec3i& c, Checksum& out) const {
    const auto q = centre(c);
    std::array<std::uint32_t, 27> idx;
    std::array<float, 27> d2;
    const std::size_t n = tree->knnSearch(q.data(), 27, idx.data(), d2.data());
    for (std::size_t m = 0; m < n; ++m) {
      // Skip the voxel itself (0) and, near the boundary, points beyond the neighbourhood.
      if (d2[m] == 0.0f || d2[m] > kRadiusSquared) continue;
      ++out.found;
      out.sum += values[idx[m]];
    }
  }
};

// ---- (c) dense array
// -------------------------------------------------------------------------------

struct DenseStorage {
  const GridGeometry* g;
  std::vector<std::uint8_t> inside;
  std::vector<std::uint32_t> values;
  std::array<std::ptrdiff_t, 26> offsets{};

  explicit DenseStorage(const VoxelSet& s)
      : g(&s.geometry), inside(s.geometry.cellCount(), 0), values(s.geometry.cellCount(), 0) {
    for (std::size_t v = 0; v < s.cells.size(); ++v) {
      const std::size_t n = g->index(s.cells[v]);
      inside[n] = 1;
      values[n] = s.values[v];
    }
    const auto& o = curvedslicer::neighbourOffsets26();
    for (int m = 0; m < 26; ++m) {
      offsets[m] =
          static_cast<std::ptrdiff_t>(o[m].x()) * static_cast<std::ptrdiff_t>(g->strideX()) +
          static_cast<std::ptrdiff_t>(o[m].y()) * static_cast<std::ptrdiff_t>(g->strideY()) +
          o[m].z();
    }
  }
  void search(const Vec3i& c, Checksum& out) const {
    const auto n = static_cast<std::ptrdiff_t>(g->index(c));
    for (std::ptrdiff_t off : offsets) {
      const auto m = static_cast<std::size_t>(n + off);
      if (inside[m]) {
        ++out.found;
        out.sum += values[m];
      }
    }
  }
};

// ---- runs ---------------------------------------------------------------------------------------

enum class Method { Map, MapRows, KdRadius, KdKnn27, Dense };

struct Built {
  std::unique_ptr<MapStorage> map;
  std::unique_ptr<KdStorage> kd;
  std::unique_ptr<DenseStorage> dense;
  std::size_t bytes = 0;
};

Checksum runSearches(const VoxelSet& s, Method method, const Built& b) {
  Checksum sum;
  NeighbourCollector collector(KdStorage::kRadiusSquared);
  for (std::uint32_t q : s.queries) {
    const Vec3i& c = s.cells[q];
    switch (method) {
      case Method::Map:
        b.map->search(c, sum);
        break;
      case Method::MapRows:
        b.map->searchRows(c, sum);
        break;
      case Method::KdRadius:
        b.kd->searchRadius(c, collector, sum);
        break;
      case Method::KdKnn27:
        b.kd->searchKnn(c, sum);
        break;
      case Method::Dense:
        b.dense->search(c, sum);
        break;
    }
  }
  return sum;
}

Built build(const VoxelSet& s, Method method) {
  Built b;
  const std::size_t before = heapInUse();
  switch (method) {
    case Method::Map:
    case Method::MapRows:
      b.map = std::make_unique<MapStorage>(s);
      break;
    case Method::KdRadius:
    case Method::KdKnn27:
      b.kd = std::make_unique<KdStorage>(s);
      break;
    case Method::Dense:
      b.dense = std::make_unique<DenseStorage>(s);
      break;
  }
  b.bytes = heapInUse() - before;
  return b;
}

/// The dense array's checksum of a set, the reference the other structures must reproduce.
Checksum referenceChecksum(const VoxelSet& s) {
  static std::map<const VoxelSet*, Checksum> cache;
  auto it = cache.find(&s);
  if (it == cache.end())
    it = cache.emplace(&s, runSearches(s, Method::Dense, build(s, Method::Dense))).first;
  return it->second;
}

/// Structures are built once per (set, method) and kept, so repetitions time only the searches.
const Built& built(const std::string& shape, Method method) {
  static std::map<std::pair<std::string, Method>, std::unique_ptr<Built>> cache;
  auto& slot = cache[{shape, method}];
  if (!slot) slot = std::make_unique<Built>(build(voxelSet(shape), method));
  return *slot;
}

void benchmarkSearch(benchmark::State& state, const std::string& shape, Method method) {
  const VoxelSet& s = voxelSet(shape);
  const Built& b = built(shape, method);
  const Checksum expected = referenceChecksum(s);
  const Checksum got = runSearches(s, method, b);
  if (!(got == expected)) {
    std::fprintf(
        stderr, "checksum mismatch (%s): found %llu sum %llu, dense array found %llu sum %llu\n",
        shape.c_str(), static_cast<unsigned long long>(got.found),
        static_cast<unsigned long long>(got.sum), static_cast<unsigned long long>(expected.found),
        static_cast<unsigned long long>(expected.sum));
    std::abort();
  }
  for (auto _ : state) {
    Checksum sum = runSearches(s, method, b);
    benchmark::DoNotOptimize(sum);
  }
  state.counters["per_search"] = benchmark::Counter(
      kSearches, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["voxels"] = static_cast<double>(s.cells.size());
  state.counters["neighbours_found"] = static_cast<double>(expected.found) / kSearches;
  state.counters["bytes_per_voxel"] =
      static_cast<double>(b.bytes) / static_cast<double>(s.cells.size());
}

void registerAll() {
  const std::pair<const char*, Method> methods[] = {{"map", Method::Map},
                                                    {"map_rows", Method::MapRows},
                                                    {"kd_radius", Method::KdRadius},
                                                    {"kd_knn27", Method::KdKnn27},
                                                    {"dense", Method::Dense}};
  for (const char* shape : {"block", "ball"}) {
    for (const auto& [name, method] : methods) {
      benchmark::RegisterBenchmark(
          (std::string("neighbour_search/") + shape + "/" + name).c_str(),
          [shape = std::string(shape), method = method](benchmark::State& st) {
            benchmarkSearch(st, shape, method);
          })
          ->Unit(benchmark::kMillisecond)
          ->MinTime(1.0);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  registerAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
