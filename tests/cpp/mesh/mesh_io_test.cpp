// Tests of readMesh / writeMesh / detectMeshFormat (mesh_io.hpp).
#include "curvedslicer/mesh/mesh_io.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "common/shapes.hpp"
#include "common/test_paths.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"

namespace curvedslicer {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using ::testing::HasSubstr;
using testing::makeBox;
using testing::makeSphere;
using testing::modelPath;

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Binary STL bytes with the given 80-byte header text, declared count and float corners
/// (one triangle per 9 floats).
std::string binaryStlBytes(const std::string& headerText, std::uint32_t declared,
                           const std::vector<float>& corners) {
  std::string header = headerText;
  header.resize(80, '\0');
  std::string out = header;
  out.append(reinterpret_cast<const char*>(&declared), 4);
  for (std::size_t t = 0; t + 9 <= corners.size(); t += 9) {
    const float normal[3] = {0, 0, 1};
    out.append(reinterpret_cast<const char*>(normal), 12);
    out.append(reinterpret_cast<const char*>(&corners[t]), 36);
    out.append(2, '\0');
  }
  return out;
}

/// The message of the InvalidInput thrown by readMesh(path); fails the test if none is thrown.
std::string readError(const fs::path& path, MeshFormat format = MeshFormat::Auto) {
  try {
    readMesh(path, format);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  ADD_FAILURE() << "readMesh did not throw InvalidInput for " << path;
  return {};
}

void expectSameTriangles(const TriMesh& a, const TriMesh& b, double tol) {
  ASSERT_EQ(a.triangleCount(), b.triangleCount());
  for (std::size_t t = 0; t < a.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_LE((a.corner(t, k) - b.corner(t, k)).cwiseAbs().maxCoeff(), tol)
          << "triangle " << t << " corner " << k;
    }
  }
}

TEST(MeshIo, BinaryStlRoundTrip) {
  const fs::path dir = freshTempDir();
  const TriMesh box = makeBox(Vec3(-1, 0, 2), Vec3(3, 5, 4.5));
  const fs::path path = dir / "box.stl";
  writeMesh(path, box);
  EXPECT_EQ(fs::file_size(path), 84u + 50u * 12u);
  EXPECT_EQ(detectMeshFormat(path), MeshFormat::StlBinary);
  const TriMesh read = readMesh(path);
  EXPECT_EQ(read.vertexCount(), 36u);   // as stored, not welded
  expectSameTriangles(read, box, 0.0);  // all coordinates are exact in float
  ASSERT_EQ(read.faceIds.size(), 12u);
  for (int t = 0; t < 12; ++t) EXPECT_EQ(read.faceIds[t], t);
  EXPECT_NEAR(signedVolume(cleanMesh(read).mesh), 4 * 5 * 2.5, 1e-12);
}

TEST(MeshIo, BinaryStlStoresFloatPrecision) {
  const fs::path dir = freshTempDir();
  const TriMesh sphere = makeSphere(Vec3(0.1, 0.2, 0.3), 7.7, 2);
  writeMesh(dir / "s.stl", sphere, MeshFormat::StlBinary);
  const TriMesh read = readMesh(dir / "s.stl");
  expectSameTriangles(read, sphere, 1e-6);
  // The reader returns exactly the stored floats. (Compared with the file's bytes rather than
  // with double(float(x)): GCC 12.2 at -O2 drops that rounding when it vectorises it.)
  const std::string bytes = readBytes(dir / "s.stl");
  ASSERT_EQ(bytes.size(), 84 + 50 * read.triangleCount());
  for (std::size_t t = 0; t < read.triangleCount(); ++t) {
    float stored[9];
    std::memcpy(stored, bytes.data() + 84 + 50 * t + 12, sizeof stored);
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) ASSERT_EQ(read.corner(t, k)[a], double{stored[3 * k + a]});
    }
  }
}

TEST(MeshIo, AsciiStlRoundTripIsExact) {
  const fs::path dir = freshTempDir();
  const TriMesh sphere = makeSphere(Vec3(0.1, 0.2, 0.3), 7.7, 2);
  const fs::path path = dir / "s.stl";
  writeMesh(path, sphere, MeshFormat::StlAscii);
  EXPECT_EQ(readBytes(path).rfind("solid", 0), 0u);
  EXPECT_EQ(detectMeshFormat(path), MeshFormat::StlAscii);
  const TriMesh read = readMesh(path);
  expectSameTriangles(read, sphere, 0.0);  // shortest round-trip decimal representation
  ASSERT_EQ(read.faceIds.size(), sphere.triangleCount());
  EXPECT_EQ(read.faceIds.back(), static_cast<int>(sphere.triangleCount()) - 1);
}

