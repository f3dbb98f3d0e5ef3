// The mesh reader on absurd coordinates: 1e308 is finite but no part, and its box
// overflows; it is refused at the reader with the vertex and the file, not reported later as
// "the model has no vertices". parseMesh reads in-memory data as readMesh reads a file.
#include <gtest/gtest.h>

#include <string>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"

namespace curvedslicer {
namespace {

std::string parseError(const std::string& data, const std::string& name) {
  try {
    parseMesh(data, name);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(MeshIoRobustness, CoordinatesBeyondABillionMillimetresAreRefused) {
  const std::string obj =
      "v 0 0 0\nv 1e308 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\n"
      "f 2 4 3\n";
  const std::string message = parseError(obj, "huge.obj");
  EXPECT_NE(message.find("coordinate beyond ±1e9 mm (1e+308, 0, 0)"), std::string::npos) << message;
  EXPECT_NE(message.find("huge.obj"), std::string::npos) << message;
  const std::string stl =
      "solid s\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\n"
      "vertex 0 -2e9 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid s\n";
  EXPECT_NE(parseError(stl, "huge.stl").find("coordinate beyond ±1e9 mm"), std::string::npos);
  // A billion millimetres itself is accepted.
  const TriMesh mesh = parseMesh("v 0 0 0\nv 1e9 0 0\nv 0 1 0\nf 1 2 3\n", "edge.obj");
  EXPECT_EQ(mesh.triangleCount(), 1u);
}

TEST(MeshIoRobustness, CadFilesAreNamedAsCadNotTakenForACorruptStl) {
  // e.g. a STEP given as a start surface mesh: read as binary STL its header declared 1.4 billion
  // triangles
  const std::string step =
      parseError("ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('x'),'2;1');\n", "boss.step");
  EXPECT_NE(step.find("'boss.step' is a STEP file (CAD surfaces), not a triangle mesh (STL or "
                      "OBJ); pass CAD models as the part"),
            std::string::npos)
      << step;
  const std::string brep =
      parseError("DBRep_DrawableShape\n\nCASCADE Topology V1, (c) Matra-Datavision\n", "box.brep");
  EXPECT_NE(brep.find("is an OpenCASCADE BREP file"), std::string::npos) << brep;
}

TEST(MeshIoRobustness, ParseMeshMatchesTheFileReadersErrors) {
  EXPECT_NE(parseError("v 0 0 0\nf 1 2 3\n", "bad.obj").find("bad.obj"), std::string::npos);
  EXPECT_NE(parseError("", "empty.stl").find("empty.stl"), std::string::npos);
}

}  // namespace
}  // namespace curvedslicer
