// Layer surface simplification: CGAL edge collapse with a distance filter, border fixed. See the
// header for the method and the bound.
#include "curvedslicer/layers/layer_simplification.hpp"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Constrained_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_ratio_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_placement.h>
#include <CGAL/Surface_mesh_simplification/Edge_collapse_visitor_base.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"

namespace curvedslicer {
namespace {

namespace SMS = CGAL::Surface_mesh_simplification;
using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = Mesh::Vertex_index;
using EdgeIndex = Mesh::Edge_index;

std::string formatNumber(double x) {
  std::ostringstream s;
  s.precision(10);
  s << x;
  return s.str();
}

/// The input with every non-manifold vertex split into one vertex per fan of triangles (corners
/// joined through shared edges). `original[v]` is the input vertex of vertex v; `split[v]` is true
/// for every copy, the first one included.
struct SplitSurface {
  std::vector<Vec3i> triangles;
  std::vector<int> original;
  std::vector<char> split;
};

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

SplitSurface splitNonManifoldVertices(const TriMesh& surface) {
  const auto nv = static_cast<int>(surface.vertices.size());
  const auto nt = static_cast<int>(surface.triangles.size());
  // Corners (3·t + k) grouped by vertex (CSR).
  std::vector<int> first(static_cast<std::size_t>(nv) + 1, 0);
  for (const Vec3i& t : surface.triangles) {
    for (int k = 0; k < 3; ++k) ++first[static_cast<std::size_t>(t[k]) + 1];
  }
  std::partial_sum(first.begin(), first.end(), first.begin());
  std::vector<int> corners(static_cast<std::size_t>(3 * nt));
  std::vector<int> fill(first.begin(), first.end() - 1);
  for (int t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) corners[fill[surface.triangles[t][k]]++] = 3 * t + k;
  }
  SplitSurface out;
  out.triangles = surface.triangles;
  out.original.resize(static_cast<std::size_t>(nv));
  std::iota(out.original.begin(), out.original.end(), 0);
  out.split.assign(static_cast<std::size_t>(nv), 0);
  std::vector<int> parent;
  std::unordered_map<int, int> byNeighbour;
  for (int v = 0; v < nv; ++v) {
    const int begin = first[v], end = first[v + 1];
    if (end - begin < 2) continue;
    parent.resize(static_cast<std::size_t>(end - begin));
    std::iota(parent.begin(), parent.end(), 0);
    byNeighbour.clear();
    for (int c = begin; c < end; ++c) {
      const int t = corners[c] / 3, k = corners[c] % 3;
      for (int other : {surface.triangles[t][(k + 1) % 3], surface.triangles[t][(k + 2) % 3]}) {
        auto [it, inserted] = byNeighbour.try_emplace(other, c - begin);
        if (!inserted) parent[findRoot(parent, c - begin)] = findRoot(parent, it->second);
      }
    }
    const int root0 = findRoot(parent, 0);
    bool manifold = true;
    for (int c = begin; c < end && manifold; ++c) manifold = findRoot(parent, c - begin) == root0;
    if (manifold) continue;
    // One vertex per fan: the fan of the first corner keeps v, the others get copies.
    out.split[static_cast<std::size_t>(v)] = 1;
    std::unordered_map<int, int> copyOfRoot{{root0, v}};
    for (int c = begin; c < end; ++c) {
      const int root = findRoot(parent, c - begin);
      auto [it, inserted] = copyOfRoot.try_emplace(root, static_cast<int>(out.original.size()));
      if (inserted) {
        out.original.push_back(v);
        out.split.push_back(1);
      }
      out.triangles[corners[c] / 3][corners[c] % 3] = it->second;
    }
  }
  return out;
}

/// The split surface as a CGAL halfedge mesh; false if a triangle cannot be added (an edge of
/// more than two triangles or inconsistent orientation).
bool buildMesh(const TriMesh& surface, const SplitSurface& split, Mesh& mesh) {
  mesh.reserve(split.original.size(), 3 * split.triangles.size() / 2 + 3,
               split.triangles.size());
  for (int v : split.original) {
    const Vec3& p = surface.vertices[static_cast<std::size_t>(v)];
    mesh.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z()));
  }
  for (const Vec3i& t : split.triangles) {
    const Mesh::Face_index f =
        mesh.add_face(VertexIndex(static_cast<Mesh::size_type>(t[0])),
                      VertexIndex(static_cast<Mesh::size_type>(t[1])),
                      VertexIndex(static_cast<Mesh::size_type>(t[2])));
    if (f == Mesh::null_face()) return false;
  }
  return true;
}

