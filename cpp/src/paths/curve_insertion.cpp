// Inserting initial curves into a triangle surface (see insertCurves in
// curvedslicer/paths/surface_geodesic.hpp).
//
// Every curve point is placed at its closest point on the surface; consecutive points are joined
// by tracing the segment across the triangles: from the current curve vertex u, the plane through
// u spanned by the segment direction and a fan triangle's normal cuts the edge opposite u at the
// next crossing, which becomes a vertex (edge split) unless it is within 1e-7 of the edge's
// length of an end. A new vertex on an edge of, or inside, a triangle incident to u is always
// joined to u by an edge, so the curve becomes a chain of mesh edges.
#include <algorithm>
#include <cmath>
#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"
#include "curvedslicer/paths/surface_geodesic.hpp"

namespace curvedslicer {

namespace {

constexpr double kSnap = 1e-7;  // relative (barycentric / edge parameter) snapping distance

std::string formatPoint(const Vec3& p) {
  return "(" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) +
         ")";
}

/// Closest point on triangle abc to p with its barycentric coordinates (Ericson RTCD §5.1.5).
struct TrianglePoint {
  Vec3 point;
  Vec3 bary;  // weights of a, b, c
};

TrianglePoint closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, Vec3(1, 0, 0)};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, Vec3(0, 1, 0)};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, Vec3(1 - v, v, 0)};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, Vec3(0, 0, 1)};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, Vec3(1 - w, 0, w)};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), Vec3(0, 1 - w, w)};
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0.0)) return {a, Vec3(1, 0, 0)};  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return {a + ab * v + ac * w, Vec3(1 - v - w, v, w)};
}

/// The mutable mesh used during insertion.
class CuttableMesh {
 public:
  explicit CuttableMesh(const TriMesh& mesh)
      : vertices_(mesh.vertices), triangles_(mesh.triangles), incident_(mesh.vertexCount()) {
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      for (int k = 0; k < 3; ++k) incident_[triangles_[t][k]].push_back(static_cast<int>(t));
    }
  }

  const std::vector<Vec3>& vertices() const { return vertices_; }
  const std::vector<Vec3i>& triangles() const { return triangles_; }
  const std::vector<int>& incident(std::int32_t v) const { return incident_[v]; }
  std::size_t added() const { return added_; }

  Vec3 corner(int t, int k) const { return vertices_[triangles_[t][k]]; }

  /// Inserts the surface point with barycentric `bary` in triangle t; returns its vertex.
  std::int32_t insertInTriangle(int t, const Vec3& bary, const Vec3& point) {
    const Vec3i tri = triangles_[t];
    for (int k = 0; k < 3; ++k) {
      if (bary[k] >= 1.0 - kSnap) return tri[k];
    }
    for (int k = 0; k < 3; ++k) {
      if (bary[k] <= kSnap) {
        const std::int32_t a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
        const double wa = bary[(k + 1) % 3], wb = bary[(k + 2) % 3];
        return splitEdge(a, b, wb / (wa + wb), point);
      }
    }
    const std::int32_t v = addVertex(point);
    replaceTriangle(t,
                    {Vec3i(tri[0], tri[1], v), Vec3i(tri[1], tri[2], v), Vec3i(tri[2], tri[0], v)});
    return v;
  }

  /// Splits edge (a, b) at parameter s (0 at a, 1 at b) unless within kSnap of an end.
  std::int32_t splitEdge(std::int32_t a, std::int32_t b, double s, const Vec3& point) {
    if (s <= kSnap) return a;
    if (s >= 1.0 - kSnap) return b;
    const std::int32_t v = addVertex(point);
    const std::vector<int> around = trianglesOfEdge(a, b);
    for (const int t : around) {
      const Vec3i tri = triangles_[t];
      int k = 0;
      while (!((tri[k] == a && tri[(k + 1) % 3] == b) || (tri[k] == b && tri[(k + 1) % 3] == a)))
        ++k;
      const std::int32_t p = tri[k], q = tri[(k + 1) % 3], r = tri[(k + 2) % 3];
      replaceTriangle(t, {Vec3i(p, v, r), Vec3i(v, q, r)});
    }
    return v;
  }

  std::vector<int> trianglesOfEdge(std::int32_t a, std::int32_t b) const {
    std::vector<int> result;
    for (const int t : incident_[a]) {
      const Vec3i& tri = triangles_[t];
      if (tri[0] == b || tri[1] == b || tri[2] == b) result.push_back(t);
    }
    return result;
  }

  TriMesh toMesh() && {
    TriMesh mesh;
    mesh.vertices = std::move(vertices_);
    mesh.triangles = std::move(triangles_);
    return mesh;
  }

 private:
  std::int32_t addVertex(const Vec3& p) {
    vertices_.push_back(p);
    incident_.emplace_back();
    ++added_;
    return static_cast<std::int32_t>(vertices_.size() - 1);
  }

  void replaceTriangle(int t, std::initializer_list<Vec3i> pieces) {
    for (int k = 0; k < 3; ++k) {
      auto& list = incident_[triangles_[t][k]];
      list.erase(std::remove(list.begin(), list.end(), t), list.end());
    }
    bool first = true;
    for (const Vec3i& piece : pieces) {
      int index = t;
      if (first) {
        triangles_[t] = piece;
        first = false;
      } else {
        index = static_cast<int>(triangles_.size());
        triangles_.push_back(piece);
      }
      for (int k = 0; k < 3; ++k) incident_[piece[k]].push_back(index);
    }
  }

  std::vector<Vec3> vertices_;
  std::vector<Vec3i> triangles_;
  std::vector<std::vector<int>> incident_;
  std::size_t added_ = 0;
};

