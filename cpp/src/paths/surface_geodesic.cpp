// GDTC on a triangle surface: fast marching (accurate) and the paper's eq. 15 Dijkstra (see
// curvedslicer/paths/surface_geodesic.hpp).
#include "curvedslicer/paths/surface_geodesic.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>
#include <string>
#include <unordered_map>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/paths/polyline.hpp"

namespace curvedslicer {

std::string_view toString(SurfaceGeodesicMethod method) {
  return method == SurfaceGeodesicMethod::Paper ? "paper" : "accurate";
}

SurfaceGeodesicMethod parseSurfaceGeodesicMethod(std::string_view name) {
  if (name == "accurate") return SurfaceGeodesicMethod::Accurate;
  if (name == "paper") return SurfaceGeodesicMethod::Paper;
  throw InvalidInput("unknown surface geodesic method: '" + std::string(name) +
                     "'; choose accurate or paper");
}

namespace {

using Clock = std::chrono::steady_clock;

struct QueueEntry {
  double value;
  std::int32_t vertex;
  bool operator>(const QueueEntry& o) const {
    return value != o.value ? value > o.value : vertex > o.vertex;
  }
};
using MinQueue = std::priority_queue<QueueEntry, std::vector<QueueEntry>, std::greater<>>;

std::vector<std::vector<int>> buildIncidence(const TriMesh& mesh) {
  std::vector<std::vector<int>> incident(mesh.vertexCount());
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) incident[mesh.triangles[t][k]].push_back(static_cast<int>(t));
  }
  return incident;
}

/// Planar-wavefront update of C from A, B (Kimmel & Sethian 1998): a = A − C, b = B − C, known
/// values dA, dB. Returns +inf if the front direction does not come through the triangle.
double planarUpdate(const Vec3& a, const Vec3& b, double dA, double dB) {
  const double aa = a.dot(a), ab = a.dot(b), bb = b.dot(b);
  const double det = aa * bb - ab * ab;
  if (!(det > 1e-14 * aa * bb)) return kInf;
  // Q = G^{-1}
  const double q00 = bb / det, q01 = -ab / det, q11 = aa / det;
  // (u − d·1)ᵀ Q (u − d·1) = 1 with u = (dA, dB)
  const double s1 = q00 + 2 * q01 + q11;                                // 1ᵀQ1
  const double su = (q00 + q01) * dA + (q01 + q11) * dB;                // 1ᵀQu
  const double uu = q00 * dA * dA + 2 * q01 * dA * dB + q11 * dB * dB;  // uᵀQu
  const double disc = su * su - s1 * (uu - 1.0);
  if (disc < 0.0 || !(s1 > 0.0)) return kInf;
  const double d = (su + std::sqrt(disc)) / s1;
  if (d < std::max(dA, dB)) return kInf;
  // Gradient n = α a + β b with (α, β) = Q (u − d); upwind −n must lie inside the wedge.
  const double r0 = dA - d, r1 = dB - d;
  const double alpha = q00 * r0 + q01 * r1, beta = q01 * r0 + q11 * r1;
  if (alpha > 0.0 || beta > 0.0) return kInf;
  return d;
}