TEST(MeshIo, AsciiStlToleratesLayoutVariants) {
  const fs::path dir = freshTempDir();
  const fs::path path = dir / "variants.stl";
  // Upper case keywords, CRLF line ends, tabs, blank lines, two solids, a quad facet.
  writeBytes(path,
             "SOLID first part\r\n"
             "\tFACET NORMAL 0 0 1\r\n  OUTER LOOP\r\n"
             "    VERTEX 0 0 0\r\n    VERTEX 1 0 0\r\n    VERTEX 0 1 0\r\n"
             "  ENDLOOP\r\n ENDFACET\r\n\r\nENDSOLID first part\r\n"
             "solid second\n facet normal 0 0 1\n  outer loop\n"
             "   vertex +1e0 1 0\n   vertex 2 1 0\n   vertex 2 2 0\n   vertex 1 2 0\n"
             "  endloop\n endfacet\nendsolid");
  const TriMesh mesh = readMesh(path);
  ASSERT_EQ(mesh.triangleCount(), 3u);
  EXPECT_EQ(mesh.faceIds, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(mesh.corner(1, 0), Vec3(1, 1, 0));
  EXPECT_EQ(mesh.corner(2, 2), Vec3(1, 2, 0));
}

TEST(MeshIo, BinaryStlWhoseHeaderStartsWithSolid) {
  const fs::path dir = freshTempDir();
  const fs::path path = dir / "solid_header.stl";
  const std::vector<float> corners = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1};
  writeBytes(path, binaryStlBytes("solid exported by a careless CAD tool", 2, corners));
  EXPECT_EQ(detectMeshFormat(path), MeshFormat::StlBinary);
  const TriMesh mesh = readMesh(path);
  ASSERT_EQ(mesh.triangleCount(), 2u);
  EXPECT_EQ(mesh.corner(1, 2), Vec3(0, 0, 1));
}

TEST(MeshIo, ObjRoundTripKeepsIndexing) {
  const fs::path dir = freshTempDir();
  const TriMesh sphere = makeSphere(Vec3(1, 2, 3), 0.3, 2);
  writeMesh(dir / "s.obj", sphere);
  EXPECT_EQ(detectMeshFormat(dir / "s.obj"), MeshFormat::Obj);
  const TriMesh read = readMesh(dir / "s.obj");
  EXPECT_EQ(read.vertices, sphere.vertices);
  EXPECT_EQ(read.triangles, sphere.triangles);
  // Detected from content even without the extension.
  fs::copy_file(dir / "s.obj", dir / "s.mesh");
  EXPECT_EQ(detectMeshFormat(dir / "s.mesh"), MeshFormat::Obj);
  EXPECT_EQ(readMesh(dir / "s.mesh").triangles, sphere.triangles);
}

TEST(MeshIo, ObjQuadsSlashFormsAndNegativeIndices) {
  const fs::path dir = freshTempDir();
  const fs::path path = dir / "quads.obj";
  writeBytes(path,
             "# a unit square as a quad, then a triangle with relative indices\n"
             "mtllib x.mtl\no square\n"
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
             "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
             "usemtl red\ns off\ng group\n"
             "f 1/1/1 2/2/1 3/3/1 4/4/1\r\n"
             "v 0 0 1\n"
             "f -5//1 -4//1 -1//1\n"
             "f 2/2 3/3 5/1\n"
             "l 1 2\n"
             "f 1 2 3 4 5\n");
  const TriMesh mesh = readMesh(path);
  ASSERT_EQ(mesh.vertexCount(), 5u);
  ASSERT_EQ(mesh.triangleCount(), 2u + 1u + 1u + 3u);
  EXPECT_EQ(mesh.triangles[0], Vec3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles[1], Vec3i(0, 2, 3));
  EXPECT_EQ(mesh.triangles[2], Vec3i(0, 1, 4));
  EXPECT_EQ(mesh.triangles[3], Vec3i(1, 2, 4));
  EXPECT_EQ(mesh.triangles[6], Vec3i(0, 3, 4));
  EXPECT_EQ(mesh.faceIds, (std::vector<int>{0, 1, 2, 3, 4, 5, 6}));
}

