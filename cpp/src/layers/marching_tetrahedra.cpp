// One-pass marching tetrahedra for all layer levels (see layer_internal.hpp).
//
// The dual grid's cubes have the centres of 2×2×2 cells as corners (corner id c: bit 0 = +x,
// bit 1 = +y, bit 2 = +z). Each cube is split into the 6 Kuhn tetrahedra 0 → e_a → e_a + e_b → 7
// around the main diagonal; every face diagonal then runs from the face's min to its max corner,
// so neighbouring cubes agree on shared faces and the surface has no cracks. Every tetrahedron
// edge joins two grid points p ≤ q (componentwise), so a vertex is keyed by the global grid edge
// (index of p, 3-bit offset q − p) — or by the grid point itself when the value there equals the
// level exactly — which makes vertices shared between tetrahedra, cubes and slabs.
//
// The x range of cubes is cut into fixed slabs (independent of the thread count, so the output is
// deterministic); slabs run in parallel, each with its own vertex map and per-level buffers, and
// each level is then merged in slab order, reusing the vertices that lie on the plane shared with
// the previous slab.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

#include "curvedslicer/core/error.hpp"
#include "layers/layer_internal.hpp"

namespace curvedslicer::layers_detail {
namespace {

// ---- tables ----

using TetCorners = std::array<int, 4>;

Vec3 cornerOffset(int c) {
  return Vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
}

// The 6 Kuhn tetrahedra, each ordered so that det[p1 − p0, p2 − p0, p3 − p0] > 0.
const std::array<TetCorners, 6>& kuhnTetrahedra() {
  static const std::array<TetCorners, 6> tets = [] {
    std::array<TetCorners, 6> t{};
    const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int p = 0; p < 6; ++p) {
      const int a = 1 << axes[p][0];
      const int b = a | (1 << axes[p][1]);
      t[p] = {0, a, b, 7};
      const Vec3 p0 = cornerOffset(t[p][0]);
      const double det = (cornerOffset(t[p][1]) - p0)
                             .dot((cornerOffset(t[p][2]) - p0).cross(cornerOffset(t[p][3]) - p0));
      if (det < 0.0) std::swap(t[p][2], t[p][3]);
    }
    return t;
  }();
  return tets;
}

/// A surface vertex on the tetrahedron edge from local vertex `below` (value < level) to `above`.
struct TetEdge {
  int below = 0, above = 0;
};
struct TetCase {
  int triangleCount = 0;
  std::array<std::array<TetEdge, 3>, 2> triangles{};
};

bool isOddPermutation(const std::array<int, 4>& p) {
  int inversions = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) inversions += p[a] > p[b] ? 1 : 0;
  return (inversions & 1) != 0;
}

// Triangles for each below-mask (bit q: local vertex q below the level) of a positively oriented
// tetrahedron, oriented with normals pointing from the below side to the above side.
const std::array<TetCase, 16>& tetCases() {
  static const std::array<TetCase, 16> cases = [] {
    std::array<TetCase, 16> table{};
    for (int mask = 1; mask < 15; ++mask) {
      std::array<int, 4> below{}, above{};
      int nb = 0, na = 0;
      for (int q = 0; q < 4; ++q) {
        if ((mask >> q) & 1) {
          below[nb++] = q;
        } else {
          above[na++] = q;
        }
      }
      TetCase& tc = table[mask];
      if (nb == 1) {
        // (a, b, c, d) even, a below: the triangle (ab, ac, ad) faces away from a.
        std::array<int, 4> p = {below[0], above[0], above[1], above[2]};
        if (isOddPermutation(p)) std::swap(p[2], p[3]);
        tc.triangleCount = 1;
        tc.triangles[0] = {TetEdge{p[0], p[1]}, TetEdge{p[0], p[2]}, TetEdge{p[0], p[3]}};
      } else if (nb == 3) {
        // a above: the same triangle reversed faces towards a.
        std::array<int, 4> p = {above[0], below[0], below[1], below[2]};
        if (isOddPermutation(p)) std::swap(p[2], p[3]);
        tc.triangleCount = 1;
        tc.triangles[0] = {TetEdge{p[1], p[0]}, TetEdge{p[3], p[0]}, TetEdge{p[2], p[0]}};
      } else {
        // a, b below, c, d above, (a, b, c, d) even: quad (ac, ad, bd, bc).
        std::array<int, 4> p = {below[0], below[1], above[0], above[1]};
        if (isOddPermutation(p)) std::swap(p[2], p[3]);
        const TetEdge ac{p[0], p[2]}, ad{p[0], p[3]}, bd{p[1], p[3]}, bc{p[1], p[2]};
        tc.triangleCount = 2;
        tc.triangles[0] = {ac, ad, bd};
        tc.triangles[1] = {ac, bd, bc};
      }
    }
    return table;
  }();
  return cases;
}