/// Closest point of q over the triangles incident to v: (triangle, closest point).
std::pair<int, TrianglePoint> closestInFan(const CuttableMesh& mesh, std::int32_t v, const Vec3& q,
                                           double& distance) {
  int best = -1;
  TrianglePoint bestPoint{Vec3::Zero(), Vec3::Zero()};
  distance = kInf;
  for (const int t : mesh.incident(v)) {
    const TrianglePoint tp =
        closestOnTriangle(q, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2));
    const double d = (tp.point - q).norm();
    if (d < distance) {
      distance = d;
      best = t;
      bestPoint = tp;
    }
  }
  return {best, bestPoint};
}

void checkInsertionInputs(const TriMesh& surface, double curveTolerance) {
  if (surface.empty()) {
    throw InvalidInput("layer surface is empty: 0 triangles; pass a surface with triangles");
  }
  if (!(curveTolerance >= 0.0) || !std::isfinite(curveTolerance)) {
    throw InvalidInput("initial-curve tolerance must be non-negative and finite: " +
                       std::to_string(curveTolerance) + " mm; pass a value such as 0.05");
  }
  for (const Vec3& v : surface.vertices) {
    if (!v.allFinite()) {
      throw InvalidInput("layer surface has a non-finite vertex: " + formatPoint(v) +
                         "; repair the surface");
    }
  }
}

/// Surface distance of every curve point (tolerance check); returns the largest.
double measureCurveDeviation(const TriangleBvh& bvh, const std::vector<Polyline>& curves,
                             double curveTolerance) {
  double deviation = 0.0;
  for (const Polyline& curve : curves) {
    for (const Vec3& q : curve.points) {
      if (!q.allFinite()) {
        throw InvalidInput("initial curve has a non-finite point: " + formatPoint(q) +
                           "; pass finite coordinates");
      }
      const double d = bvh.closestPoint(q).distance;
      deviation = std::max(deviation, d);
      if (d > curveTolerance) {
        throw InvalidInput("initial curve is not on the layer surface: point " + formatPoint(q) +
                           " is " + std::to_string(d) + " mm away (tolerance " +
                           std::to_string(curveTolerance) +
                           " mm); pass a curve on the surface or raise the tolerance");
      }
    }
  }
  return deviation;
}

/// Traces curves over a cuttable mesh, inserting their points and the crossings of their
/// segments with the mesh edges as vertices.
class CurveTracer {
 public:
  CurveTracer(const TriMesh& surface, const TriangleBvh& bvh)
      : bvh_(bvh),
        mesh_(surface),
        scale_(std::max(surface.bounds().diagonal(), 1e-300)),
        maxSteps_(8 * surface.triangleCount() + 1000) {}

  void trace(const Polyline& curve);
  CurveInsertion finish(double maxCurveDeviation) &&;

 private:
  std::int32_t insertFirstPoint(const Vec3& first);
  std::int32_t traceSegment(std::int32_t u, const Vec3& q);
  std::int32_t crossNextEdge(std::int32_t u, const Vec3& q);

  const TriangleBvh& bvh_;  // the original surface: the reference for "Q is reached"
  CuttableMesh mesh_;
  const double scale_;
  const std::size_t maxSteps_;
  std::size_t steps_ = 0;
  std::vector<std::int32_t> onCurve_;
};

void CurveTracer::trace(const Polyline& curve) {
  if (curve.points.empty()) return;
  std::int32_t u = insertFirstPoint(curve.points.front());
  const std::size_t segmentCount =
      curve.closed && curve.points.size() >= 3 ? curve.points.size() : curve.points.size() - 1;
  for (std::size_t i = 0; i < segmentCount; ++i) {
    u = traceSegment(u, curve.points[(i + 1) % curve.points.size()]);
  }
}