/// Second-order update: fits the front through three known points as a circle (Apollonius:
/// |X_i − S| = |d_i + ρ|, centre S and radius offset ρ in the unfolded plane, C at the origin)
/// and evaluates it at C. Exact for straight and circular fronts (the parallels of a curve on a
/// developable surface; to second order on curved ones). Returns NaN where the three points do
/// not determine a circle consistent with the planar estimate `planar`.
double circleUpdate(const Eigen::Vector2d& A, const Eigen::Vector2d& B, const Eigen::Vector2d& D,
                    double dA, double dB, double dD, double planar, double maxCorrection) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::Matrix2d M;
  M.row(0) = -2.0 * (B - A).transpose();
  M.row(1) = -2.0 * (D - A).transpose();
  const double det = M.determinant();
  const double scale = (B - A).squaredNorm() * (D - A).squaredNorm();
  if (!(std::abs(det) > 1e-10 * 4.0 * scale)) return nan;
  const Eigen::Vector2d r((dB * dB - dA * dA) - (B.squaredNorm() - A.squaredNorm()),
                          (dD * dD - dA * dA) - (D.squaredNorm() - A.squaredNorm()));
  const Eigen::Vector2d q(2.0 * (dB - dA), 2.0 * (dD - dA));
  const Eigen::Matrix2d Minv = M.inverse();
  const Eigen::Vector2d S0 = Minv * r, S1 = Minv * q;  // S = S0 + S1·ρ
  const Eigen::Vector2d w = A - S0;
  const double a = S1.squaredNorm() - 1.0;
  const double b = 2.0 * (-w.dot(S1) - dA);
  const double c = w.squaredNorm() - dA * dA;
  // Planar gradient n (C at the origin): n·A = dA − planar, n·B = dB − planar.
  Eigen::Matrix2d P;
  P.row(0) = A.transpose();
  P.row(1) = B.transpose();
  if (!(std::abs(P.determinant()) > 0.0)) return nan;
  const Eigen::Vector2d n = P.inverse() * Eigen::Vector2d(dA - planar, dB - planar);
  const double nNorm = n.norm();
  if (!(nNorm > 0.0)) return nan;
  const double stencil = std::sqrt(
      std::max({A.squaredNorm(), B.squaredNorm(), (B - A).squaredNorm(), (D - A).squaredNorm()}));
  const double flat = 1e4 * stencil;
  const double minRadius = 2.0 * stencil;
  // Of the two Apollonius solutions keep the flatter one (the larger front radius): the other is
  // a small circle hugging the stencil point nearest its centre. Its gradient at C must agree
  // with the planar gradient n.
  double best = nan, bestRadius = -1.0;
  auto consider = [&](double rho) {
    if (!std::isfinite(rho)) return;
    if (std::abs(rho) > flat) {
      // Practically straight: the planar update is exact and better conditioned.
      best = planar;
      bestRadius = kInf;
      return;
    }
    const Eigen::Vector2d S = S0 + S1 * rho;
    const double sign = dA + rho >= 0.0 ? 1.0 : -1.0;
    if ((dB + rho) * sign < 0.0 || (dD + rho) * sign < 0.0) return;
    const double sNorm = S.norm();
    if (!(sNorm > 0.0)) return;
    const double radius = std::min({std::abs(dA + rho), std::abs(dB + rho), std::abs(dD + rho)});
    if (radius <= bestRadius) return;
    // Fronts tighter than twice the stencil are not resolved by three samples (point-source fans
    // next to single source vertices, noise): keep the planar value there.
    if (radius < minRadius) return;
    const double dC = sign * sNorm - rho;
    if (!(dC >= std::max(dA, dB))) return;
    if (std::abs(dC - planar) > maxCorrection) return;
    if ((-sign * S / sNorm).dot(n) / nNorm < 0.9) return;
    best = dC;
    bestRadius = radius;
  };
  if (std::abs(a) < 1e-12) {
    if (b != 0.0) consider(-c / b);
    consider(1e300);  // the straight front
  } else {
    const double disc = b * b - 4 * a * c;
    if (disc < 0.0) return nan;
    const double sq = std::sqrt(disc);
    // Stable roots.
    const double qq = -0.5 * (b + (b >= 0 ? sq : -sq));
    consider(qq / a);
    if (qq != 0.0) consider(c / qq);
  }
  return best;
}

struct Unfolder {
  const TriMesh& mesh;
  const std::vector<std::vector<int>>& incident;

  /// The triangle across edge (a, b) from triangle t, or −1.
  int across(int t, std::int32_t a, std::int32_t b) const {
    for (const int u : incident[a]) {
      if (u == t) continue;
      const Vec3i& tri = mesh.triangles[u];
      if (tri[0] == b || tri[1] == b || tri[2] == b) return u;
    }
    return -1;
  }
  static std::int32_t third(const Vec3i& tri, std::int32_t a, std::int32_t b) {
    for (int k = 0; k < 3; ++k) {
      if (tri[k] != a && tri[k] != b) return tri[k];
    }
    return -1;
  }
};

}  // namespace

