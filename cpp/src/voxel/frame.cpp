// Principal-axis frame of a triangle surface (paper §2.1).
//
// The covariance is integrated exactly over every triangle: for a triangle with corners a, b, c
// (relative to the area centroid) and area A,
//   ∫ x xᵀ dA = A/12 · (a aᵀ + b bᵀ + c cᵀ + s sᵀ),   s = a + b + c,
// so the frame depends only on the surface, not on its tessellation. The eigenvectors of the
// area-normalised covariance (Eigen::SelfAdjointEigenSolver) are ordered by decreasing variance.
// Where the decomposition is ambiguous (variances equal within 1e-9 of the largest) the axes are
// chosen from the model axes instead: all three equal -> the model axes; two equal -> the model
// axis with the largest component in their plane, projected into the plane, and its cross product
// with the distinct axis. Signs: x and y have their largest-magnitude component positive,
// z = x × y (right-handed). A frame that is a signed permutation up to 1e-9 per component is made
// exact. Triangles repeating another triangle's three corners count once.
#include "curvedslicer/voxel/frame.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "curvedslicer/core/error.hpp"
#include "voxel/distinct_keys.hpp"

namespace curvedslicer {

std::string_view toString(GridAlignment alignment) {
  return alignment == GridAlignment::Pca ? "pca" : "model";
}

GridAlignment parseGridAlignment(std::string_view name) {
  const std::size_t first = name.find_first_not_of(" \t\r\n");
  const std::size_t last = name.find_last_not_of(" \t\r\n");
  std::string n(first == std::string_view::npos ? "" : name.substr(first, last - first + 1));
  for (char& c : n) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (n == "pca") return GridAlignment::Pca;
  if (n == "model") return GridAlignment::Model;
  throw InvalidInput("unknown grid alignment: '" + std::string(name) +
                     "'; use pca (principal axes, paper §2.1) or model (the model's axes)");
}
namespace {

/// Relative tolerance under which two variances count as equal (see frame.hpp).
constexpr double kEqualVarianceTolerance = 1e-9;
/// Components below this magnitude count as zero when snapping to a signed permutation.
constexpr double kPermutationTolerance = 1e-9;

void validateMesh(const TriMesh& mesh) {
  if (mesh.triangles.empty()) {
    throw InvalidInput(
        "cannot compute a principal-axis frame of an empty mesh: 0 triangles; pass a mesh with "
        "at least one triangle of non-zero area");
  }
  const int vertexCount = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles[t][k];
      if (v < 0 || v >= vertexCount) {
        std::ostringstream msg;
        msg << "triangle " << t << " refers to vertex index " << v << " outside [0, " << vertexCount
            << "); repair or re-export the mesh";
        throw InvalidInput(msg.str());
      }
      if (!mesh.vertices[v].allFinite()) {
        std::ostringstream msg;
        msg << "vertex " << v << " has a non-finite coordinate: (" << mesh.vertices[v].x() << ", "
            << mesh.vertices[v].y() << ", " << mesh.vertices[v].z()
            << "); repair or re-export the mesh";
        throw InvalidInput(msg.str());
      }
    }
  }
}

/// Triangles that are not a repeat of an earlier triangle over the same three corner positions
/// (in any order or orientation): the surface counts a duplicated facet once.
std::vector<std::size_t> uniqueTriangles(const TriMesh& mesh) {
  using Corner = std::array<double, 3>;
  using Key = std::array<Corner, 3>;
  std::vector<Key> keys(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.corner(t, k);
      keys[t][k] = {p.x(), p.y(), p.z()};
    }
    std::sort(keys[t].begin(), keys[t].end());
  }
  std::vector<std::size_t> all(mesh.triangles.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  return detail::firstOfEachDistinctKey(keys, std::move(all));
}

/// Index of the first component whose magnitude is within a small tolerance of the largest.
int dominantComponent(const Vec3& v) {
  const double largest = v.cwiseAbs().maxCoeff();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(v[k]) >= largest - 1e-9 * largest) return k;
  }
  return 0;
}

Vec3 signByDominantComponent(const Vec3& v) {
  return v[dominantComponent(v)] < 0 ? -v : v;
}

