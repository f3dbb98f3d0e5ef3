// TriangleBvh: CGAL AABB tree facade. See the header for the method.
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"

#include <CGAL/version.h>
// CGAL 6 renamed the AABB traits and primitive to their _3 names (the old headers are deprecated).
#if CGAL_VERSION_MAJOR >= 6
#include <CGAL/AABB_traits_3.h>
#include <CGAL/AABB_triangle_primitive_3.h>
#else
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_triangle_primitive.h>
#endif
#include <CGAL/AABB_tree.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <variant>
#include <vector>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {
namespace {

using K = CGAL::Simple_cartesian<double>;
using CgalPoint = K::Point_3;
using CgalTriangle = K::Triangle_3;
using TriangleIterator = std::vector<CgalTriangle>::const_iterator;
#if CGAL_VERSION_MAJOR >= 6
using Primitive = CGAL::AABB_triangle_primitive_3<K, TriangleIterator>;
using Traits = CGAL::AABB_traits_3<K, Primitive>;
#else
using Primitive = CGAL::AABB_triangle_primitive<K, TriangleIterator>;
using Traits = CGAL::AABB_traits<K, Primitive>;
#endif
using Tree = CGAL::AABB_tree<Traits>;

/// The alternative T of an intersection result, or null: CGAL 6 returns std::variant, CGAL 5 a
/// boost::variant.
template <class T, class Variant>
const T* alternativeOf(const Variant& result) {
#if CGAL_VERSION_MAJOR >= 6
  return std::get_if<T>(&result);
#else
  return boost::get<T>(&result);
#endif
}

CgalPoint toCgal(const Vec3& p) {
  return CgalPoint(p.x(), p.y(), p.z());
}
Vec3 fromCgal(const CgalPoint& p) {
  return Vec3(p.x(), p.y(), p.z());
}

/// Voronoi region of a triangle (a, b, c) that holds the closest point.
enum class Region { Face, VertexA, VertexB, VertexC, EdgeAB, EdgeBC, EdgeCA };

/// Closest point on triangle (a, b, c) to p and the region it lies in (Ericson, Real-Time
/// Collision Detection, §5.1.5; barycentric region tests).
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Region& region) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    region = Region::VertexA;
    return a;
  }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    region = Region::VertexB;
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    region = Region::EdgeAB;
    return a + (d1 / (d1 - d3)) * ab;
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    region = Region::VertexC;
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    region = Region::EdgeCA;
    return a + (d2 / (d2 - d6)) * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    region = Region::EdgeBC;
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  region = Region::Face;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double angleBetween(const Vec3& u, const Vec3& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

struct TriangleBvh::Impl {
  std::vector<Vec3> vertices;            // copy of the mesh vertices
  std::vector<Vec3i> triangles;          // copy of the mesh triangles
  std::vector<CgalTriangle> primitives;  // kept (non-degenerate) triangles
  std::vector<int> original;             // primitive -> mesh triangle index
  std::vector<int> primitiveOf;          // mesh triangle -> primitive (-1 if degenerate)
  // Built on the first signed-distance query, per primitive: unit face normal, edge
  // pseudo-normals (edges ab, bc, ca) and welded vertex ids.
  std::vector<Vec3> faceNormal;
  std::vector<std::array<Vec3, 3>> edgeNormal;
  std::vector<std::array<int, 3>> weldedCorner;
  std::vector<Vec3> vertexNormal;  // per welded vertex
  Aabb box;
  Tree tree;

  Impl(const TriMesh& mesh, const TriangleBvhOptions& options)
      : vertices(mesh.vertices), triangles(mesh.triangles) {
    const auto nv = static_cast<int>(vertices.size());
    for (std::size_t v = 0; v < vertices.size(); ++v) {
      if (!vertices[v].allFinite()) {
        std::ostringstream msg;
        msg << "mesh vertex " << v << " has a non-finite coordinate; repair the mesh first";
        throw InvalidInput(msg.str());
      }
    }
    primitiveOf.assign(triangles.size(), -1);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      const Vec3i& tri = triangles[t];
      if ((tri.array() < 0).any() || (tri.array() >= nv).any()) {
        std::ostringstream msg;
        msg << "triangle " << t << " has a vertex index out of range [0, " << nv
            << "): " << tri.transpose() << "; repair the mesh first";
        throw InvalidInput(msg.str());
      }
      const Vec3 n = mesh.areaNormal(t);
      const double n2 = n.squaredNorm();
      if (!(n2 > 0.0) || !std::isfinite(n2)) continue;
      primitiveOf[t] = static_cast<int>(original.size());
      original.push_back(static_cast<int>(t));
      primitives.emplace_back(toCgal(vertices[tri[0]]), toCgal(vertices[tri[1]]),
                              toCgal(vertices[tri[2]]));
      for (int k = 0; k < 3; ++k) box.extend(vertices[tri[k]]);
    }
    if (!primitives.empty()) {
      tree.insert(primitives.cbegin(), primitives.cend());
      tree.build();
      if (options.searchTree) {
        tree.accelerate_distance_queries();  // builds the k-d tree now: queries stay const
      } else {
        tree.do_not_accelerate_distance_queries();
      }
    }
  }

  // Welds vertices with identical coordinates, then accumulates angle-weighted vertex normals and
  // edge normals over the kept triangles.
  // Pseudo-normals are built on the first signed-distance query (thread-safe), so hierarchies
  // used only for unsigned distances do not pay for them.
  std::once_flag pseudoNormalsOnce;
  void ensurePseudoNormals() {
    std::call_once(pseudoNormalsOnce, [this] { buildPseudoNormals(); });
  }

  void buildPseudoNormals() {
    // Weld by position (STL soups repeat vertices), numbering the distinct positions 0, 1, …
    const std::vector<int> rep = findExactDuplicateVertices(vertices);
    std::vector<int> weld(vertices.size(), -1);
    int welded = -1;
    for (std::size_t i = 0; i < rep.size(); ++i)
      weld[i] = rep[i] == static_cast<int>(i) ? ++welded : weld[static_cast<std::size_t>(rep[i])];
    vertexNormal.assign(static_cast<std::size_t>(welded + 1), Vec3::Zero());

    std::unordered_map<std::uint64_t, Vec3> edgeSum;
    edgeSum.reserve(original.size() * 2);
    auto edgeKey = [](int a, int b) {
      if (a > b) std::swap(a, b);
      return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
    };
    weldedCorner.resize(original.size());
    faceNormal.resize(original.size());
    for (std::size_t p = 0; p < original.size(); ++p) {
      const Vec3i& tri = triangles[original[p]];
      faceNormal[p] = (vertices[tri[1]] - vertices[tri[0]])
                          .cross(vertices[tri[2]] - vertices[tri[0]])
                          .normalized();
      const Vec3& n = faceNormal[p];
      for (int k = 0; k < 3; ++k) {
        const int v = tri[k], vn = tri[(k + 1) % 3], vp = tri[(k + 2) % 3];
        weldedCorner[p][k] = weld[v];
        const double angle = angleBetween(vertices[vn] - vertices[v], vertices[vp] - vertices[v]);
        vertexNormal[weld[v]] += angle * n;
        // Eigen vectors are not zero-initialised by default construction.
        edgeSum.try_emplace(edgeKey(weld[v], weld[vn]), Vec3::Zero()).first->second += n;
      }
    }
    edgeNormal.resize(original.size());
    for (std::size_t p = 0; p < original.size(); ++p) {
      for (int k = 0; k < 3; ++k) {
        edgeNormal[p][k] = edgeSum.at(edgeKey(weldedCorner[p][k], weldedCorner[p][(k + 1) % 3]));
      }
    }
  }

  int primitiveIndex(TriangleIterator it) const {
    return static_cast<int>(it - primitives.cbegin());
  }

  // Closest point via the tree, refined on the returned triangle (for the region).
  // A usable hint is a point on the surface with its (non-degenerate) triangle.
  ClosestPoint closest(const Vec3& p, const ClosestPoint* hint, Region* regionOut,
                       int* primitiveOut) const {
    ClosestPoint result;
    if (primitives.empty()) return result;
    const int hintPrim =
        hint && hint->triangle >= 0 && static_cast<std::size_t>(hint->triangle) < primitiveOf.size()
            ? primitiveOf[hint->triangle]
            : -1;
    const auto hit =
        hintPrim >= 0
            ? tree.closest_point_and_primitive(
                  toCgal(p), std::make_pair(toCgal(hint->point), primitives.cbegin() + hintPrim))
            : tree.closest_point_and_primitive(toCgal(p));
    const int prim = primitiveIndex(hit.second);
    const Vec3i& tri = triangles[original[prim]];
    Region region = Region::Face;
    result.point =
        closestOnTriangle(p, vertices[tri[0]], vertices[tri[1]], vertices[tri[2]], region);
    result.triangle = original[prim];
    result.distance = (p - result.point).norm();
    if (regionOut) *regionOut = region;
    if (primitiveOut) *primitiveOut = prim;
    return result;
  }

  const Vec3& pseudoNormal(int prim, Region region) const {
    switch (region) {
      case Region::VertexA:
        return vertexNormal[weldedCorner[prim][0]];
      case Region::VertexB:
        return vertexNormal[weldedCorner[prim][1]];
      case Region::VertexC:
        return vertexNormal[weldedCorner[prim][2]];
      case Region::EdgeAB:
        return edgeNormal[prim][0];
      case Region::EdgeBC:
        return edgeNormal[prim][1];
      case Region::EdgeCA:
        return edgeNormal[prim][2];
      case Region::Face:
        break;
    }
    return faceNormal[prim];
  }
};

