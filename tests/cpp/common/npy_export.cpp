// NumPy exports for the scikit-fmm peers of the field benchmarks (see npy_export.hpp).
#include "common/npy_export.hpp"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/geom/triangle_bvh.hpp"

namespace curvedslicer::testing {

void writeNpy(const std::filesystem::path& path, const char* descr, const Vec3i& dims,
              const void* data, std::size_t bytes) {
  std::ostringstream h;
  h << "{'descr': '" << descr << "', 'fortran_order': False, 'shape': (" << dims.x() << ", "
    << dims.y() << ", " << dims.z() << "), }";
  std::string header = h.str();
  // Magic (6) + version (2) + header length (2) + header, padded with spaces to a multiple of 64
  // and ended by a newline.
  const std::size_t total = ((10 + header.size() + 1 + 63) / 64) * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header.push_back('\n');
  writeFileAtomically(
      path,
      [&](std::ostream& out) {
        const char magic[] = "\x93NUMPY\x01\x00";
        out.write(magic, 8);
        const auto len = static_cast<std::uint16_t>(header.size());
        const char lenBytes[2] = {static_cast<char>(len & 0xff), static_cast<char>(len >> 8)};
        out.write(lenBytes, 2);
        out << header;
        out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
      },
      /*binary=*/true);
}

std::vector<double> signedBandDistances(const VoxelGrid& grid, const TriMesh& source) {
  const GridGeometry& g = grid.geometry;
  const double L = g.voxelSize;
  const double band = std::sqrt(3.0) * L;
  const std::size_t N = g.cellCount();
  // Candidates: cells in each triangle's band-grown box and within the band of its plane.
  std::vector<std::uint8_t> candidate(N, 0);
  for (std::size_t t = 0; t < source.triangles.size(); ++t) {
    const Vec3 a = g.toCellCoordinates(source.corner(t, 0));
    const Vec3 b = g.toCellCoordinates(source.corner(t, 1));
    const Vec3 d = g.toCellCoordinates(source.corner(t, 2));
    const Vec3 normal = (b - a).cross(d - a);
    if (normal.squaredNorm() <= 0.0) continue;
    const Vec3 n = normal.normalized();
    const double bandCells = std::sqrt(3.0) * 1.001;
    const Vec3 lo = a.cwiseMin(b).cwiseMin(d).array() - bandCells;
    const Vec3 hi = a.cwiseMax(b).cwiseMax(d).array() + bandCells;
    const Vec3i c0 = (lo.array() - 0.5).ceil().cast<int>().max(0);
    const Vec3i c1 = (hi.array() - 0.5).floor().cast<int>().min(g.dims.array() - 1);
    for (int i = c0.x(); i <= c1.x(); ++i)
      for (int j = c0.y(); j <= c1.y(); ++j)
        for (int k = c0.z(); k <= c1.z(); ++k) {
          const Vec3 x(i + 0.5, j + 0.5, k + 0.5);
          if (std::abs(n.dot(x - a)) <= bandCells) candidate[g.index(i, j, k)] = 1;
        }
  }
  const TriangleBvh bvh(source);
  std::vector<double> out(N, std::nan(""));
  for (std::size_t idx = 0; idx < N; ++idx) {
    if (!candidate[idx]) continue;
    const Vec3 p = g.centerInPart(idx);
    const ClosestPoint cp = bvh.closestPoint(p);
    if (cp.distance > band) continue;
    if (grid.inside[idx]) {
      out[idx] = cp.distance;
      continue;
    }
    const auto t = static_cast<std::size_t>(cp.triangle);
    const Vec3 v0 = source.corner(t, 0);
    const Vec3 n = (source.corner(t, 1) - v0).cross(source.corner(t, 2) - v0).normalized();
    const double planeDistance = std::abs(n.dot(p - v0));
    if (planeDistance >= cp.distance * (1.0 - 1e-9) - 1e-12) out[idx] = -cp.distance;
  }
  return out;
}

std::vector<double> insideSourceDistances(const VoxelGrid& grid, const TriMesh& source,
                                          double reach) {
  const GridGeometry& g = grid.geometry;
  const TriangleBvh bvh(source);
  std::vector<double> out(g.cellCount(), std::nan(""));
  for (std::size_t idx = 0; idx < out.size(); ++idx) {
    if (!grid.inside[idx]) continue;
    const ClosestPoint cp = bvh.closestPoint(g.centerInPart(idx));
    if (cp.distance <= reach) out[idx] = cp.distance;
  }
  return out;
}

}  // namespace curvedslicer::testing