namespace {

/// The update of vertex w from triangle t whose other corners are v (just accepted) and x:
/// first order (planar), refined to second order by a circular front through a third accepted
/// vertex, and for a triangle obtuse at w from the triangles unfolded across the far edge.
class TriangleUpdate {
 public:
  TriangleUpdate(const TriMesh& mesh, const Unfolder& unfolder, const std::vector<double>& d,
                 const std::vector<char>& accepted, const SurfaceGeodesicOptions& options,
                 SurfaceGeodesicResult& result)
      : mesh_(mesh),
        V(mesh.vertices),
        unfolder_(unfolder),
        d_(d),
        accepted_(accepted),
        options_(options),
        result_(result) {}

  double operator()(int t, std::int32_t w, std::int32_t v, std::int32_t x) {
    const Vec3 C = V[w];
    double best = kInf;
    const Vec3 a = V[v] - C, b = V[x] - C;
    if (!accepted_[x]) return best;
    const double cosC = a.dot(b);
    const double planar = planarUpdate(a, b, d_[v], d_[x]);
    double refined = std::numeric_limits<double>::quiet_NaN();
    if (std::isfinite(planar) && options_.secondOrder) refined = refine(t, v, x, a, b, planar);
    best = std::min(best, std::isnan(refined) ? planar : refined);
    if (cosC < 0.0) updateAcrossObtuse(t, v, x, a, b, best);
    return best;
  }

 private:
  /// Second order: the vertex across edge AB, unfolded into the plane of (C, A, B), as the third
  /// point of circleUpdate; NaN when there is none.
  double refine(int t, std::int32_t v, std::int32_t x, const Vec3& a, const Vec3& b,
                double planar) const {
    const int nb = unfolder_.across(t, v, x);
    const std::int32_t id = nb >= 0 ? Unfolder::third(mesh_.triangles[nb], v, x) : -1;
    if (id < 0 || !accepted_[id]) return std::numeric_limits<double>::quiet_NaN();
    const Vec3 nrm = a.cross(b);
    const double nn = nrm.norm();
    if (!(nn > 0.0)) return std::numeric_limits<double>::quiet_NaN();
    const Vec3 ex = a.normalized();
    const Vec3 ey = (nrm / nn).cross(ex);
    const Eigen::Vector2d pa(a.dot(ex), a.dot(ey)), pb(b.dot(ex), b.dot(ey));
    const double la = (V[id] - V[v]).norm(), lb = (V[id] - V[x]).norm();
    const Eigen::Vector2d e = pb - pa;
    const double l = e.norm();
    const double along = (la * la - lb * lb + l * l) / (2 * l);
    const double h2 = la * la - along * along;
    const Eigen::Vector2d eu = e / l;
    Eigen::Vector2d perp(-eu.y(), eu.x());
    if (perp.dot(-pa) > 0.0) perp = -perp;
    const Eigen::Vector2d pd = pa + along * eu + (h2 > 0.0 ? std::sqrt(h2) : 0.0) * perp;
    return circleUpdate(pa, pb, pd, d_[v], d_[x], d_[id], planar, 0.5 * l);
  }