TriangleBvh::TriangleBvh() : impl_(std::make_unique<Impl>(TriMesh{}, TriangleBvhOptions{})) {}
TriangleBvh::TriangleBvh(const TriMesh& mesh, const TriangleBvhOptions& options)
    : impl_(std::make_unique<Impl>(mesh, options)) {}
TriangleBvh::~TriangleBvh() = default;
TriangleBvh::TriangleBvh(TriangleBvh&&) noexcept = default;
TriangleBvh& TriangleBvh::operator=(TriangleBvh&&) noexcept = default;

bool TriangleBvh::empty() const {
  return impl_->primitives.empty();
}
std::size_t TriangleBvh::triangleCount() const {
  return impl_->primitives.size();
}
Aabb TriangleBvh::bounds() const {
  return impl_->box;
}

ClosestPoint TriangleBvh::closestPoint(const Vec3& p) const {
  return impl_->closest(p, nullptr, nullptr, nullptr);
}

ClosestPoint TriangleBvh::closestPoint(const Vec3& p, const ClosestPoint& hint) const {
  return impl_->closest(p, &hint, nullptr, nullptr);
}

double TriangleBvh::distance(const Vec3& p) const {
  return closestPoint(p).distance;
}

double TriangleBvh::signedDistance(const Vec3& p, ClosestPoint* closest) const {
  return signedDistance(p, ClosestPoint{}, closest);
}

