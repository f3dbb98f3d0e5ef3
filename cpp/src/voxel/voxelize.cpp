// Voxelization by exact, watertight ray parity (paper §2.1, fig. 3). See voxelize.hpp.
//
// Phases (the progress stage names):
//   "plan grid"            frame, corner and dims, memory budget check. The grid lattice is
//                          anchored at the frame origin (cell faces at integer multiples of L in
//                          the grid frame), so dims = ceil(extent / L) + 2·padding, or one more
//                          where the box straddles the lattice unfavourably;
//   "voxelize"             one ray per (x, y) column along the grid z axis, parity fill;
//   "resolve odd columns"  voxels of columns with an odd crossing count, by x and y rays.
//
// Exactness. Vertex coordinates are expressed in cell units of the grid (cell centres at
// integer + 1/2) and snapped to a lattice of 2^-20 cells, stored as int64; ray coordinates are
// lattice points. The 2D orientation of a ray point relative to a triangle edge is evaluated in
// 128-bit integers with the edge taken in a canonical (lexicographic) direction, so the two
// triangles sharing an edge see exactly opposite values. Ties (ray through an edge or vertex) are
// broken by the symbolic perturbation r = (x + ε, y + ε²) (Edelsbrunner & Mücke 1990, "Simulation
// of Simplicity"): a perturbed point lies strictly inside exactly one of the triangles around a
// shared vertex or edge, and never inside a triangle of zero projected area. The crossing depth is
// interpolated from the triangle's (unsnapped) vertex depths with the exact barycentric weights,
// so it always lies within the triangle's depth range.
//
// Fill rule: non-zero winding when the surface is a closed, consistently oriented cycle (every
// edge used as often in one direction as in the other, after the snapping and de-duplication
// below): each crossing counts +1 where the ray enters (the triangle faces against the ray) and
// −1 where it leaves, and a voxel centre c is inside iff the sum over the crossings at depth ≤ c
// is not zero (half-open spans [enter, leave)). Overlapping or nested closed shells thus give
// their union, and voxels with |sum| ≥ 2 are counted as overlap. On one embedded closed shell the
// crossings alternate and this equals parity. A surface whose edges do not cancel (flipped
// triangles, a missing facet) has no well-defined winding number: it is filled by parity, inside
// iff the number of crossings at depth ≤ c is odd. A column whose winding does not return to 0
// (parity: an odd number of crossings) is resolved as below.
//
// Triangles that repeat another triangle's three snapped vertices (in any order or orientation)
// are used once, so duplicated facets in a triangle soup do not flip the parity.
#include "curvedslicer/voxel/voxelize.hpp"

#include <unistd.h>

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "voxel/distinct_keys.hpp"
#include "voxel/grid_memory.hpp"
#include "voxel/parallel_chunks.hpp"

namespace curvedslicer {
namespace {

using voxel_internal::chunksForCells;
using voxel_internal::runChunked;

__extension__ typedef __int128 Int128;

constexpr int kLatticeBits = 20;
constexpr std::int64_t kCellUnits = std::int64_t{1} << kLatticeBits;  ///< lattice units per cell
constexpr std::int64_t kHalfCell = kCellUnits / 2;
/// Largest grid extent per axis (keeps lattice coordinates below 2^45 and indices in int).
constexpr double kMaxDim = static_cast<double>(1 << 24);
/// Largest cell count: the geodesic field indexes cells with int32 (checked here, before the
/// mask is allocated, rather than after voxelizing).
constexpr double kMaxCells = 2147483647.0;
/// Fallback memory budget when the physical memory cannot be queried.
constexpr double kFallbackBudgetBytes = 4e9;

// ---- number formatting for messages ------------------------------------------------------------

std::string formatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string formatCount(double count) {
  if (!(count < 1e18)) return formatNumber(count);  // beyond unsigned long long: 1e+30
  const std::string digits = std::to_string(static_cast<unsigned long long>(count));
  std::string grouped;
  for (std::size_t n = 0; n < digits.size(); ++n) {
    if (n > 0 && (digits.size() - n) % 3 == 0) grouped += ',';
    grouped += digits[n];
  }
  return grouped;
}

std::string formatBytes(double bytes) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1);
  if (!(bytes < 1e15)) {
    out << std::scientific << std::setprecision(1) << bytes << " bytes";  // 1.0e+36 bytes
  } else if (bytes >= 1e9) {
    out << bytes / 1e9 << " GB";
  } else if (bytes >= 1e6) {
    out << bytes / 1e6 << " MB";
  } else {
    out << std::setprecision(0) << bytes << " bytes";
  }
  return out.str();
}