/// First point: global location.
std::int32_t CurveTracer::insertFirstPoint(const Vec3& first) {
  int bestTriangle = -1;
  TrianglePoint bestPoint{Vec3::Zero(), Vec3::Zero()};
  double bestDistance = kInf;
  for (std::size_t t = 0; t < mesh_.triangles().size(); ++t) {
    const int ti = static_cast<int>(t);
    const TrianglePoint tp =
        closestOnTriangle(first, mesh_.corner(ti, 0), mesh_.corner(ti, 1), mesh_.corner(ti, 2));
    const double d = (tp.point - first).squaredNorm();
    if (d < bestDistance) {
      bestDistance = d;
      bestTriangle = ti;
      bestPoint = tp;
    }
  }
  const std::int32_t u = mesh_.insertInTriangle(bestTriangle, bestPoint.bary, bestPoint.point);
  onCurve_.push_back(u);
  return u;
}

/// From vertex u to the curve point q; returns q's vertex.
std::int32_t CurveTracer::traceSegment(std::int32_t u, const Vec3& q) {
  const double qSurface = bvh_.closestPoint(q).distance;
  const double reach = qSurface + 1e-9 * scale_;
  for (;;) {
    if (++steps_ > maxSteps_) {
      throw NumericalFailure("initial curve could not be traced on the surface: segment to " +
                             formatPoint(q) +
                             " did not arrive; check that the curve does not jump between "
                             "separate parts of the layer");
    }
    double fanDistance = kInf;
    const auto [t, tp] = closestInFan(mesh_, u, q, fanDistance);
    if (t >= 0 && fanDistance <= reach) {
      u = mesh_.insertInTriangle(t, tp.bary, tp.point);
      onCurve_.push_back(u);
      return u;
    }
    u = crossNextEdge(u, q);
    onCurve_.push_back(u);
  }
}

/// Next crossing of the segment plane with an edge opposite u, inserted as a vertex.
std::int32_t CurveTracer::crossNextEdge(std::int32_t u, const Vec3& q) {
  const Vec3 p = mesh_.vertices()[u];
  const Vec3 dir = q - p;
  double bestCos = -kInf;
  std::int32_t ea = -1, eb = -1;
  double es = 0.0;
  Vec3 ex = Vec3::Zero();
  for (const int ft : mesh_.incident(u)) {
    const Vec3i tri = mesh_.triangles()[ft];
    int k = 0;
    while (tri[k] != u) ++k;
    const std::int32_t a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
    const Vec3& pa = mesh_.vertices()[a];
    const Vec3& pb = mesh_.vertices()[b];
    const Vec3 normal = (pa - p).cross(pb - p);
    const Vec3 m = dir.cross(normal);
    const double sa = m.dot(pa - p), sb = m.dot(pb - p);
    if ((sa > 0 && sb > 0) || (sa < 0 && sb < 0) || sa == sb) continue;
    const double s = sa / (sa - sb);
    const Vec3 x = pa + s * (pb - pa);
    const Vec3 step = x - p;
    const double len = step.norm();
    if (!(len > 0.0)) continue;
    const double cosine = step.dot(dir) / (len * dir.norm());
    if (cosine > bestCos) {
      bestCos = cosine;
      ea = a;
      eb = b;
      es = s;
      ex = x;
    }
  }
  if (ea < 0 || bestCos <= 0.0) {
    throw NumericalFailure(
        "initial curve could not be traced on the surface: no way forward towards " +
        formatPoint(q) + " (" + std::to_string(dir.norm()) +
        " mm away); check that the curve stays on the layer and does not cross its boundary");
  }
  const std::int32_t next = mesh_.splitEdge(ea, eb, es, ex);
  if (next == u) {
    throw NumericalFailure("initial curve could not be traced on the surface: stalled at " +
                           formatPoint(p) + "; check the curve for degenerate segments");
  }
  return next;
}

CurveInsertion CurveTracer::finish(double maxCurveDeviation) && {
  CurveInsertion result;
  result.maxCurveDeviation = maxCurveDeviation;
  result.insertedVertices = mesh_.added();
  result.mesh = std::move(mesh_).toMesh();
  std::sort(onCurve_.begin(), onCurve_.end());
  onCurve_.erase(std::unique(onCurve_.begin(), onCurve_.end()), onCurve_.end());
  result.curveVertices = std::move(onCurve_);
  return result;
}

}  // namespace

CurveInsertion insertCurves(const TriMesh& surface, const std::vector<Polyline>& curves,
                            double curveTolerance) {
  checkInsertionInputs(surface, curveTolerance);
  const TriangleBvh bvh(surface);
  const double deviation = measureCurveDeviation(bvh, curves, curveTolerance);
  CurveTracer tracer(surface, bvh);
  for (const Polyline& curve : curves) tracer.trace(curve);
  return std::move(tracer).finish(deviation);
}

}  // namespace curvedslicer
