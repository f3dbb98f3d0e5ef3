// libFuzzer target: the STL/OBJ reader (mesh_io) on arbitrary bytes. The first byte chooses how
// the data is named ("fuzz.stl" lets the content decide, "fuzz.obj" forces OBJ), the rest is the
// file. The reader may only return a mesh or throw a curvedslicer::Error.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool obj = (data[0] & 1) != 0;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const curvedslicer::TriMesh mesh = curvedslicer::parseMesh(text, obj ? "fuzz.obj" : "fuzz.stl");
    (void)mesh.bounds();
  } catch (const curvedslicer::Error&) {
  }
  return 0;
}