/// A length already rounded to two significant digits, printed without an exponent.
std::string formatLength(double mm) {
  const int decimals = std::max(0, 1 - static_cast<int>(std::floor(std::log10(mm))));
  std::ostringstream out;
  out << std::fixed << std::setprecision(decimals) << mm;
  return out.str();
}

/// Smallest value with two significant digits that is ≥ `value`.
double roundUpTwoDigits(double value) {
  const double step = std::pow(10.0, std::floor(std::log10(value)) - 1.0);
  return std::ceil(value / step * (1.0 - 1e-12)) * step;
}

double nextTwoDigitValue(double value) {
  const double step = std::pow(10.0, std::floor(std::log10(value)) - 1.0);
  return roundUpTwoDigits(value + 0.5 * step);
}

// ---- validation ---------------------------------------------------------------------------------

void validateOptions(const VoxelizeOptions& options) {
  if (!(options.voxelSize > 0.0) || !std::isfinite(options.voxelSize)) {
    throw InvalidInput("voxel size must be a positive, finite length: " +
                       formatNumber(options.voxelSize) + " mm; pass a value such as 0.5");
  }
  if (options.padding < 1) {
    throw InvalidInput("grid padding must be at least 1 cell: " + std::to_string(options.padding) +
                       "; pass 1 or more (default 2)");
  }
  if (!(options.memoryBudgetBytes >= 0.0) || !std::isfinite(options.memoryBudgetBytes)) {
    throw InvalidInput("memory budget must be finite and not negative: " +
                       formatNumber(options.memoryBudgetBytes) +
                       " bytes; pass 0 for 80 % of the physical memory");
  }
  if (!(options.bytesPerCell > 0.0) || !std::isfinite(options.bytesPerCell)) {
    throw InvalidInput("bytes per cell must be positive and finite: " +
                       formatNumber(options.bytesPerCell) + "; pass the default 16");
  }
}

void validateMesh(const TriMesh& mesh) {
  if (mesh.triangles.empty()) {
    throw InvalidInput("cannot voxelize an empty mesh: 0 triangles; pass a closed triangle mesh");
  }
  const int vertexCount = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles[t][k];
      if (v < 0 || v >= vertexCount) {
        throw InvalidInput("triangle " + std::to_string(t) + " refers to vertex index " +
                           std::to_string(v) + " outside [0, " + std::to_string(vertexCount) +
                           "); repair or re-export the mesh");
      }
      const Vec3& p = mesh.vertices[v];
      if (!p.allFinite()) {
        throw InvalidInput("vertex " + std::to_string(v) + " has a non-finite coordinate: (" +
                           formatNumber(p.x()) + ", " + formatNumber(p.y()) + ", " +
                           formatNumber(p.z()) + "); repair or re-export the mesh");
      }
    }
  }
}

// ---- grid planning ------------------------------------------------------------------------------

/// Box of the vertices used by triangles, in grid-frame coordinates.
Aabb gridFrameBox(const TriMesh& mesh, const Frame& frame) {
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const Vec3i& tri : mesh.triangles) used[tri[0]] = used[tri[1]] = used[tri[2]] = 1;
  Aabb box;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (used[v]) box.extend(frame.toFrame(mesh.vertices[v]));
  }
  return box;
}

/// The grid lattice is anchored at the frame origin (cell faces at integer multiples of L), so
/// the cells are [lo − padding, hi + padding] with lo/hi the cells holding the box's min/max.
struct LatticeExtent {
  std::array<double, 3> first{};  ///< index of the first cell on the lattice
  std::array<double, 3> dims{};   ///< cells per axis
  double cells() const { return dims[0] * dims[1] * dims[2]; }
  bool withinLimits() const {
    return dims[0] <= kMaxDim && dims[1] <= kMaxDim && dims[2] <= kMaxDim && cells() < kMaxCells;
  }
};

LatticeExtent latticeExtent(const Aabb& box, double L, int padding) {
  LatticeExtent e;
  for (int a = 0; a < 3; ++a) {
    const double lo = std::floor(box.min[a] / L);
    const double hi = std::floor(box.max[a] / L);
    e.first[a] = lo - padding;
    e.dims[a] = hi - lo + 1.0 + 2.0 * padding;
  }
  return e;
}

bool fitsBudget(const Aabb& box, double L, int padding, double bytesPerCell, double budget) {
  const LatticeExtent e = latticeExtent(box, L, padding);
  return e.withinLimits() && e.cells() * bytesPerCell <= budget;
}