  /// Obtuse at C: unfolds triangles across the far edge into the plane of (C, A, B) until a
  /// virtual vertex D lies inside the angle at C, then updates `best` from (A, D) and (D, B).
  void updateAcrossObtuse(int t, std::int32_t v, std::int32_t x, const Vec3& a, const Vec3& b,
                          double& best) {
    const Vec3 nrm = a.cross(b);
    const double nn = nrm.norm();
    if (!(nn > 0.0)) return;
    const Vec3 ez = nrm / nn;
    // 2D frame in the plane of C, A, B with C at the origin.
    const Vec3 ex = a.normalized();
    const Vec3 ey = ez.cross(ex);
    auto to2 = [&](const Vec3& p) { return Eigen::Vector2d(p.dot(ex), p.dot(ey)); };
    Eigen::Vector2d pa = to2(a), pb = to2(b);
    std::int32_t ia = v, ib = x;
    int tri = t;
    for (int step = 0; step < 8; ++step) {
      const int nb = unfolder_.across(tri, ia, ib);
      if (nb < 0) break;
      const std::int32_t id = Unfolder::third(mesh_.triangles[nb], ia, ib);
      if (id < 0) break;
      // Place D: its distances to A and B are preserved; on the far side of AB from C.
      const double la = (V[id] - V[ia]).norm(), lb = (V[id] - V[ib]).norm();
      const Eigen::Vector2d e = pb - pa;
      const double l = e.norm();
      if (!(l > 0.0)) break;
      const double along = (la * la - lb * lb + l * l) / (2 * l);
      const double h2 = la * la - along * along;
      const double h = h2 > 0.0 ? std::sqrt(h2) : 0.0;
      const Eigen::Vector2d eu = e / l;
      Eigen::Vector2d perp(-eu.y(), eu.x());
      // C (origin) must be on the other side.
      if (perp.dot(-pa) > 0.0) perp = -perp;
      const Eigen::Vector2d pd = pa + along * eu + h * perp;
      const double crossA = pa.x() * pd.y() - pa.y() * pd.x();  // A × D
      const double crossD = pd.x() * pb.y() - pd.y() * pb.x();  // D × B
      const double orient = pa.x() * pb.y() - pa.y() * pb.x();  // A × B
      const bool inside = crossA * orient > 0.0 && crossD * orient > 0.0;
      if (inside) {
        ++result_.unfoldings;
        if (accepted_[id]) {
          const Vec3 dv = pd.x() * ex + pd.y() * ey;
          const Vec3 av = pa.x() * ex + pa.y() * ey, bv = pb.x() * ex + pb.y() * ey;
          best = std::min(best, planarUpdate(av, dv, d_[ia], d_[id]));
          best = std::min(best, planarUpdate(dv, bv, d_[id], d_[ib]));
        }
        break;
      }
      // Continue across the edge that the wedge still sees: (A, D) if D is past B's side.
      if (crossA * orient <= 0.0) {
        ib = id;
        pb = pd;
      } else {
        ia = id;
        pa = pd;
      }
      tri = nb;
    }
  }