TEST(MeshIo, BundledModelsRead) {
  for (const char* name :
       {"simple_box_closed_low_res.stl", "bunny_closed_low_res.stl",
        "overhang_coin_closed_low_res.stl", "branches_70_closed_low_res.stl",
        "distorted_v_closed_mid_res.stl", "simple_cylinder_closed_mid_res.stl"}) {
    SCOPED_TRACE(name);
    const fs::path path = modelPath(name);
    EXPECT_EQ(detectMeshFormat(path), MeshFormat::StlBinary);
    const TriMesh mesh = readMesh(path);
    EXPECT_EQ(84 + 50 * mesh.triangleCount(), fs::file_size(path));
    EXPECT_EQ(mesh.vertexCount(), 3 * mesh.triangleCount());
  }
  EXPECT_EQ(readMesh(modelPath("custom_base_geom_to_slice.obj")).triangleCount(), 1820u);
  // 54 triangles and 120 quads.
  const TriMesh surface = readMesh(modelPath("custom_base_surface.obj"));
  EXPECT_EQ(surface.triangleCount(), 54u + 2u * 120u);
  EXPECT_EQ(surface.vertexCount(), 171u);
}

TEST(MeshIo, ReadingAOneMegabyteBinaryStlIsFast) {
  const fs::path path = modelPath("simple_cylinder_closed_mid_res.stl");
  ASSERT_GT(fs::file_size(path), 1'000'000u);
  readMesh(path);  // warm the file cache
  const auto start = std::chrono::steady_clock::now();
  const TriMesh mesh = readMesh(path);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(mesh.triangleCount(), 20200u);
  // About 1 ms in Release; the bound leaves room for sanitizer builds and a busy machine.
  EXPECT_LT(ms, 250.0);
  RecordProperty("read_ms", std::to_string(ms));
}

// ---- bad input ------------------------------------------------------------------------------

TEST(MeshIo, MissingFile) {
  const fs::path path = freshTempDir() / "nope.stl";
  EXPECT_THAT(readError(path), HasSubstr("mesh file not found"));
  EXPECT_THAT(readError(path), HasSubstr("nope.stl"));
  EXPECT_THROW(detectMeshFormat(path), InvalidInput);
}

TEST(MeshIo, EmptyFile) {
  const fs::path path = freshTempDir() / "empty.stl";
  writeBytes(path, "");
  EXPECT_THAT(readError(path), HasSubstr("mesh file is empty"));
}

TEST(MeshIo, FileShorterThanTheBinaryHeader) {
  const fs::path path = freshTempDir() / "short.stl";
  writeBytes(path, std::string(40, '\x01'));
  EXPECT_THAT(readError(path), HasSubstr("binary STL is truncated"));
  EXPECT_THAT(readError(path), HasSubstr("40 bytes"));
}

TEST(MeshIo, BinaryStlCountDisagreesWithSize) {
  const fs::path dir = freshTempDir();
  std::vector<float> corners(9 * 12, 0.5f);
  std::string bytes = binaryStlBytes("truncated", 12, corners);
  bytes.resize(bytes.size() - 84);  // 684 bytes expected, 600 present
  writeBytes(dir / "cut.stl", bytes);
  const std::string message = readError(dir / "cut.stl");
  EXPECT_THAT(message, HasSubstr("declares 12 triangles"));
  EXPECT_THAT(message, HasSubstr("expected size 684 bytes"));
  EXPECT_THAT(message, HasSubstr("actual size 600 bytes"));
  // Same for a binary file whose header begins with "solid" (not taken for ASCII).
  std::string solid = binaryStlBytes("solid x", 12, corners);
  solid.resize(solid.size() - 84);
  writeBytes(dir / "cut_solid.stl", solid);
  EXPECT_THAT(readError(dir / "cut_solid.stl"), HasSubstr("actual size 600 bytes"));
}

TEST(MeshIo, BinaryStlWithZeroTriangles) {
  const fs::path path = freshTempDir() / "zero.stl";
  writeBytes(path, binaryStlBytes("nothing", 0, {}));
  EXPECT_THAT(readError(path), HasSubstr("no triangles"));
}

TEST(MeshIo, BinaryStlWithNanNamesTriangleAndVertex) {
  const fs::path path = freshTempDir() / "nan.stl";
  std::vector<float> corners(18, 1.0f);
  corners[9 + 7] = std::numeric_limits<float>::quiet_NaN();  // triangle 1, vertex 2, y
  writeBytes(path, binaryStlBytes("nan", 2, corners));
  const std::string message = readError(path);
  EXPECT_THAT(message, HasSubstr("non-finite coordinate"));
  EXPECT_THAT(message, HasSubstr("triangle 1 vertex 2"));
}