/// Smallest two-significant-digit voxel size whose grid fits the budget; 0 if none does.
double smallestFittingVoxelSize(const Aabb& box, double L, int padding, double bytesPerCell,
                                double budget) {
  double hi = L;
  const double limit = 1e6 * std::max(box.diagonal(), L);
  while (!fitsBudget(box, hi, padding, bytesPerCell, budget)) {
    hi *= 2.0;
    if (hi > limit) return 0.0;
  }
  double lo = L;
  for (int iteration = 0; iteration < 100 && hi - lo > 1e-9 * hi; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (fitsBudget(box, mid, padding, bytesPerCell, budget) ? hi : lo) = mid;
  }
  double suggestion = roundUpTwoDigits(hi);
  while (!fitsBudget(box, suggestion, padding, bytesPerCell, budget)) {
    suggestion = nextTwoDigitValue(suggestion);
  }
  return suggestion;
}

double effectiveBudget(const VoxelizeOptions& options) {
  if (options.memoryBudgetBytes > 0.0) return options.memoryBudgetBytes;
  const double physical = physicalMemoryBytes();
  return physical > 0.0 ? 0.8 * physical : kFallbackBudgetBytes;
}

// ---- exact ray casting --------------------------------------------------------------------------

using LatticePoint = std::array<std::int64_t, 3>;

/// The mesh in cell units of the grid: snapped lattice coordinates for the exact 2D tests,
/// unsnapped doubles for crossing depths.
struct LatticeMesh {
  std::vector<LatticePoint> lattice;
  std::vector<std::array<double, 3>> cell;
  std::vector<std::array<int, 3>> triangles;  ///< unique, not degenerate on the lattice
  std::array<double, 3> boxMin{}, boxMax{};   ///< cell units, over the vertices used
  bool windingRule = false;  ///< edges cancel: fill by non-zero winding (else by parity)
};

/// True if every lattice edge of the triangles is used as often in one direction as in the other
/// (a closed, consistently oriented surface, possibly several shells).
bool edgesCancel(const LatticeMesh& m) {
  // Weld vertices by lattice point: ids[v] is the same for vertices that snapped together.
  std::vector<int> used;
  used.reserve(3 * m.triangles.size());
  for (const auto& tri : m.triangles) used.insert(used.end(), tri.begin(), tri.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::stable_sort(used.begin(), used.end(),
                   [&](int a, int b) { return m.lattice[a] < m.lattice[b]; });
  std::vector<std::uint32_t> ids(m.lattice.size(), 0);
  std::uint32_t next = 0;
  for (std::size_t n = 0; n < used.size(); ++n) {
    if (n > 0 && m.lattice[used[n]] != m.lattice[used[n - 1]]) ++next;
    ids[used[n]] = next;
  }
  // Each directed edge as (smaller id, larger id) with +1 / −1 for its direction.
  std::vector<std::pair<std::uint64_t, int>> edges;
  edges.reserve(3 * m.triangles.size());
  for (const auto& tri : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t u = ids[tri[k]], v = ids[tri[(k + 1) % 3]];
      edges.emplace_back(u < v ? (u << 32 | v) : (v << 32 | u), u < v ? 1 : -1);
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t n = 0; n < edges.size();) {
    int sum = 0;
    std::size_t end = n;
    for (; end < edges.size() && edges[end].first == edges[n].first; ++end)
      sum += edges[end].second;
    if (sum != 0) return false;
    n = end;
  }
  return true;
}

LatticeMesh buildLatticeMesh(const TriMesh& mesh, const GridGeometry& g) {
  LatticeMesh m;
  const std::size_t n = mesh.vertices.size();
  m.lattice.assign(n, LatticePoint{});
  m.cell.assign(n, std::array<double, 3>{});
  std::vector<char> used(n, 0);  // unused vertices may lie anywhere (or be non-finite): skip them
  for (const Vec3i& tri : mesh.triangles) used[tri[0]] = used[tri[1]] = used[tri[2]] = 1;
  for (std::size_t v = 0; v < n; ++v) {
    if (!used[v]) continue;
    const Vec3 u = (g.frame.toFrame(mesh.vertices[v]) - g.corner) / g.voxelSize;
    for (int a = 0; a < 3; ++a) {
      m.cell[v][a] = u[a];
      m.lattice[v][a] = std::llround(u[a] * static_cast<double>(kCellUnits));
    }
  }

  // Sorted corner triple of each triangle; repeated or lattice-degenerate triangles are dropped.
  using Key = std::array<LatticePoint, 3>;
  std::vector<Key> keys(mesh.triangles.size());
  std::vector<std::size_t> order;
  order.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Key& key = keys[t];
    for (int k = 0; k < 3; ++k) key[k] = m.lattice[mesh.triangles[t][k]];
    std::sort(key.begin(), key.end());
    if (key[0] == key[1] || key[1] == key[2]) continue;
    order.push_back(t);
  }
  order = detail::firstOfEachDistinctKey(keys, std::move(order));

  m.boxMin.fill(kInf);
  m.boxMax.fill(-kInf);
  m.triangles.reserve(order.size());
  for (std::size_t t : order) {
    const Vec3i& tri = mesh.triangles[t];
    m.triangles.push_back({tri[0], tri[1], tri[2]});
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) {
        m.boxMin[a] = std::min(m.boxMin[a], m.cell[tri[k]][a]);
        m.boxMax[a] = std::max(m.boxMax[a], m.cell[tri[k]][a]);
      }
    }
  }
  m.windingRule = edgesCancel(m);
  return m;
}

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