  const TriMesh& mesh_;
  const std::vector<Vec3>& V;  // mesh vertices, mm
  const Unfolder& unfolder_;
  const std::vector<double>& d_;
  const std::vector<char>& accepted_;
  const SurfaceGeodesicOptions& options_;
  SurfaceGeodesicResult& result_;
};

/// Fast marching on the triangles from seeded values.
void runFastMarching(const TriMesh& mesh, std::vector<double>& d,
                     const std::vector<std::int32_t>& sources,
                     const SurfaceGeodesicOptions& options, SurfaceGeodesicResult& result,
                     const Progress& progress) {
  const double maxDistance = options.maxDistance;
  const std::size_t n = mesh.vertexCount();
  const auto incident = buildIncidence(mesh);
  const Unfolder unfolder{mesh, incident};
  std::vector<char> accepted(n, 0);
  MinQueue queue;
  for (const std::int32_t s : sources) queue.push({d[s], s});
  const auto& V = mesh.vertices;
  TriangleUpdate triangleUpdate(mesh, unfolder, d, accepted, options, result);
  std::size_t done = 0;
  const std::size_t reportEvery = std::max<std::size_t>(n / 50, 1000);
  while (!queue.empty()) {
    const QueueEntry top = queue.top();
    queue.pop();
    const std::int32_t v = top.vertex;
    if (accepted[v] || top.value > d[v]) continue;
    if (d[v] > maxDistance) {
      d[v] = kInf;
      continue;
    }
    accepted[v] = 1;
    if (++done % reportEvery == 0)
      progress.report(static_cast<double>(done) / n, "propagating surface distance");
    for (const int t : incident[v]) {
      const Vec3i& tri = mesh.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const std::int32_t w = tri[k];
        if (accepted[w]) continue;
        const std::int32_t x = tri[(k + 1) % 3] == v ? tri[(k + 2) % 3] : tri[(k + 1) % 3];
        double candidate = d[v] + (V[w] - V[v]).norm();
        candidate = std::min(candidate, triangleUpdate(t, w, v, x));
        if (candidate < d[w]) {
          d[w] = candidate;
          queue.push({candidate, w});
        }
      }
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (!accepted[v]) d[v] = kInf;
  }
}

/// The paper's method: Dijkstra over a search ball with the projected length of eq. 15.
void runPaperDijkstra(const TriMesh& mesh, std::vector<double>& d,
                      const std::vector<std::int32_t>& sources, double radius, double maxDistance,
                      const Progress& progress) {
  const std::size_t n = mesh.vertexCount();
  const auto& V = mesh.vertices;
  // Uniform hash grid with cell size = radius.
  auto cellOf = [&](const Vec3& p) {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / radius)),
                           static_cast<int>(std::floor(p.y() / radius)),
                           static_cast<int>(std::floor(p.z() / radius)));
  };
  auto key = [](const Eigen::Vector3i& c) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.x()) & 0x1FFFFF) << 42) |
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.y()) & 0x1FFFFF) << 21) |
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.z()) & 0x1FFFFF));
  };
  std::unordered_map<std::uint64_t, std::vector<std::int32_t>> grid;
  for (std::size_t v = 0; v < n; ++v)
    grid[key(cellOf(V[v]))].push_back(static_cast<std::int32_t>(v));
  const double r2 = radius * radius;
  auto neighbours = [&](std::int32_t v, std::vector<std::int32_t>& out) {
    out.clear();
    const Eigen::Vector3i c = cellOf(V[v]);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == grid.end()) continue;
          for (const std::int32_t w : it->second) {
            if (w != v && (V[w] - V[v]).squaredNorm() <= r2) out.push_back(w);
          }
        }
      }
    }
  };
  // Normals Np from least-squares plane fits over the search ball.
  std::vector<Vec3> normal(n, Vec3::UnitZ());
  std::vector<std::int32_t> ball;
  for (std::size_t v = 0; v < n; ++v) {
    neighbours(static_cast<std::int32_t>(v), ball);
    Vec3 mean = V[v];
    for (const std::int32_t w : ball) mean += V[w];
    mean /= static_cast<double>(ball.size() + 1);
    Mat3 cov = (V[v] - mean) * (V[v] - mean).transpose();
    for (const std::int32_t w : ball) cov += (V[w] - mean) * (V[w] - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
    normal[v] = eig.eigenvectors().col(0);
  }
  progress.report(0.3, "propagating surface distance");
  std::vector<char> accepted(n, 0);
  MinQueue queue;
  for (const std::int32_t s : sources) queue.push({d[s], s});
  std::size_t done = 0;
  const std::size_t reportEvery = std::max<std::size_t>(n / 50, 1000);
  while (!queue.empty()) {
    const QueueEntry top = queue.top();
    queue.pop();
    const std::int32_t q = top.vertex;
    if (accepted[q] || top.value > d[q]) continue;
    if (d[q] > maxDistance) {
      d[q] = kInf;
      continue;
    }
    accepted[q] = 1;
    if (++done % reportEvery == 0) {
      progress.report(0.3 + 0.7 * static_cast<double>(done) / n, "propagating surface distance");
    }
    neighbours(q, ball);
    for (const std::int32_t p : ball) {
      if (accepted[p]) continue;
      const Vec3 qp = V[p] - V[q];
      const Vec3& np = normal[p];
      const double l = (qp - qp.dot(np) * np).norm();  // eq. 15
      if (d[q] + l < d[p]) {
        d[p] = d[q] + l;
        queue.push({d[p], p});
      }
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (!accepted[v]) d[v] = kInf;
  }
}

double meanEdgeLength(const TriMesh& mesh) {
  double sum = 0.0;
  std::size_t count = 0;
  for (const Vec3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      sum += (mesh.vertices[t[(k + 1) % 3]] - mesh.vertices[t[k]]).norm();
      ++count;
    }
  }
  return count ? sum / static_cast<double>(count) : 0.0;
}