// ---- vertex map: open addressing, 64-bit keys -> 32-bit local indices ----

class KeyIndexMap {
 public:
  KeyIndexMap() { rehash(1u << 12); }

  /// Returns the index stored for `key`, inserting `fresh` if the key is new (then `inserted`).
  std::uint32_t findOrInsert(std::uint64_t key, std::uint32_t fresh, bool& inserted) {
    if (2 * (size_ + 1) > keys_.size()) rehash(2 * keys_.size());
    std::size_t slot = hash(key) & mask_;
    while (true) {
      if (keys_[slot] == kEmpty) {
        keys_[slot] = key;
        values_[slot] = fresh;
        ++size_;
        inserted = true;
        return fresh;
      }
      if (keys_[slot] == key) {
        inserted = false;
        return values_[slot];
      }
      slot = (slot + 1) & mask_;
    }
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  static std::size_t hash(std::uint64_t x) {  // splitmix64 finaliser
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    x ^= x >> 31;
    return static_cast<std::size_t>(x);
  }
  void rehash(std::size_t capacity) {
    std::vector<std::uint64_t> oldKeys = std::move(keys_);
    std::vector<std::uint32_t> oldValues = std::move(values_);
    keys_.assign(capacity, kEmpty);
    values_.assign(capacity, 0);
    mask_ = capacity - 1;
    size_ = 0;
    for (std::size_t s = 0; s < oldKeys.size(); ++s) {
      if (oldKeys[s] == kEmpty) continue;
      std::size_t slot = hash(oldKeys[s]) & mask_;
      while (keys_[slot] != kEmpty) slot = (slot + 1) & mask_;
      keys_[slot] = oldKeys[s];
      values_[slot] = oldValues[s];
      ++size_;
    }
  }
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> values_;
  std::size_t mask_ = 0, size_ = 0;
};

// ---- slabs ----

struct LayerPiece {
  std::vector<Vec3> vertices;       // part frame
  std::vector<std::uint64_t> keys;  // grid key: point index · 8 + edge offset bits (0 = point)
  std::vector<Vec3i> triangles;     // local vertex indices
};

struct Slab {
  int x0 = 0, x1 = 0;  // cubes with min-corner x in [x0, x1)
  std::vector<LayerPiece> layers;
};

int bitsFor(std::uint64_t n) {
  int bits = 0;
  while (bits < 64 && (n >> bits) != 0) ++bits;
  return bits;
}

/// Marches the cubes of `slab` for levels [levelBegin, levelEnd] (1-based, within 1..layerCount);
/// slab.layers[level − levelBegin] receives level `level`.
void marchSlab(Slab& slab, const std::vector<float>& values, const GridGeometry& g, double h,
               int layerCount, int levelBegin, int levelEnd, int layerBits, bool flip) {
  const int ny = g.dims.y(), nz = g.dims.z();
  const std::size_t sx = g.strideX(), sy = g.strideY();
  std::array<std::size_t, 8> offset{};
  for (int c = 0; c < 8; ++c) offset[c] = (c & 1) * sx + ((c >> 1) & 1) * sy + ((c >> 2) & 1);
  const auto& tets = kuhnTetrahedra();
  const auto& cases = tetCases();
  slab.layers.assign(static_cast<std::size_t>(levelEnd - levelBegin + 1), {});
  KeyIndexMap map;
  const double lowest = levelBegin * h, highest = levelEnd * h;

  std::array<double, 8> v{};
  std::array<Vec3, 8> centre{};  // grid frame
  for (int i = slab.x0; i < slab.x1; ++i) {
    for (int j = 0; j + 1 < ny; ++j) {
      for (int k = 0; k + 1 < nz; ++k) {
        const std::size_t n = g.index(i, j, k);
        bool complete = true;
        double lo = kInf, hi = -kInf;
        for (int c = 0; c < 8; ++c) {
          const float f = values[n + offset[c]];
          if (!(f < kInfF)) {
            complete = false;
            break;
          }
          v[c] = f;
          lo = std::min(lo, v[c]);
          hi = std::max(hi, v[c]);
        }
        if (!complete) continue;
        // Cubes entirely above or below the levels of this pass (the exact test is below).
        if (!(lo < highest + h && hi >= lowest - h)) continue;
        // Candidate levels (one extra on each side against rounding), clamped before the cast.
        const int first = static_cast<int>(
            std::clamp(std::floor(lo / h), static_cast<double>(levelBegin), levelEnd + 1.0));
        const int last = static_cast<int>(
            std::clamp(std::floor(hi / h) + 1.0, levelBegin - 1.0, static_cast<double>(levelEnd)));
        bool centresReady = false;
        for (int level = first; level <= last; ++level) {
          const double lambda = level * h;
          if (!(lo < lambda && lambda <= hi)) continue;
          if (!centresReady) {
            for (int c = 0; c < 8; ++c) {
              centre[c] =
                  g.corner + (Vec3(i, j, k) + cornerOffset(c) + Vec3::Constant(0.5)) * g.voxelSize;
            }
            centresReady = true;
          }
          LayerPiece& piece = slab.layers[static_cast<std::size_t>(level - levelBegin)];
          // Vertices already looked up in this cube for this level, by corner pair.
          std::array<int, 64> cached;
          cached.fill(-1);
          auto vertexOn = [&](int ca, int cb) -> int {  // ca below, cb above (cube corners)
            int& slot = cached[static_cast<std::size_t>(ca * 8 + cb)];
            if (slot >= 0) return slot;
            std::uint64_t key;
            Vec3 position;
            if (v[cb] == lambda) {
              key = static_cast<std::uint64_t>(n + offset[cb]) << 3;
              position = centre[cb];
            } else {
              const int lower = (ca & cb) == ca ? ca : cb;
              key = (static_cast<std::uint64_t>(n + offset[lower]) << 3) |
                    static_cast<std::uint64_t>(ca ^ cb);
              const double t = (lambda - v[ca]) / (v[cb] - v[ca]);
              position = centre[ca] + t * (centre[cb] - centre[ca]);
            }
            bool inserted = false;
            const auto fresh = static_cast<std::uint32_t>(piece.vertices.size());
            const std::uint32_t index = map.findOrInsert(
                (key << layerBits) | static_cast<std::uint64_t>(level - 1), fresh, inserted);
            if (inserted) {
              piece.vertices.push_back(g.frame.toPart(position));
              piece.keys.push_back(key);
            }
            slot = static_cast<int>(index);
            return slot;
          };
          for (const TetCorners& tet : tets) {
            int mask = 0;
            for (int q = 0; q < 4; ++q) mask |= (v[tet[q]] < lambda ? 1 : 0) << q;
            const TetCase& tc = cases[mask];
            for (int t = 0; t < tc.triangleCount; ++t) {
              Vec3i tri;
              for (int e = 0; e < 3; ++e) {
                const TetEdge& edge = tc.triangles[t][e];
                tri[e] = vertexOn(tet[edge.below], tet[edge.above]);
              }
              if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) continue;
              if (flip) std::swap(tri[1], tri[2]);
              piece.triangles.push_back(tri);
            }
          }
        }
      }
    }
  }
}