/// Columns c in [0, n) whose centre (c + 1/2 cells) lies in the lattice interval [lo, hi];
/// empty when first > last.
struct ColumnRange {
  int first = 0;
  int last = -1;
};

ColumnRange columnRange(std::int64_t lo, std::int64_t hi, int n) {
  const std::int64_t first = -floorDiv(-(lo - kHalfCell), kCellUnits);  // ceil
  const std::int64_t last = floorDiv(hi - kHalfCell, kCellUnits);
  ColumnRange r;
  r.first = static_cast<int>(std::max<std::int64_t>(first, 0));
  r.last = static_cast<int>(std::min<std::int64_t>(last, n - 1));
  return r;
}

std::int64_t columnCentre(int c) {
  return static_cast<std::int64_t>(c) * kCellUnits + kHalfCell;
}

/// Rays of one family: they run along axis `w`; a ray is identified by its column on axis `a`
/// (the "slab") and on axis `b` (the "row"); the exact 2D test works in the (a, b) plane.
/// `handedness` is +1 if (a, b, w) is a right-handed axis order, −1 if not.
struct RayAxes {
  int a, b, w;
  int handedness;
};

/// Triangles binned by the slabs (columns along axis a) their lattice box covers (CSR).
struct SlabBins {
  std::vector<std::size_t> start;  ///< size slabs + 1
  std::vector<int> triangles;
};

SlabBins binTriangles(const LatticeMesh& m, int axis, int slabs) {
  SlabBins bins;
  bins.start.assign(static_cast<std::size_t>(slabs) + 1, 0);
  std::vector<ColumnRange> ranges(m.triangles.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    const std::int64_t lo =
        std::min({m.lattice[tri[0]][axis], m.lattice[tri[1]][axis], m.lattice[tri[2]][axis]});
    const std::int64_t hi =
        std::max({m.lattice[tri[0]][axis], m.lattice[tri[1]][axis], m.lattice[tri[2]][axis]});
    ranges[t] = columnRange(lo, hi, slabs);
    for (int s = ranges[t].first; s <= ranges[t].last; ++s) ++bins.start[s + 1];
  }
  std::partial_sum(bins.start.begin(), bins.start.end(), bins.start.begin());
  bins.triangles.resize(bins.start.back());
  std::vector<std::size_t> fill(bins.start.begin(), bins.start.end() - 1);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    for (int s = ranges[t].first; s <= ranges[t].last; ++s) {
      bins.triangles[fill[s]++] = static_cast<int>(t);
    }
  }
  return bins;
}

struct Hit {
  int row;
  std::int8_t
      winding;   ///< +1 where the ray enters (triangle facing against it), −1 where it leaves
  double depth;  ///< cell units along the ray axis
  bool operator<(const Hit& o) const { return row != o.row ? row < o.row : depth < o.depth; }
};

/// Per-thread hit list, on its own cache line (push_back writes the vector's header).
struct alignas(64) HitBuffer {
  std::vector<Hit> hits;
};

/// One triangle edge in canonical direction (lexicographically smaller endpoint first).
struct CanonicalEdge {
  std::int64_t ax, ay;  ///< canonical start
  std::int64_t dx, dy;  ///< canonical end − start
  int tieSign;          ///< sign of the ε and ε² terms of the perturbed orientation
  bool flipped;         ///< canonical direction is opposite to the triangle's
};

CanonicalEdge makeEdge(std::int64_t px, std::int64_t py, std::int64_t qx, std::int64_t qy) {
  CanonicalEdge e;
  e.flipped = qx < px || (qx == px && qy < py);
  if (e.flipped) {
    std::swap(px, qx);
    std::swap(py, qy);
  }
  e.ax = px;
  e.ay = py;
  e.dx = qx - px;
  e.dy = qy - py;
  // orient(a, b, (x + ε, y + ε²)) = o₀ − dy·ε + dx·ε².
  e.tieSign = e.dy != 0 ? (e.dy < 0 ? 1 : -1) : (e.dx > 0 ? 1 : (e.dx < 0 ? -1 : 0));
  return e;
}

