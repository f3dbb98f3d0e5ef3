// Writes the large thin-walled part of the scale benchmark: an open-top box
// shell, by default 600 × 400 × 300 mm with 8 mm walls (floor and four side walls), as a closed
// binary STL through the project's mesh writer. `large_part_bench.sh` then runs the command line's
// `layers` and `plan` jobs on it under /usr/bin/time and summarises report.json; see README.md,
// section "Large thin-walled part".
//
// Usage: large_part_bench OUT.stl [SIZE_X SIZE_Y SIZE_Z WALL]   (mm)
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "common/shapes.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/mesh/mesh_report.hpp"

namespace {

double parsePositive(const char* text, const char* what) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(value > 0.0)) {
    throw std::invalid_argument(std::string(what) + " must be a positive number of mm: '" + text +
                                "'; pass e.g. 600");
  }
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace curvedslicer;
  if (argc != 2 && argc != 6) {
    std::fprintf(stderr,
                 "usage: %s OUT.stl [SIZE_X SIZE_Y SIZE_Z WALL]  (mm; default 600 400 300 8)\n",
                 argv[0]);
    return 2;
  }
  try {
    Vec3 size(600.0, 400.0, 300.0);
    double wall = 8.0;
    if (argc == 6) {
      size = Vec3(parsePositive(argv[2], "size x"), parsePositive(argv[3], "size y"),
                  parsePositive(argv[4], "size z"));
      wall = parsePositive(argv[5], "wall");
    }
    const TriMesh part = testing::makeOpenBox(size, wall);
    writeMesh(argv[1], part);
    // Read back and welded as the layer job does (an STL is a triangle soup).
    const MeshReport report = analyzeMesh(cleanMesh(readMesh(argv[1])).mesh);
    const bool good = report.closed() && report.consistentlyOriented() && report.volume > 0.0;
    std::printf(
        "%s: open-top box %g x %g x %g mm, wall %g mm, %zu triangles, %s, volume %.0f mm^3\n",
        argv[1], size.x(), size.y(), size.z(), wall, part.triangles.size(),
        good ? "closed and outward-oriented" : "NOT CLOSED/ORIENTED", report.volume);
    return good ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "large_part_bench: error: %s\n", error.what());
    return 2;
  }
}
