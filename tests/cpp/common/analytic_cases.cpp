#include "common/analytic_cases.hpp"

#include <cmath>

#include "common/shapes.hpp"

namespace curvedslicer::testing {

namespace {

TriMesh rectangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  TriMesh m;
  m.vertices = {a, b, c, d};
  m.triangles = {Vec3i(0, 1, 2), Vec3i(0, 2, 3)};
  return m;
}

}  // namespace

VoxelGrid makeGridFromPredicate(const Aabb& box, double L,
                                const std::function<bool(const Vec3&)>& inside) {
  VoxelGrid grid;
  GridGeometry& g = grid.geometry;
  g.voxelSize = L;
  g.corner = box.min.array() - 2 * L;
  g.dims = ((box.size().array() / L).ceil() + 4).cast<int>();
  grid.inside.assign(g.cellCount(), 0);
  for (int i = 0; i < g.dims.x(); ++i)
    for (int j = 0; j < g.dims.y(); ++j)
      for (int k = 0; k < g.dims.z(); ++k) {
        const std::size_t n = g.index(i, j, k);
        if (inside(g.centerInPart(Vec3i(i, j, k)))) {
          grid.inside[n] = 1;
          ++grid.insideCount;
        }
      }
  return grid;
}

AnalyticCase makeTiltedSlabCase(int cells) {
  // Slab 60 x 44 mm, 14 mm thick, normal tilted ~27° from z and rotated about z.
  const Vec3 n = Vec3(0.35, 0.25, 1.0).normalized();
  const Vec3 u = n.cross(Vec3::UnitX()).normalized();
  const Vec3 v = n.cross(u);
  const Vec3 x0(0.3, -0.2, 0.1);
  const double A = 30.0, B = 22.0, T = 14.0;
  auto local = [=](const Vec3& p) { return Vec3(u.dot(p - x0), v.dot(p - x0), n.dot(p - x0)); };
  Aabb box;
  for (int s = 0; s < 8; ++s) {
    box.extend(x0 + ((s & 1) ? A : -A) * u + ((s & 2) ? B : -B) * v + ((s & 4) ? T : 0.0) * n);
  }
  AnalyticCase c;
  c.name = "tilted slab";
  c.grid = makeGridFromPredicate(box, box.size().maxCoeff() / cells, [=](const Vec3& p) {
    const Vec3 q = local(p);
    return std::abs(q.x()) <= A && std::abs(q.y()) <= B && q.z() >= 0 && q.z() <= T;
  });
  c.model = makeBox(Vec3(-A, -B, 0), Vec3(A, B, T));
  for (Vec3& p : c.model.vertices) p = x0 + p.x() * u + p.y() * v + p.z() * n;
  c.source =
      rectangle(x0 - A * u - B * v, x0 + A * u - B * v, x0 + A * u + B * v, x0 - A * u + B * v);
  c.exact = [=](const Vec3& p) { return n.dot(p - x0); };
  return c;
}

AnalyticCase makeSphericalShellCase(int cells) {
  const Vec3 centre(0.13, -0.07, 0.21);
  const double r1 = 10.0, r2 = 32.0;
  Aabb box;
  box.extend(centre - Vec3::Constant(r2));
  box.extend(centre + Vec3::Constant(r2));
  AnalyticCase c;
  c.name = "spherical shell";
  c.grid = makeGridFromPredicate(box, 2 * r2 / cells, [=](const Vec3& p) {
    const double r = (p - centre).norm();
    return r >= r1 && r <= r2;
  });
  c.model = makeSphericalShell(centre, r1, r2, 5);
  c.source = makeSphere(centre, r1, 5);
  c.exact = [=](const Vec3& p) { return (p - centre).norm() - r1; };
  return c;
}