/// Appends the crossings of the rays in slab `slab` with rows in [rowLo, rowHi].
void castSlab(const LatticeMesh& m, const SlabBins& bins, const RayAxes& axes, int slab, int rowLo,
              int rowHi, std::vector<Hit>& hits) {
  const std::int64_t X = columnCentre(slab);
  for (std::size_t n = bins.start[slab]; n < bins.start[slab + 1]; ++n) {
    const auto& tri = m.triangles[bins.triangles[n]];
    const LatticePoint& p0 = m.lattice[tri[0]];
    const LatticePoint& p1 = m.lattice[tri[1]];
    const LatticePoint& p2 = m.lattice[tri[2]];
    const ColumnRange rows = columnRange(std::min({p0[axes.b], p1[axes.b], p2[axes.b]}),
                                         std::max({p0[axes.b], p1[axes.b], p2[axes.b]}), rowHi + 1);
    const int first = std::max(rows.first, rowLo);
    if (first > rows.last) continue;

    const std::array<CanonicalEdge, 3> edges = {
        makeEdge(p0[axes.a], p0[axes.b], p1[axes.a], p1[axes.b]),
        makeEdge(p1[axes.a], p1[axes.b], p2[axes.a], p2[axes.b]),
        makeEdge(p2[axes.a], p2[axes.b], p0[axes.a], p0[axes.b])};
    // The x part of each orientation is fixed within the slab.
    std::array<Int128, 3> fixedPart;
    for (int e = 0; e < 3; ++e) {
      fixedPart[e] = static_cast<Int128>(edges[e].dy) * (X - edges[e].ax);
    }
    const double d0 = m.cell[tri[0]][axes.w];
    const double d1 = m.cell[tri[1]][axes.w];
    const double d2 = m.cell[tri[2]][axes.w];
    const double dMin = std::min({d0, d1, d2}), dMax = std::max({d0, d1, d2});

    for (int row = first; row <= rows.last; ++row) {
      const std::int64_t Y = columnCentre(row);
      std::array<Int128, 3> value;
      std::array<int, 3> sign;
      for (int e = 0; e < 3; ++e) {
        const CanonicalEdge& edge = edges[e];
        const Int128 o = static_cast<Int128>(edge.dx) * (Y - edge.ay) - fixedPart[e];
        const int s = o > 0 ? 1 : (o < 0 ? -1 : edge.tieSign);
        sign[e] = edge.flipped ? -s : s;
        value[e] = edge.flipped ? -o : o;
      }
      if (sign[0] == 0 || sign[0] != sign[1] || sign[1] != sign[2]) continue;
      // Barycentric weights: vertex 0 ↔ edge 1, vertex 1 ↔ edge 2, vertex 2 ↔ edge 0.
      const double w1 = static_cast<double>(value[2]);
      const double w2 = static_cast<double>(value[0]);
      const double W = static_cast<double>(value[0] + value[1] + value[2]);
      const double depth = std::clamp(d0 + (w1 * (d1 - d0) + w2 * (d2 - d0)) / W, dMin, dMax);
      // sign[0] > 0: counter-clockwise in (a, b), so the normal points along +w in a right-handed
      // order and the ray (running along +w) leaves there.
      hits.push_back({row, static_cast<std::int8_t>(-sign[0] * axes.handedness), depth});
    }
  }
}

// ---- voxelize ----------------------------------------------------------------------------------

/// Whether the crossings [begin, end) of one ray close up: winding sum 0 (winding rule) or an
/// even count (parity). Rays that do not close cannot be filled from their own crossings.
bool rayCloses(std::vector<Hit>::const_iterator begin, std::vector<Hit>::const_iterator end,
               bool winding) {
  if (!winding) return (end - begin) % 2 == 0;
  int sum = 0;
  for (auto h = begin; h != end; ++h) sum += h->winding;
  return sum == 0;
}

/// Cells filled and cells inside more than one shell (|winding| ≥ 2) of one slab.
struct SlabFill {
  std::size_t filled = 0;
  std::size_t overlap = 0;
  Vec3i overlapLo = Vec3i::Constant(std::numeric_limits<int>::max());  ///< cell index box
  Vec3i overlapHi = Vec3i::Constant(std::numeric_limits<int>::min());
};