void validateOptions(const SurfaceGeodesicOptions& options) {
  if (!(options.curveTolerance >= 0.0) || !std::isfinite(options.curveTolerance)) {
    throw InvalidInput("initial-curve tolerance must be non-negative and finite: " +
                       std::to_string(options.curveTolerance) + " mm; pass a value such as 0.05");
  }
  if (std::isnan(options.paperSearchRadius) || std::isinf(options.paperSearchRadius)) {
    throw InvalidInput(
        "paper search radius is not finite: " + std::to_string(options.paperSearchRadius) +
        " mm; pass a positive radius or 0 for the default");
  }
  if (std::isnan(options.maxDistance) || !(options.maxDistance > 0.0)) {
    throw InvalidInput("largest surface distance must be positive: " +
                       std::to_string(options.maxDistance) + " mm; pass a positive value or +inf");
  }
}

/// Near-field seeding: vertices within `rings` edge rings of the curve vertices get the exact
/// Euclidean distance to the initial curve (equal to the geodesic distance up to O(d³κ²) at these
/// distances of a few edge lengths). Removes the first-order error fast marching makes next to
/// curve end points and corners, where the front is singular. Returns the seeded vertices and
/// their values.
void seedNearField(const TriMesh& mesh, const std::vector<std::int32_t>& curveVertices,
                   const std::vector<Polyline>& curves, int rings, std::vector<std::int32_t>& seeds,
                   std::vector<double>& values) {
  const auto incident = buildIncidence(mesh);
  std::vector<char> inBand(mesh.vertexCount(), 0);
  std::vector<std::int32_t> band = curveVertices;
  for (const std::int32_t v : band) inBand[v] = 1;
  std::size_t begin = 0;
  for (int r = 0; r < rings; ++r) {
    const std::size_t end = band.size();
    for (std::size_t i = begin; i < end; ++i) {
      for (const int t : incident[band[i]]) {
        for (int k = 0; k < 3; ++k) {
          const std::int32_t w = mesh.triangles[t][k];
          if (!inBand[w]) {
            inBand[w] = 1;
            band.push_back(w);
          }
        }
      }
    }
    begin = end;
  }
  seeds.clear();
  values.clear();
  for (const std::int32_t v : band) {
    double d = 0.0;
    if (!std::binary_search(curveVertices.begin(), curveVertices.end(), v)) {
      d = kInf;
      for (const Polyline& c : curves)
        d = std::min(d, closestPointOnPolyline(c, mesh.vertices[v]).distance);
    }
    seeds.push_back(v);
    values.push_back(d);
  }
}

void propagate(SurfaceGeodesicResult& result, const std::vector<std::int32_t>& sources,
               const std::vector<double>& values, const SurfaceGeodesicOptions& options,
               const Progress& progress) {
  const std::size_t n = result.mesh.vertexCount();
  result.distance.assign(n, kInf);
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const double value = values.empty() ? 0.0 : values[i];
    result.distance[sources[i]] = std::min(result.distance[sources[i]], value);
  }
  if (options.method == SurfaceGeodesicMethod::Paper) {
    result.searchRadius = options.paperSearchRadius > 0.0
                              ? options.paperSearchRadius
                              : 2.0 * std::sqrt(3.0) * meanEdgeLength(result.mesh);
    runPaperDijkstra(result.mesh, result.distance, sources, result.searchRadius,
                     options.maxDistance, progress);
  } else {
    runFastMarching(result.mesh, result.distance, sources, options, result, progress);
  }
  result.unreachedVertices = static_cast<std::size_t>(std::count_if(
      result.distance.begin(), result.distance.end(), [](double x) { return !std::isfinite(x); }));
  progress.report(1.0, "propagating surface distance");
}

}  // namespace