AnalyticCase makeLShapeCase(int cells) {
  const double A = 64.3, B = 64.3, W = 20.2, H = 12.1;
  Aabb box;
  box.extend(Vec3(0, 0, 0));
  box.extend(Vec3(A, B, H));
  AnalyticCase c;
  c.name = "L-shape";
  c.grid = makeGridFromPredicate(box, A / cells, [=](const Vec3& p) {
    if (p.z() < 0 || p.z() > H || p.x() < 0 || p.y() < 0) return false;
    return (p.x() <= A && p.y() <= W) || (p.x() <= W && p.y() <= B);
  });
  c.model = makeLPrism(A, B, W, H);
  c.source = rectangle(Vec3(A, 0, 0), Vec3(A, W, 0), Vec3(A, W, H), Vec3(A, 0, H));
  c.exact = [=](const Vec3& p) {
    if (p.y() <= W) return A - p.x();
    return std::hypot(p.x() - W, p.y() - W) + (A - W);
  };
  return c;
}

AnalyticCase makeUChannelCase(int cells) {
  const double A = 50.3, B = 60.7, W = 14.1, H = 9.3;
  Aabb box;
  box.extend(Vec3(0, 0, 0));
  box.extend(Vec3(A, B, H));
  AnalyticCase c;
  c.name = "U-channel";
  c.grid = makeGridFromPredicate(box, B / cells, [=](const Vec3& p) {
    if (p.z() < 0 || p.z() > H || p.x() < 0 || p.y() < 0 || p.y() > B) return false;
    return (p.x() <= A && (p.y() <= W || p.y() >= B - W)) || p.x() <= W;
  });
  c.model = makeUChannel(A, B, W, H);
  c.source = rectangle(Vec3(A, 0, 0), Vec3(A, W, 0), Vec3(A, W, H), Vec3(A, 0, H));
  c.exact = [=](const Vec3& p) {
    if (p.y() <= W) return A - p.x();  // lower arm: straight to the end face
    if (p.x() <= W) return (A - W) + std::hypot(p.x() - W, p.y() - W);      // around (W, W)
    return (A - W) + (B - 2 * W) + std::hypot(p.x() - W, p.y() - (B - W));  // and (W, B − W)
  };
  return c;
}

AnalyticCase makeUBendCase(int cells) {
  const double ri = 20.0, ro = 40.0, H = 10.0;
  Aabb box;
  box.extend(Vec3(-ro, 0, 0));
  box.extend(Vec3(ro, ro, H));
  AnalyticCase c;
  c.name = "U-bend";
  c.grid = makeGridFromPredicate(box, 2 * ro / cells, [=](const Vec3& p) {
    const double r = std::hypot(p.x(), p.y());
    return p.y() >= 0 && r >= ri && r <= ro && p.z() >= 0 && p.z() <= H;
  });
  c.model = makeHalfAnnulus(ri, ro, H, 512);
  c.source = rectangle(Vec3(ri, 0, 0), Vec3(ro, 0, 0), Vec3(ro, 0, H), Vec3(ri, 0, H));
  c.exact = [=](const Vec3& p) {
    if (p.x() >= ri) return p.y();
    const double r = std::hypot(p.x(), p.y());
    const double theta = std::atan2(p.y(), p.x());
    return ri * (theta - std::acos(ri / r)) + std::sqrt(r * r - ri * ri);
  };
  return c;
}

FieldError measureFieldError(const AnalyticCase& c, const DistanceField& field) {
  FieldError e;
  const GridGeometry& g = c.grid.geometry;
  const double L = g.voxelSize;
  double sum = 0.0;
  for (std::size_t n = 0; n < c.grid.inside.size(); ++n) {
    if (!c.grid.inside[n]) continue;
    if (!field.reached(n)) {
      ++e.unreached;
      continue;
    }
    const Vec3 p = g.centerInPart(n);
    const double exact = c.exact(p);
    const double diff = (field.at(n) - exact) / L;
    sum += std::abs(diff);
    ++e.voxels;
    if (std::abs(diff) > e.max) {
      e.max = std::abs(diff);
      e.worst = p;
    }
    e.maxOver = std::max(e.maxOver, diff);
    if (exact > L) e.maxRelativeOver = std::max(e.maxRelativeOver, (diff - 1.0) * L / exact);
  }
  e.mean = e.voxels ? sum / static_cast<double>(e.voxels) : 0.0;
  return e;
}

}  // namespace curvedslicer::testing