TriMesh mergeLevel(std::vector<Slab>& slabs, std::size_t level, std::size_t strideX) {
  TriMesh mesh;
  std::size_t vertexTotal = 0, triangleTotal = 0;
  for (const Slab& s : slabs) {
    vertexTotal += s.layers[level].vertices.size();
    triangleTotal += s.layers[level].triangles.size();
  }
  mesh.vertices.reserve(vertexTotal);
  mesh.triangles.reserve(triangleTotal);
  std::unordered_map<std::uint64_t, int> previous, next;
  std::vector<int> remap;
  for (std::size_t s = 0; s < slabs.size(); ++s) {
    LayerPiece& piece = slabs[s].layers[level];
    const auto lowerPlane = static_cast<std::uint64_t>(slabs[s].x0);
    const auto upperPlane = static_cast<std::uint64_t>(slabs[s].x1);
    remap.assign(piece.vertices.size(), -1);
    next.clear();
    for (std::size_t v = 0; v < piece.vertices.size(); ++v) {
      const std::uint64_t key = piece.keys[v];
      const bool inXPlane = (key & 1) == 0;  // the edge (or point) does not advance in x
      const std::uint64_t px = (key >> 3) / strideX;
      if (inXPlane && px == lowerPlane && s > 0) {
        const auto it = previous.find(key);
        if (it != previous.end()) {
          remap[v] = it->second;
          continue;
        }
      }
      remap[v] = static_cast<int>(mesh.vertices.size());
      mesh.vertices.push_back(piece.vertices[v]);
      if (inXPlane && px == upperPlane) next.emplace(key, remap[v]);
    }
    for (const Vec3i& t : piece.triangles) {
      const Vec3i g(remap[t[0]], remap[t[1]], remap[t[2]]);
      if (g[0] == g[1] || g[1] == g[2] || g[2] == g[0]) continue;
      mesh.triangles.push_back(g);
    }
    previous.swap(next);
    piece = LayerPiece{};  // release memory early
  }
  return mesh;
}

}  // namespace