SurfaceGeodesicResult computeSurfaceGeodesic(const TriMesh& surface,
                                             const std::vector<Polyline>& initialCurve,
                                             const SurfaceGeodesicOptions& options,
                                             Progress progress) {
  const auto start = Clock::now();
  validateOptions(options);
  if (surface.empty()) {
    throw InvalidInput("layer surface is empty: 0 triangles; pass a surface with triangles");
  }
  std::size_t points = 0;
  for (const Polyline& c : initialCurve) points += c.points.size();
  if (points == 0) {
    throw InvalidInput("initial curve has no points: " + std::to_string(initialCurve.size()) +
                       " polylines; pass at least one point on the surface");
  }
  progress.report(0.0, "inserting initial curve");
  CurveInsertion inserted = insertCurves(surface, initialCurve, options.curveTolerance);
  progress.report(0.1, "inserting initial curve");
  SurfaceGeodesicResult result;
  result.mesh = std::move(inserted.mesh);
  result.curveVertices = std::move(inserted.curveVertices);
  result.maxCurveDeviation = inserted.maxCurveDeviation;
  result.insertedVertices = inserted.insertedVertices;
  if (options.method == SurfaceGeodesicMethod::Accurate && options.nearFieldRings > 0) {
    std::vector<std::int32_t> seeds;
    std::vector<double> values;
    seedNearField(result.mesh, result.curveVertices, initialCurve, options.nearFieldRings, seeds,
                  values);
    propagate(result, seeds, values, options, progress.sub(0.1, 1.0));
  } else {
    propagate(result, result.curveVertices, {}, options, progress.sub(0.1, 1.0));
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

SurfaceGeodesicResult computeSurfaceGeodesicFromVertices(
    const TriMesh& mesh, const std::vector<std::int32_t>& sourceVertices,
    const std::vector<double>& sourceValues, const SurfaceGeodesicOptions& options,
    Progress progress) {
  const auto start = Clock::now();
  validateOptions(options);
  if (mesh.empty()) {
    throw InvalidInput("layer surface is empty: 0 triangles; pass a surface with triangles");
  }
  if (sourceVertices.empty()) {
    throw InvalidInput("no source vertex for the surface distance: 0 vertices; pass at least one");
  }
  if (!sourceValues.empty() && sourceValues.size() != sourceVertices.size()) {
    throw InvalidInput(
        "source values do not match the source vertices: " + std::to_string(sourceValues.size()) +
        " values for " + std::to_string(sourceVertices.size()) +
        " vertices; pass one value per vertex or none");
  }
  for (std::size_t i = 0; i < sourceVertices.size(); ++i) {
    const std::int32_t v = sourceVertices[i];
    if (v < 0 || static_cast<std::size_t>(v) >= mesh.vertexCount()) {
      throw InvalidInput("source vertex index out of range: " + std::to_string(v) + " (mesh has " +
                         std::to_string(mesh.vertexCount()) + " vertices); pass valid indices");
    }
    if (!sourceValues.empty() && (!(sourceValues[i] >= 0.0) || !std::isfinite(sourceValues[i]))) {
      throw InvalidInput("source value must be non-negative and finite: " +
                         std::to_string(sourceValues[i]) + " mm; pass a value ≥ 0");
    }
  }
  SurfaceGeodesicResult result;
  result.mesh = mesh;
  result.curveVertices = sourceVertices;
  std::sort(result.curveVertices.begin(), result.curveVertices.end());
  result.curveVertices.erase(std::unique(result.curveVertices.begin(), result.curveVertices.end()),
                             result.curveVertices.end());
  propagate(result, sourceVertices, sourceValues, options, progress);
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace curvedslicer