/// Fills the voxels of one column from the crossings [begin, end) of its ray, sorted by depth:
/// the centres c = k + ½ in each span [depth_p, depth_p+1) where the running winding sum after
/// crossing p is not zero (winding rule) or p is even (parity).
void fillColumn(std::vector<Hit>::const_iterator begin, std::vector<Hit>::const_iterator end,
                bool winding, const Vec3i& column0, int nz, std::uint8_t* column, SlabFill& fill) {
  int sum = 0;
  for (auto p = begin; p + 1 < end; ++p) {
    sum += p->winding;
    if (winding ? sum == 0 : (p - begin) % 2 != 0) continue;
    const double k0 = std::max(0.0, std::ceil(p->depth - 0.5));
    const double k1 = std::min(static_cast<double>(nz), std::ceil((p + 1)->depth - 0.5));
    if (k1 > k0) {
      const auto count = static_cast<std::size_t>(k1 - k0);
      std::memset(column + static_cast<std::size_t>(k0), 1, count);
      fill.filled += count;
      if (std::abs(sum) >= 2) {
        fill.overlap += count;
        const Vec3i lo(column0.x(), column0.y(), static_cast<int>(k0));
        const Vec3i hi(column0.x(), column0.y(), static_cast<int>(k1) - 1);
        fill.overlapLo = fill.overlapLo.cwiseMin(lo);
        fill.overlapHi = fill.overlapHi.cwiseMax(hi);
      }
    }
  }
}

/// Casts the z rays of x slab `i`, fills the inside spans of the columns whose rays close (mask
/// of the slab only) and lists the rows of the others (the odd columns).
SlabFill fillSlab(const LatticeMesh& m, const SlabBins& xBins, const GridGeometry& g, int i,
                  std::uint8_t* mask, std::vector<Hit>& hits, std::vector<int>& oddRows) {
  const int ny = g.dims.y(), nz = g.dims.z();
  hits.clear();
  castSlab(m, xBins, RayAxes{0, 1, 2, 1}, i, 0, ny - 1, hits);
  std::sort(hits.begin(), hits.end());
  std::uint8_t* slab = mask + static_cast<std::size_t>(i) * g.strideX();
  SlabFill fill;
  for (auto h = hits.cbegin(); h != hits.cend();) {
    auto end = h;
    while (end != hits.cend() && end->row == h->row) ++end;
    if (!rayCloses(h, end, m.windingRule)) {
      oddRows.push_back(h->row);
    } else {
      fillColumn(h, end, m.windingRule, Vec3i(i, h->row, 0), nz,
                 slab + static_cast<std::size_t>(h->row) * nz, fill);
    }
    h = end;
  }
  return fill;
}

// ---- resolve odd columns -----------------------------------------------------------------------

struct OddColumn {
  int i, j;
};

// Vote bits kept in the mask of odd-column voxels while they are being resolved.
constexpr std::uint8_t kVoteXInside = 2, kVoteXOutside = 4, kVoteYInside = 8, kVoteYOutside = 16;

/// Odd columns grouped by their j (x rays) or i (y rays): `order` lists column indices sorted by
/// the key, group n is order[starts[n] .. starts[n + 1]).
struct ColumnGroups {
  std::vector<std::size_t> order;
  std::vector<std::size_t> starts;
};

