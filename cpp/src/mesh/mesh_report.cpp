// analyzeMesh: one sort of all half-edges by their undirected edge gives open, non-manifold and
// inconsistent edges; union-find over triangles sharing an edge gives the components.
#include "curvedslicer/mesh/mesh_report.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "mesh/mesh_checks.hpp"

namespace curvedslicer {

namespace {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];  // path halving
      x = parent_[x];
    }
    return x;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

struct HalfEdge {
  int lo, hi;    // undirected edge, lo < hi
  bool forward;  // traversed lo -> hi
  std::uint32_t triangle;
};

}  // namespace

MeshReport analyzeMesh(const TriMesh& mesh) {
  detail::requireValidMesh(mesh, "analyzeMesh");
  MeshReport report;
  report.vertices = mesh.vertices.size();
  report.triangles = mesh.triangles.size();
  report.bounds = mesh.bounds();
  report.area = surfaceArea(mesh);
  report.volume = signedVolume(mesh);

  const double minArea = detail::degenerateAreaThreshold(report.bounds.diagonal());
  std::vector<HalfEdge> halfEdges;
  halfEdges.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3i& tri = mesh.triangles[t];
    const bool repeated = tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0];
    if (repeated || mesh.triangleArea(t) < minArea) ++report.degenerateTriangles;
    for (int k = 0; k < 3; ++k) {
      const int a = tri[k], b = tri[(k + 1) % 3];
      if (a == b) continue;  // a collapsed edge joins nothing
      halfEdges.push_back({std::min(a, b), std::max(a, b), a < b, static_cast<std::uint32_t>(t)});
    }
  }
  std::sort(halfEdges.begin(), halfEdges.end(), [](const HalfEdge& p, const HalfEdge& q) {
    if (p.lo != q.lo) return p.lo < q.lo;
    if (p.hi != q.hi) return p.hi < q.hi;
    return p.triangle < q.triangle;
  });

  UnionFind components(mesh.triangles.size());
  for (std::size_t begin = 0; begin < halfEdges.size();) {
    std::size_t end = begin + 1;
    while (end < halfEdges.size() && halfEdges[end].lo == halfEdges[begin].lo &&
           halfEdges[end].hi == halfEdges[begin].hi) {
      components.unite(halfEdges[begin].triangle, halfEdges[end].triangle);
      ++end;
    }
    const std::size_t uses = end - begin;
    const bool inconsistent = uses == 2 && halfEdges[begin].forward == halfEdges[begin + 1].forward;
    report.openEdges += uses == 1;
    report.nonManifoldEdges += uses >= 3;
    report.inconsistentEdges += inconsistent;
    if (uses != 2 || inconsistent) {
      report.defectBounds.extend(mesh.vertices[halfEdges[begin].lo]);
      report.defectBounds.extend(mesh.vertices[halfEdges[begin].hi]);
    }
    begin = end;
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    report.components += components.find(t) == t;
  }
  return report;
}

}  // namespace curvedslicer