TEST(MeshIo, AsciiStlParseErrorHasLineNumber) {
  const fs::path path = freshTempDir() / "bad.stl";
  writeBytes(path,
             "solid bad\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
             "   vertex 1 zero 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid\n");
  const std::string message = readError(path);
  EXPECT_THAT(message, HasSubstr("ASCII STL parse error"));
  EXPECT_THAT(message, HasSubstr("line 5"));
  EXPECT_THAT(message, HasSubstr("'zero'"));
}

TEST(MeshIo, AsciiStlUnexpectedKeyword) {
  const fs::path path = freshTempDir() / "bad.stl";
  writeBytes(path, "solid bad\n facet normal 0 0 1\n  inner loop\n");
  EXPECT_THAT(readError(path), HasSubstr("line 3: expected 'outer', found 'inner'"));
}

TEST(MeshIo, AsciiStlTruncated) {
  const fs::path dir = freshTempDir();
  writeBytes(dir / "a.stl", "solid cut\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n");
  EXPECT_THAT(readError(dir / "a.stl"), HasSubstr("ASCII STL is truncated"));
  EXPECT_THAT(readError(dir / "a.stl"), HasSubstr("inside a facet"));
  writeBytes(dir / "b.stl",
             "solid cut\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
             "   vertex 0 1 0\n  endloop\n endfacet\n");
  EXPECT_THAT(readError(dir / "b.stl"), HasSubstr("no 'endsolid'"));
}

TEST(MeshIo, AsciiStlWithInfinityNamesLine) {
  const fs::path path = freshTempDir() / "inf.stl";
  writeBytes(path,
             "solid inf\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
             "   vertex 1 0 inf\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid\n");
  const std::string message = readError(path);
  EXPECT_THAT(message, HasSubstr("non-finite coordinate"));
  EXPECT_THAT(message, HasSubstr("line 5 (triangle 0)"));
}

TEST(MeshIo, AsciiStlWithoutFacets) {
  const fs::path path = freshTempDir() / "hollow.stl";
  writeBytes(path, "solid hollow\nendsolid hollow\n");
  EXPECT_THAT(readError(path), HasSubstr("no triangles"));
}