ColumnGroups groupColumns(const std::vector<OddColumn>& odd, bool byJ) {
  auto key = [&](std::size_t c) { return byJ ? odd[c].j : odd[c].i; };
  ColumnGroups groups;
  groups.order.resize(odd.size());
  std::iota(groups.order.begin(), groups.order.end(), std::size_t{0});
  std::stable_sort(groups.order.begin(), groups.order.end(),
                   [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  for (std::size_t n = 0; n < groups.order.size(); ++n) {
    if (n == 0 || key(groups.order[n]) != key(groups.order[n - 1])) groups.starts.push_back(n);
  }
  groups.starts.push_back(groups.order.size());
  return groups;
}

/// Casts the x rays (alongX) or y rays of one group's slab for rows [kLo, kHi] and records each
/// group column's vote for its voxels in the mask.
void voteGroup(const LatticeMesh& m, const SlabBins& bins, const GridGeometry& g,
               const std::vector<OddColumn>& odd, const ColumnGroups& groups, std::size_t group,
               bool alongX, int kLo, int kHi, std::uint8_t* mask, std::vector<Hit>& hits) {
  const std::size_t begin = groups.starts[group], end = groups.starts[group + 1];
  const OddColumn& first = odd[groups.order[begin]];
  const RayAxes axes = alongX ? RayAxes{1, 2, 0, 1} : RayAxes{0, 2, 1, -1};
  hits.clear();
  castSlab(m, bins, axes, alongX ? first.j : first.i, kLo, kHi, hits);
  std::sort(hits.begin(), hits.end());
  const std::uint8_t insideVote = alongX ? kVoteXInside : kVoteYInside;
  const std::uint8_t outsideVote = alongX ? kVoteXOutside : kVoteYOutside;
  auto h = hits.begin();
  for (int k = kLo; k <= kHi; ++k) {
    while (h != hits.end() && h->row < k) ++h;
    auto rowEnd = h;
    while (rowEnd != hits.end() && rowEnd->row == k) ++rowEnd;
    if (rayCloses(h, rowEnd, m.windingRule)) {
      for (std::size_t n = begin; n < end; ++n) {
        const OddColumn& col = odd[groups.order[n]];
        const double centre = (alongX ? col.i : col.j) + 0.5;
        const auto upTo = std::upper_bound(
            h, rowEnd, centre, [](double value, const Hit& hit) { return value < hit.depth; });
        const bool inside = m.windingRule ? !rayCloses(h, upTo, true) : (upTo - h) % 2 != 0;
        mask[g.index(col.i, col.j, k)] |= inside ? insideVote : outsideVote;
      }
    }
    h = rowEnd;
  }
}

/// Decides the voxels of the odd columns (see voxelize.hpp) and counts them into `stats`;
/// returns the number of voxels set inside.
std::size_t resolveOddColumns(const LatticeMesh& m, const SlabBins& xBins, const GridGeometry& g,
                              const std::vector<OddColumn>& odd, std::uint8_t* mask,
                              std::vector<HitBuffer>& hitBuffers, const Progress& progress,
                              VoxelizeStats& stats) {
  // Voxel centres outside the mesh's z range are outside. (Odd columns imply triangles, so the
  // range is finite; clamp before converting anyway.)
  const int nz = g.dims.z();
  const int kLo = static_cast<int>(std::clamp(std::ceil(m.boxMin[2] - 0.5), 0.0, double(nz)));
  const int kHi = static_cast<int>(std::clamp(std::floor(m.boxMax[2] - 0.5), -1.0, nz - 1.0));
  if (odd.empty() || kLo > kHi) return 0;
  // Work of one ray pass: about one grid row of cells per odd-column voxel.
  const int chunks = chunksForCells(static_cast<double>(odd.size()) * (g.dims.x() + g.dims.y()) *
                                    static_cast<double>(kHi - kLo + 1));

  // x rays: slabs along y (j), rows along z, depth along x.
  const ColumnGroups byJ = groupColumns(odd, true);
  const SlabBins yBins = binTriangles(m, 1, g.dims.y());
  runChunked(static_cast<int>(byJ.starts.size()) - 1, chunks, progress.sub(0.0, 0.5),
             "resolve odd columns", [&](int group, int thread) {
               voteGroup(m, yBins, g, odd, byJ, group, true, kLo, kHi, mask,
                         hitBuffers[thread].hits);
             });
  // y rays: slabs along x (i), rows along z, depth along y.
  const ColumnGroups byI = groupColumns(odd, false);
  runChunked(static_cast<int>(byI.starts.size()) - 1, chunks, progress.sub(0.5, 1.0),
             "resolve odd columns", [&](int group, int thread) {
               voteGroup(m, xBins, g, odd, byI, group, false, kLo, kHi, mask,
                         hitBuffers[thread].hits);
             });

  // Majority of the even rays; no vote (or a tie) leaves the voxel outside.
  std::size_t inside = 0;
  for (const OddColumn& col : odd) {
    for (int k = kLo; k <= kHi; ++k) {
      std::uint8_t& cell = mask[g.index(col.i, col.j, k)];
      const int in = ((cell & kVoteXInside) ? 1 : 0) + ((cell & kVoteYInside) ? 1 : 0);
      const int out = ((cell & kVoteXOutside) ? 1 : 0) + ((cell & kVoteYOutside) ? 1 : 0);
      ++(in + out == 0 ? stats.unresolvedVoxels : stats.resolvedVoxels);
      cell = in > out ? 1 : 0;
      inside += cell;
    }
  }
  return inside;
}

}  // namespace

std::string_view toString(FillRule rule) {
  return rule == FillRule::Parity ? "parity" : "nonzero";
}

double physicalMemoryBytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long pageSize = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || pageSize <= 0) return 0.0;
  return static_cast<double>(pages) * static_cast<double>(pageSize);
}