IsoSurfacePlan planIsoSurfaces(const std::vector<float>& values, const GridGeometry& geometry,
                               double h, int layerCount, const Progress& progress) {
  IsoSurfacePlan plan;
  plan.h = h;
  plan.layerCount = std::max(0, layerCount);
  plan.crossingCubes.assign(static_cast<std::size_t>(plan.layerCount), 0);
  const int cubesX = geometry.dims.x() - 1;
  if (plan.layerCount == 0 || cubesX < 1 || geometry.dims.y() < 2 || geometry.dims.z() < 2) {
    progress.report(1.0, "counting crossings");
    return plan;
  }
  plan.layerBits = std::max(1, bitsFor(static_cast<std::uint64_t>(plan.layerCount - 1)));
  const int keyBits = bitsFor(static_cast<std::uint64_t>(geometry.cellCount())) + 3;
  if (keyBits + plan.layerBits > 64) {
    throw InvalidInput(
        "grid too large for layer extraction: " + std::to_string(geometry.cellCount()) +
        " cells with " + std::to_string(layerCount) + " layers; use a coarser voxel size");
  }
  const int slabWidth = std::max(1, (cubesX + 127) / 128);
  for (int x0 = 0; x0 < cubesX; x0 += slabWidth) {
    plan.slabs.push_back({x0, std::min(cubesX, x0 + slabWidth), 0, -1});
  }
  // Per slab: crossings of the levels [firstLevel, lastLevel] it meets (a window, so the counts
  // take memory in proportion to the levels each slab spans).
  struct Counts {
    int first = 0;
    std::vector<std::uint64_t> perLevel;
  };
  std::vector<Counts> counts(plan.slabs.size());
  const int ny = geometry.dims.y(), nz = geometry.dims.z();
  const std::size_t sx = geometry.strideX(), sy = geometry.strideY();
  std::array<std::size_t, 8> offset{};
  for (int c = 0; c < 8; ++c) offset[c] = (c & 1) * sx + ((c >> 1) & 1) * sy + ((c >> 2) & 1);
  runChunked(plan.slabs.size(), progress, "counting crossings", [&](std::size_t s) {
    IsoSurfacePlan::SlabLevels& slab = plan.slabs[s];
    // Pass 1: the range of values over the slab's complete cubes; pass 2: crossings per level.
    double slabLo = kInf, slabHi = -kInf;
    std::vector<std::uint64_t>& perLevel = counts[s].perLevel;
    for (int pass = 0; pass < 2; ++pass) {
      for (int i = slab.x0; i < slab.x1; ++i) {
        for (int j = 0; j + 1 < ny; ++j) {
          for (int k = 0; k + 1 < nz; ++k) {
            const std::size_t n = geometry.index(i, j, k);
            bool complete = true;
            double lo = kInf, hi = -kInf;
            for (int c = 0; c < 8; ++c) {
              const float f = values[n + offset[c]];
              if (!(f < kInfF)) {
                complete = false;
                break;
              }
              lo = std::min(lo, static_cast<double>(f));
              hi = std::max(hi, static_cast<double>(f));
            }
            if (!complete) continue;
            if (pass == 0) {
              slabLo = std::min(slabLo, lo);
              slabHi = std::max(slabHi, hi);
              continue;
            }
            // The same candidate levels and test as marchSlab.
            const double count = plan.layerCount;
            const int first = static_cast<int>(std::clamp(std::floor(lo / h), 1.0, count + 1.0));
            const int last = static_cast<int>(std::clamp(std::floor(hi / h) + 1.0, 0.0, count));
            for (int level = first; level <= last; ++level) {
              const double lambda = level * h;
              if (!(lo < lambda && lambda <= hi)) continue;
              ++perLevel[static_cast<std::size_t>(level - counts[s].first)];
              slab.firstLevel = std::min(slab.firstLevel, level);
              slab.lastLevel = std::max(slab.lastLevel, level);
            }
          }
        }
      }
      if (pass == 0) {
        if (!(slabLo <= slabHi)) break;  // no complete cube
        const double count = plan.layerCount;
        counts[s].first = static_cast<int>(std::clamp(std::floor(slabLo / h), 1.0, count + 1.0));
        const int last = static_cast<int>(std::clamp(std::floor(slabHi / h) + 1.0, 0.0, count));
        if (last < counts[s].first) break;
        perLevel.assign(static_cast<std::size_t>(last - counts[s].first + 1), 0);
        slab.firstLevel = plan.layerCount + 1;
        slab.lastLevel = 0;
      }
    }
    if (slab.lastLevel < slab.firstLevel) {
      slab.firstLevel = 0;
      slab.lastLevel = -1;
    }
  });
  for (const Counts& c : counts) {
    for (std::size_t q = 0; q < c.perLevel.size(); ++q) {
      plan.crossingCubes[static_cast<std::size_t>(c.first - 1) + q] += c.perLevel[q];
    }
  }
  return plan;
}