/// Two unit vectors spanning the plane orthogonal to `normal`, built from the model axis that has
/// the largest component in that plane (first such axis on ties).
std::array<Vec3, 2> modelAlignedPlaneAxes(const Vec3& normal) {
  std::array<double, 3> inPlane{};  // squared length of each model axis projected into the plane
  for (int k = 0; k < 3; ++k) inPlane[k] = 1.0 - normal[k] * normal[k];
  const double largest = std::max({inPlane[0], inPlane[1], inPlane[2]});
  int best = 0;
  while (inPlane[best] < largest - 1e-12) ++best;
  const Vec3 e = Vec3::Unit(best);
  const Vec3 a = (e - e.dot(normal) * normal).normalized();
  const Vec3 b = normal.cross(a).normalized();
  return {a, b};
}

/// If every column is a signed unit axis up to kPermutationTolerance, returns the exact matrix.
Mat3 snapToSignedPermutation(const Mat3& r) {
  Mat3 exact = Mat3::Zero();
  std::array<bool, 3> used{false, false, false};
  for (int c = 0; c < 3; ++c) {
    const Vec3 col = r.col(c);
    const int k = dominantComponent(col);
    for (int m = 0; m < 3; ++m) {
      if (m != k && std::abs(col[m]) > kPermutationTolerance) return r;
    }
    if (used[k]) return r;
    used[k] = true;
    exact(k, c) = col[k] < 0 ? -1.0 : 1.0;
  }
  return exact;
}

}  // namespace

Frame computePcaFrame(const TriMesh& mesh) {
  validateMesh(mesh);
  const std::vector<std::size_t> triangles = uniqueTriangles(mesh);

  // Area centroid.
  double area = 0.0;
  Vec3 firstMoment = Vec3::Zero();
  for (const std::size_t t : triangles) {
    const double A = mesh.triangleArea(t);
    area += A;
    firstMoment += A * (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)) / 3.0;
  }
  const double diagonal = [&] {
    Aabb box;
    for (const Vec3i& tri : mesh.triangles) {
      for (int k = 0; k < 3; ++k) box.extend(mesh.vertices[tri[k]]);
    }
    return box.diagonal();
  }();
  if (!(area > 1e-14 * diagonal * diagonal) || !std::isfinite(area)) {
    std::ostringstream msg;
    msg << "cannot compute a principal-axis frame of a mesh with zero surface area: " << area
        << " mm² (" << mesh.triangles.size() << " triangles); pass a mesh with non-degenerate "
        << "triangles";
    throw InvalidInput(msg.str());
  }
  const Vec3 centroid = firstMoment / area;

  // Exact second moments about the centroid.
  Mat3 second = Mat3::Zero();
  for (const std::size_t t : triangles) {
    const double A = mesh.triangleArea(t);
    const Vec3 a = mesh.corner(t, 0) - centroid;
    const Vec3 b = mesh.corner(t, 1) - centroid;
    const Vec3 c = mesh.corner(t, 2) - centroid;
    const Vec3 s = a + b + c;
    second += (A / 12.0) *
              (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  const Mat3 covariance = second / area;

  Eigen::SelfAdjointEigenSolver<Mat3> solver(covariance);
  if (solver.info() != Eigen::Success || !solver.eigenvalues().allFinite()) {
    throw NumericalFailure(
        "the eigen-decomposition of the surface covariance failed; check the mesh for extreme "
        "coordinates");
  }
  // Eigen sorts increasingly; we want decreasing variance.
  std::array<double, 3> variance{};
  std::array<Vec3, 3> axis;
  for (int k = 0; k < 3; ++k) {
    variance[k] = solver.eigenvalues()[2 - k];
    axis[k] = solver.eigenvectors().col(2 - k).normalized();
  }

  const double tolerance = kEqualVarianceTolerance * std::max(variance[0], 0.0);
  const bool equal01 = variance[0] - variance[1] <= tolerance;
  const bool equal12 = variance[1] - variance[2] <= tolerance;
  if (equal01 && equal12) {
    axis = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  } else if (equal01) {
    const auto plane = modelAlignedPlaneAxes(axis[2]);
    axis[0] = plane[0];
    axis[1] = plane[1];
  } else if (equal12) {
    const auto plane = modelAlignedPlaneAxes(axis[0]);
    axis[1] = plane[0];
    axis[2] = plane[1];
  }

  Frame frame;
  frame.origin = centroid;
  const Vec3 x = signByDominantComponent(axis[0]);
  Vec3 y = axis[1] - axis[1].dot(x) * x;  // re-orthogonalise against round-off
  y = signByDominantComponent(y.normalized());
  const Vec3 z = x.cross(y).normalized();
  frame.rotation.col(0) = x;
  frame.rotation.col(1) = y;
  frame.rotation.col(2) = z;
  frame.rotation = snapToSignedPermutation(frame.rotation);
  return frame;
}

}  // namespace curvedslicer