/// Border edges and every edge of a split vertex: never collapsed; their vertices never move.
std::size_t constrainBorder(const Mesh& mesh, const SplitSurface& split,
                            Mesh::Property_map<EdgeIndex, bool>& constrained) {
  std::vector<char> fixed(mesh.number_of_vertices(), 0);
  for (EdgeIndex e : mesh.edges()) {
    const VertexIndex a = mesh.vertex(e, 0), b = mesh.vertex(e, 1);
    const bool keep = mesh.is_border(e) || split.split[a.idx()] != 0 || split.split[b.idx()] != 0;
    constrained[e] = keep;
    if (keep) fixed[a.idx()] = fixed[b.idx()] = 1;
  }
  return static_cast<std::size_t>(std::count(fixed.begin(), fixed.end(), 1));
}

/// The remaining vertices and faces in index order; copies of a split vertex welded again.
TriMesh collectResult(const Mesh& mesh, const SplitSurface& split, std::size_t inputVertices) {
  TriMesh out;
  std::vector<int> newIndex(inputVertices, -1);
  std::vector<int> byMeshVertex(mesh.num_vertices(), -1);
  for (VertexIndex v : mesh.vertices()) {
    const int original = split.original[v.idx()];
    int& id = newIndex[static_cast<std::size_t>(original)];
    if (id < 0) {
      id = static_cast<int>(out.vertices.size());
      const Kernel::Point_3& p = mesh.point(v);
      out.vertices.emplace_back(p.x(), p.y(), p.z());
    }
    byMeshVertex[v.idx()] = id;
  }
  out.triangles.reserve(mesh.number_of_faces());
  for (Mesh::Face_index f : mesh.faces()) {
    Vec3i t;
    int k = 0;
    for (VertexIndex v : mesh.vertices_around_face(mesh.halfedge(f))) t[k++] = byMeshVertex[v.idx()];
    out.triangles.push_back(t);
  }
  return out;
}

Vec3 toVec(const Kernel::Point_3& p) { return Vec3(p.x(), p.y(), p.z()); }

/// Points sampled inside new triangles must lie within this share of ε: the samples are a third of
/// an edge apart, and the surface between them can bulge a little further out.
constexpr double kInteriorShare = 0.75;

/// New triangles must have |a × b| above kMinSine times their longest edge squared (angles not
/// within about 1e-6 rad of 0 or π).
constexpr double kMinSine = 1e-6;

/// A new triangle's normal must stay within acos(kMinNormalCosine) = 60° of the normal of the
/// triangle it replaces.
constexpr double kMinNormalCosine = 0.5;

/// Per vertex: its closest point on the full surface (a search hint for nearby queries).
using HintMap = Mesh::Property_map<VertexIndex, ClosestPoint>;

/// Accepts a collapse only if the placement lies within ε of the full surface and the points of
/// the barycentric grid of step 1/3 on every triangle the collapse creates within kInteriorShare·ε
/// (closest-point queries, each started from the answer before it). Records the placement's closest point for
/// the visitor, which stores it on the surviving vertex once the collapse is done.
class DistanceFilter {
 public:
  DistanceFilter(const TriangleBvh& full, double epsilon, HintMap hints)
      : full_(full), epsilon_(epsilon), hints_(hints) {}

  template <class Profile>
  boost::optional<Kernel::Point_3> operator()(const Profile& profile,
                                              boost::optional<Kernel::Point_3> placement) const {
    if (!placement) return placement;
    const Vec3 p = toVec(*placement);
    ClosestPoint hint = full_.closestPoint(p, hints_[profile.v0()]);
    if (hint.distance > epsilon_) return boost::none;
    pending_ = hint;
    const auto v0 = profile.v0(), v1 = profile.v1();
    const auto& vpm = profile.vertex_point_map();
    for (const auto& t : profile.triangles()) {
      std::array<VertexIndex, 3> ids = {t.v0, t.v1, t.v2};
      if (std::count(ids.begin(), ids.end(), v0) + std::count(ids.begin(), ids.end(), v1) == 2) {
        continue;  // removed by the collapse
      }
      std::array<Vec3, 3> corners;
      int moved = 0;
      for (int k = 0; k < 3; ++k) {
        const bool isMoved = ids[k] == v0 || ids[k] == v1;
        corners[k] = isMoved ? p : toVec(get(vpm, ids[k]));
        if (isMoved) moved = k;
      }
      // No new sliver of (nearly) zero area, e.g. three rim vertices on a straight rim.
      const Vec3 normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
      const double longest = std::max({(corners[1] - corners[0]).squaredNorm(),
                                       (corners[2] - corners[1]).squaredNorm(),
                                       (corners[0] - corners[2]).squaredNorm()});
      if (!(normal.squaredNorm() > kMinSine * kMinSine * longest * longest)) return boost::none;
      // Nor one turned far from the triangle it replaces (e.g. standing up on a curved rim).
      std::array<Vec3, 3> before = corners;
      before[moved] = toVec(get(vpm, ids[moved]));
      const Vec3 oldNormal = (before[1] - before[0]).cross(before[2] - before[0]);
      if (!(normal.dot(oldNormal) > kMinNormalCosine * normal.norm() * oldNormal.norm())) {
        return boost::none;
      }
      // The barycentric grid of step 1/3 on the triangle, but for its two unmoved corners.
      const Vec3& a = corners[moved];
      const Vec3& b = corners[(moved + 1) % 3];
      const Vec3& c = corners[(moved + 2) % 3];
      for (int i = 0; i <= 3; ++i) {
        for (int j = 0; i + j <= 3; ++j) {
          if ((i == 3 && j == 0) || (i == 0 && j == 3) || (i == 0 && j == 0)) continue;
          const Vec3 q = a + (i / 3.0) * (b - a) + (j / 3.0) * (c - a);
          hint = full_.closestPoint(q, hint);
          if (hint.distance > kInteriorShare * epsilon_) return boost::none;
        }
      }
    }
    return placement;
  }