double TriangleBvh::signedDistance(const Vec3& p, const ClosestPoint& hint,
                                   ClosestPoint* closest) const {
  Region region = Region::Face;
  int prim = -1;
  const ClosestPoint c = impl_->closest(p, &hint, &region, &prim);
  if (closest) *closest = c;
  if (prim < 0) return kInf;
  if (c.distance == 0.0) return 0.0;
  impl_->ensurePseudoNormals();
  const double side = (p - c.point).dot(impl_->pseudoNormal(prim, region));
  return side < 0.0 ? -c.distance : c.distance;
}

std::optional<RayHit> TriangleBvh::firstRayHit(const Vec3& origin, const Vec3& direction,
                                               double maxT) const {
  const double d2 = direction.squaredNorm();
  if (impl_->primitives.empty() || !(d2 > 0.0) || !origin.allFinite() || !direction.allFinite()) {
    return std::nullopt;
  }
  const K::Ray_3 ray(toCgal(origin), K::Vector_3(direction.x(), direction.y(), direction.z()));
  const auto hit = impl_->tree.first_intersection(ray);
  if (!hit) return std::nullopt;
  RayHit result;
  result.triangle = impl_->original[impl_->primitiveIndex(hit->second)];
  auto paramOf = [&](const CgalPoint& q) { return (fromCgal(q) - origin).dot(direction) / d2; };
  if (const CgalPoint* q = alternativeOf<CgalPoint>(hit->first)) {
    result.point = fromCgal(*q);
    result.t = paramOf(*q);
  } else if (const K::Segment_3* s = alternativeOf<K::Segment_3>(hit->first)) {
    // Ray in the triangle's plane: the entry point is the segment end nearer the origin.
    const double t0 = paramOf(s->source()), t1 = paramOf(s->target());
    result.point = fromCgal(t0 <= t1 ? s->source() : s->target());
    result.t = std::min(t0, t1);
  } else {
    return std::nullopt;
  }
  result.t = std::max(result.t, 0.0);
  if (result.t > maxT) return std::nullopt;
  return result;
}

bool TriangleBvh::intersectsBox(const Aabb& box) const {
  if (impl_->primitives.empty() || box.empty()) return false;
  const CGAL::Bbox_3 query(box.min.x(), box.min.y(), box.min.z(), box.max.x(), box.max.y(),
                           box.max.z());
  return impl_->tree.do_intersect(query);
}

}  // namespace curvedslicer