GridGeometry planGrid(const TriMesh& mesh, const VoxelizeOptions& options) {
  validateOptions(options);
  validateMesh(mesh);
  const double L = options.voxelSize;

  GridGeometry g;
  g.voxelSize = L;
  if (options.alignment == GridAlignment::Pca) g.frame = computePcaFrame(mesh);
  const Aabb box = gridFrameBox(mesh, g.frame);
  const LatticeExtent extent = latticeExtent(box, L, options.padding);

  const double budget = effectiveBudget(options);
  const double needed = extent.cells() * options.bytesPerCell;
  if (!extent.withinLimits() || needed > budget) {
    std::ostringstream msg;
    msg << "grid " << formatCount(extent.dims[0]) << " x " << formatCount(extent.dims[1]) << " x "
        << formatCount(extent.dims[2]) << " = " << formatCount(extent.cells())
        << " cells at voxel size " << formatNumber(L) << " mm needs " << formatBytes(needed)
        << " at " << formatNumber(options.bytesPerCell) << " bytes per cell, over the memory "
        << "budget of " << formatBytes(budget);
    if (!extent.withinLimits()) {
      msg << " (or over the limits of " << formatCount(kMaxDim) << " cells per axis and "
          << formatCount(kMaxCells) << " cells in all)";
    }
    const double fitting =
        smallestFittingVoxelSize(box, L, options.padding, options.bytesPerCell, budget);
    if (fitting > 0.0) {
      // Beyond the per-axis or total cell limits a larger budget does not help.
      msg << "; use a voxel size of at least " << formatLength(fitting) << " mm"
          << (extent.withinLimits() ? " or raise the memory budget" : "");
    } else {
      msg << "; no voxel size fits, raise the memory budget";
    }
    throw ResourceLimit(msg.str());
  }

  for (int a = 0; a < 3; ++a) {
    g.corner[a] = extent.first[a] * L;
    g.dims[a] = static_cast<int>(extent.dims[a]);
  }
  return g;
}

GridEstimate estimateGrid(const TriMesh& mesh, const VoxelizeOptions& options) {
  validateOptions(options);
  validateMesh(mesh);
  const Frame frame =
      options.alignment == GridAlignment::Pca ? computePcaFrame(mesh) : GridGeometry{}.frame;
  const LatticeExtent extent =
      latticeExtent(gridFrameBox(mesh, frame), options.voxelSize, options.padding);
  GridEstimate e;
  e.dims = extent.dims;
  e.cells = extent.cells();
  e.bytes = e.cells * options.bytesPerCell;
  e.budgetBytes = effectiveBudget(options);
  try {
    (void)planGrid(mesh, options);
  } catch (const ResourceLimit& error) {
    e.fits = false;
    e.message = error.what();
  }
  return e;
}

VoxelizeResult voxelize(const TriMesh& mesh, const VoxelizeOptions& options, Progress progress) {
  const auto started = std::chrono::steady_clock::now();
  progress.report(0.0, "plan grid");
  VoxelizeResult result;
  VoxelGrid& grid = result.grid;
  grid.geometry = planGrid(mesh, options);
  const GridGeometry& g = grid.geometry;
  const int nx = g.dims.x();

  const LatticeMesh m = buildLatticeMesh(mesh, g);
  voxel_internal::assignZeroed(grid.inside, g.cellCount());

  // ---- voxelize: z rays through every (x, y) column, parallel over x slabs ----
  const SlabBins xBins = binTriangles(m, 0, nx);
  std::vector<HitBuffer> hitBuffers(static_cast<std::size_t>(omp_get_max_threads()));
  std::vector<std::vector<int>> oddRows(nx);
  std::vector<SlabFill> filled(nx);
  runChunked(nx, chunksForCells(static_cast<double>(g.cellCount())), progress.sub(0.0, 0.9),
             "voxelize", [&](int i, int thread) {
               filled[i] = fillSlab(m, xBins, g, i, grid.inside.data(), hitBuffers[thread].hits,
                                    oddRows[i]);
             });
  VoxelizeStats& stats = result.stats;
  grid.insideCount = 0;
  for (const SlabFill& f : filled) {
    grid.insideCount += f.filled;
    stats.overlapVoxels += f.overlap;
    if (f.overlap == 0) continue;
    for (int corner = 0; corner < 8; ++corner) {  // the index box's corners, in the part frame
      const Vec3i c((corner & 1 ? f.overlapHi : f.overlapLo).x(),
                    (corner & 2 ? f.overlapHi : f.overlapLo).y(),
                    (corner & 4 ? f.overlapHi : f.overlapLo).z());
      stats.overlapBounds.extend(g.centerInPart(c));
    }
  }
  stats.fillRule = m.windingRule ? FillRule::NonZeroWinding : FillRule::Parity;

  stats.columns = static_cast<std::size_t>(nx) * g.dims.y();
  std::vector<OddColumn> odd;  // sorted by (i, j)
  for (int i = 0; i < nx; ++i) {
    for (const int j : oddRows[i]) odd.push_back({i, j});
  }
  stats.oddColumns = odd.size();

  // ---- resolve odd columns: x and y rays through each of their voxel centres ----
  grid.insideCount += resolveOddColumns(m, xBins, g, odd, grid.inside.data(), hitBuffers,
                                        progress.sub(0.9, 1.0), stats);

  progress.report(1.0, "voxelize");
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace curvedslicer