  const ClosestPoint& pending() const { return pending_; }

 private:
  const TriangleBvh& full_;
  double epsilon_;
  HintMap hints_;
  mutable ClosestPoint pending_;
};

/// Stores the placement's closest point on the vertex that survives a collapse.
struct HintVisitor : SMS::Edge_collapse_visitor_base<Mesh> {
  HintVisitor(const DistanceFilter& filter, HintMap hints) : filter_(&filter), hints_(hints) {}
  template <class Profile>
  void OnCollapsed(const Profile&, VertexIndex survivor) {
    hints_[survivor] = filter_->pending();
  }
  const DistanceFilter* filter_;
  HintMap hints_;
};

/// Each vertex's hint: itself, on one of its input triangles.
HintMap addHints(Mesh& mesh, const TriMesh& surface, const SplitSurface& split) {
  HintMap hints = mesh.add_property_map<VertexIndex, ClosestPoint>("v:hint").first;
  for (std::size_t t = 0; t < split.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      ClosestPoint& h = hints[VertexIndex(static_cast<Mesh::size_type>(split.triangles[t][k]))];
      h.triangle = static_cast<int>(t);
      h.point = surface.vertices[static_cast<std::size_t>(split.original[split.triangles[t][k]])];
      h.distance = 0.0;
    }
  }
  return hints;
}

}  // namespace

double resolveLayerTolerance(const LayerSimplificationOptions& options, double voxelSize) {
  if (!(options.tolerance >= 0.0) || !std::isfinite(options.tolerance)) {
    throw InvalidInput("layer tolerance must be positive: " + formatNumber(options.tolerance) +
                       " mm; pass a finite value such as 0.05 times the voxel size, or 0 for "
                       "that default");
  }
  return options.tolerance > 0.0 ? options.tolerance : kDefaultLayerToleranceVoxels * voxelSize;
}

SimplifiedSurface simplifyLayerSurface(const TriMesh& surface, double tolerance) {
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) {
    throw InvalidInput("layer tolerance must be positive: " + formatNumber(tolerance) +
                       " mm; pass a finite value such as 0.025");
  }
  SimplifiedSurface result;
  result.trianglesBefore = surface.triangleCount();
  result.verticesBefore = surface.vertexCount();
  const SplitSurface split = splitNonManifoldVertices(surface);
  Mesh mesh;
  if (surface.empty() || !buildMesh(surface, split, mesh)) {
    result.mesh = surface;
    result.keptFull = !surface.empty();
    result.trianglesAfter = result.trianglesBefore;
    result.verticesAfter = result.verticesBefore;
    return result;
  }
  auto constrained = mesh.add_property_map<EdgeIndex, bool>("e:constrained", false).first;
  result.fixedVertices = constrainBorder(mesh, split, constrained);

  const TriangleBvh full(surface);
  const HintMap hints = addHints(mesh, surface, split);
  using Placement = SMS::Constrained_placement<SMS::LindstromTurk_placement<Mesh>,
                                               Mesh::Property_map<EdgeIndex, bool>>;
  const SMS::Count_ratio_stop_predicate<Mesh> never(0.0);  // the distance filter decides
  const DistanceFilter filter(full, tolerance, hints);
  HintVisitor visitor(filter, hints);
  SMS::edge_collapse(mesh, never,
                     CGAL::parameters::edge_is_constrained_map(constrained)
                         .get_cost(SMS::LindstromTurk_cost<Mesh>())
                         .get_placement(Placement(constrained))
                         .filter(std::cref(filter))
                         .visitor(visitor));

  result.mesh = collectResult(mesh, split, surface.vertexCount());
  result.trianglesAfter = result.mesh.triangleCount();
  result.verticesAfter = result.mesh.vertexCount();
  return result;
}

}  // namespace curvedslicer