TEST(MeshIo, ObjIndexOutOfRange) {
  const fs::path dir = freshTempDir();
  writeBytes(dir / "a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n");
  std::string message = readError(dir / "a.obj");
  EXPECT_THAT(message, HasSubstr("OBJ index out of range"));
  EXPECT_THAT(message, HasSubstr("line 5"));
  EXPECT_THAT(message, HasSubstr("vertex 7 but the file has 3 vertices"));
  writeBytes(dir / "b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
  message = readError(dir / "b.obj");
  EXPECT_THAT(message, HasSubstr("OBJ index out of range: -4"));
  EXPECT_THAT(message, HasSubstr("line 4"));
  writeBytes(dir / "c.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  EXPECT_THAT(readError(dir / "c.obj"), HasSubstr("line 4: expected a vertex index"));
}

TEST(MeshIo, ObjParseErrors) {
  const fs::path dir = freshTempDir();
  writeBytes(dir / "a.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_THAT(readError(dir / "a.obj"),
              HasSubstr("line 2: expected a vertex coordinate, found end of line"));
  writeBytes(dir / "b.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
  EXPECT_THAT(readError(dir / "b.obj"), HasSubstr("line 3: a face needs at least 3 vertices"));
  writeBytes(dir / "c.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_THAT(readError(dir / "c.obj"), HasSubstr("non-finite coordinate"));
  EXPECT_THAT(readError(dir / "c.obj"), HasSubstr("vertex 2 (line 2)"));
  writeBytes(dir / "d.obj", "# only points\nv 0 0 0\nv 1 0 0\n");
  EXPECT_THAT(readError(dir / "d.obj"), HasSubstr("no triangles"));
}

TEST(MeshIo, PlyIsWriteOnly) {
  const fs::path dir = freshTempDir();
  writeMesh(dir / "box.ply", makeBox(Vec3::Zero(), Vec3::Ones()));
  EXPECT_THAT(readError(dir / "box.ply", MeshFormat::Ply), HasSubstr("reading PLY"));
}

// ---- writers --------------------------------------------------------------------------------

TEST(MeshIo, BinaryPlyLayout) {
  const fs::path path = freshTempDir() / "box.ply";
  TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(1, 2, 3));
  for (std::size_t t = 0; t < box.triangleCount(); ++t) box.faceIds[t] = static_cast<int>(t) + 100;
  writeMesh(path, box);
  const std::string bytes = readBytes(path);
  const std::string endHeader = "end_header\n";
  const std::size_t bodyStart = bytes.find(endHeader) + endHeader.size();
  const std::string header = bytes.substr(0, bodyStart);
  EXPECT_THAT(header, HasSubstr("format binary_little_endian 1.0\n"));
  EXPECT_THAT(header, HasSubstr("element vertex 8\n"));
  EXPECT_THAT(header, HasSubstr("element face 12\n"));
  EXPECT_THAT(header, HasSubstr("property int face_id\n"));
  ASSERT_EQ(bytes.size(), bodyStart + 8 * 24 + 12 * (1 + 12 + 4));
  const char* body = bytes.data() + bodyStart;
  for (int i = 0; i < 8; ++i) {
    double p[3];
    std::memcpy(p, body + 24 * i, 24);
    EXPECT_EQ(Vec3(p[0], p[1], p[2]), box.vertices[i]);
  }
  const char* face = body + 8 * 24 + 5 * 17;  // face 5
  EXPECT_EQ(face[0], 3);
  std::int32_t idx[4];
  std::memcpy(idx, face + 1, 16);
  EXPECT_EQ(Vec3i(idx[0], idx[1], idx[2]), box.triangles[5]);
  EXPECT_EQ(idx[3], 105);
}

TEST(MeshIo, AsciiPlyLayout) {
  const fs::path path = freshTempDir() / "box.ply";
  TriMesh box = makeBox(Vec3(0, 0, 0), Vec3(1, 2, 3.5));
  box.faceIds.clear();
  writeMesh(path, box, MeshFormat::PlyAscii);
  std::istringstream in(readBytes(path));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "ply");
  std::getline(in, line);
  EXPECT_EQ(line, "format ascii 1.0");
  while (std::getline(in, line) && line != "end_header") {
    EXPECT_THAT(line, ::testing::Not(HasSubstr("face_id")));
  }
  for (int i = 0; i < 8; ++i) {
    Vec3 p;
    in >> p.x() >> p.y() >> p.z();
    EXPECT_EQ(p, box.vertices[i]);
  }
  for (int t = 0; t < 12; ++t) {
    int n = 0;
    Vec3i tri;
    in >> n >> tri[0] >> tri[1] >> tri[2];
    EXPECT_EQ(n, 3);
    EXPECT_EQ(tri, box.triangles[t]);
  }
  EXPECT_TRUE(static_cast<bool>(in));
}

TEST(MeshIo, UnknownExtensionIsRejected) {
  const fs::path dir = freshTempDir();
  try {
    writeMesh(dir / "box.dxf", makeBox(Vec3::Zero(), Vec3::Ones()));
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("unknown mesh file extension"));
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(MeshIo, AtomicWriteLeavesNoTemporaryFile) {
  const fs::path dir = freshTempDir();
  writeMesh(dir / "a.stl", makeBox(Vec3::Zero(), Vec3::Ones()));
  writeMesh(dir / "a.stl", makeBox(Vec3::Zero(), Vec3(2, 2, 2)));  // replaces
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "a.stl");
  }
  EXPECT_EQ(files, 1u);
  EXPECT_NEAR(signedVolume(cleanMesh(readMesh(dir / "a.stl")).mesh), 8.0, 1e-12);
}

TEST(MeshIo, FailedWriteKeepsTheExistingFile) {
  const fs::path dir = freshTempDir();
  const fs::path path = dir / "keep.obj";
  writeBytes(path, "original");
  TriMesh broken = makeBox(Vec3::Zero(), Vec3::Ones());
  broken.triangles[3][1] = 99;
  EXPECT_THROW(writeMesh(path, broken), InvalidInput);
  EXPECT_EQ(readBytes(path), "original");
  // A failure after the data was written (the target is a non-empty folder, so the final rename
  // fails): IoError, the folder untouched, no temporary file left behind.
  const fs::path blocked = dir / "blocked.stl";
  fs::create_directory(blocked);
  writeBytes(blocked / "inside", "x");
  EXPECT_THROW(writeMesh(blocked, makeBox(Vec3::Zero(), Vec3::Ones())), IoError);
  EXPECT_TRUE(fs::is_directory(blocked));
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 2u);  // keep.obj and blocked.stl only
  EXPECT_THROW(writeMesh(dir / "missing" / "x.stl", broken), InvalidInput);
  EXPECT_THROW(writeMesh(dir / "missing" / "x.stl", makeBox(Vec3::Zero(), Vec3::Ones())), IoError);
}

}  // namespace
}  // namespace curvedslicer