std::vector<TriMesh> extractIsoSurfaces(const std::vector<float>& values,
                                        const GridGeometry& geometry, const IsoSurfacePlan& plan,
                                        int levelBegin, int levelEnd, const Progress& progress) {
  if (levelBegin < 1 || levelEnd > plan.layerCount || levelEnd < levelBegin) {
    throw InvalidInput("level range outside the planned layers: " + std::to_string(levelBegin) +
                       ".." + std::to_string(levelEnd) + " of 1.." +
                       std::to_string(plan.layerCount) + "; pass a range within the plan");
  }
  std::vector<TriMesh> result(static_cast<std::size_t>(levelEnd - levelBegin + 1));
  if (plan.slabs.empty()) {
    progress.report(1.0, "merging layers");
    return result;
  }
  const bool flip = geometry.frame.rotation.determinant() < 0.0;

  // ---- marching tetrahedra ----
  // Only the slabs that meet a level of the range; the others contribute nothing to it.
  std::vector<Slab> slabs;
  for (const IsoSurfacePlan::SlabLevels& s : plan.slabs) {
    if (s.lastLevel < levelBegin || s.firstLevel > levelEnd) continue;
    Slab slab;
    slab.x0 = s.x0;
    slab.x1 = s.x1;
    slabs.push_back(std::move(slab));
  }
  runChunked(slabs.size(), progress.sub(0.0, 0.85), "marching tetrahedra", [&](std::size_t s) {
    marchSlab(slabs[s], values, geometry, plan.h, plan.layerCount, levelBegin, levelEnd,
              plan.layerBits, flip);
  });

  // ---- merging layers ----
  runChunked(result.size(), progress.sub(0.85, 1.0), "merging layers", [&](std::size_t level) {
    result[level] = mergeLevel(slabs, level, geometry.strideX());
  });
  return result;
}

}  // namespace curvedslicer::layers_detail
