// Analytic test surfaces for the path-geometry tests: surfaces of revolution about the z axis
// (cylinder side, cone side, spherical cap, flat annulus) and flat rectangles, as indexed
// triangle meshes with every vertex exactly on the surface. Surfaces of revolution are built
// ring by ring from a profile (r(t), z(t)), each ring with about 2πr/h vertices (h the target
// edge length) and neighbouring rings zipped together, so triangles are near-equilateral with a
// few obtuse ones where ring counts change. The geodesic distance from a boundary circle is the
// profile arc length (meridians are geodesics).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer::testing {

struct Profile {
  std::function<double(double)> radius;  // r(t)
  std::function<double(double)> height;  // z(t)
  double t0 = 0.0, t1 = 1.0;
  int rings = 10;  // rings = number of intervals in t
};

/// Ring-zipped surface of revolution; edge length about `h`. Rings with r = 0 become one vertex.
inline TriMesh makeRevolutionMesh(const Profile& profile, double h) {
  TriMesh mesh;
  std::vector<std::vector<int>> rings;
  std::vector<std::vector<double>> angles;
  for (int i = 0; i <= profile.rings; ++i) {
    const double t = profile.t0 + (profile.t1 - profile.t0) * i / profile.rings;
    const double r = profile.radius(t), z = profile.height(t);
    std::vector<int> ring;
    std::vector<double> phi;
    if (r < 1e-12) {
      ring.push_back(static_cast<int>(mesh.vertices.size()));
      phi.push_back(0.0);
      mesh.vertices.emplace_back(0.0, 0.0, z);
    } else {
      const int n = std::max(6, static_cast<int>(std::lround(2 * std::numbers::pi * r / h)));
      const double offset = (i % 2) * 0.5;  // stagger rings for better triangles
      for (int k = 0; k < n; ++k) {
        const double a = 2 * std::numbers::pi * (k + offset) / n;
        ring.push_back(static_cast<int>(mesh.vertices.size()));
        phi.push_back(a);
        mesh.vertices.emplace_back(r * std::cos(a), r * std::sin(a), z);
      }
    }
    rings.push_back(ring);
    angles.push_back(phi);
  }
  for (int i = 0; i < profile.rings; ++i) {
    const auto& A = rings[i];
    const auto& B = rings[i + 1];
    const auto& pa = angles[i];
    const auto& pb = angles[i + 1];
    const int na = static_cast<int>(A.size()), nb = static_cast<int>(B.size());
    if (na == 1 || nb == 1) {
      const int apex = na == 1 ? A[0] : B[0];
      const auto& ring = na == 1 ? B : A;
      const int n = static_cast<int>(ring.size());
      for (int k = 0; k < n; ++k) {
        if (na == 1) {
          mesh.triangles.emplace_back(apex, ring[k], ring[(k + 1) % n]);
        } else {
          mesh.triangles.emplace_back(ring[k], ring[(k + 1) % n], apex);
        }
      }
      continue;
    }
    // Zipper: advance along whichever ring's next vertex has the smaller angle.
    int ia = 0, ib = 0;
    auto angleA = [&](int k) { return pa[k % na] + 2 * std::numbers::pi * (k / na); };
    auto angleB = [&](int k) { return pb[k % nb] + 2 * std::numbers::pi * (k / nb); };
    while (ia < na || ib < nb) {
      const bool advanceA = ib >= nb || (ia < na && angleA(ia + 1) <= angleB(ib + 1));
      if (advanceA) {
        mesh.triangles.emplace_back(A[ia % na], A[(ia + 1) % na], B[ib % nb]);
        ++ia;
      } else {
        mesh.triangles.emplace_back(A[ia % na], B[(ib + 1) % nb], B[ib % nb]);
        ++ib;
      }
    }
  }
  return mesh;
}

/// Flat rectangle [x0, x1] × [y0, y1] at z = 0, nx × ny cells each split into two triangles
/// (alternating diagonals), normals +z.
inline TriMesh makeRectangleMesh(double x0, double x1, double y0, double y1, int nx, int ny) {
  TriMesh mesh;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      mesh.vertices.emplace_back(x0 + (x1 - x0) * i / nx, y0 + (y1 - y0) * j / ny, 0.0);
    }
  }
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if ((i + j) % 2 == 0) {
        mesh.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        mesh.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      } else {
        mesh.triangles.emplace_back(id(i, j), id(i + 1, j), id(i, j + 1));
        mesh.triangles.emplace_back(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  }
  return mesh;
}

}  // namespace curvedslicer::testing
