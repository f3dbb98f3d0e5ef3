// STL / OBJ readers and STL / OBJ / PLY writers. Files are read into memory in one call and
// parsed from the buffer (binary STL by memcpy of whole records, text with std::from_chars);
// writers build the file in memory and hand it to writeFileAtomically.
#include "curvedslicer/mesh/mesh_io.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kStlHeaderBytes = 84;  // 80-byte header + uint32 triangle count
constexpr std::size_t kStlRecordBytes = 50;  // normal, 3 vertices (12 floats) + uint16 attribute

std::string quoted(const fs::path& path) {
  return "'" + path.string() + "'";
}

// ---- byte order ---------------------------------------------------------------------------------

template <typename T>
T fromLittleEndian(const char* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    char swapped[sizeof(T)];
    for (std::size_t i = 0; i < sizeof(T); ++i) swapped[i] = bytes[sizeof(T) - 1 - i];
    std::memcpy(&value, swapped, sizeof(T));
  }
  return value;
}

template <typename T>
void appendLittleEndian(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
  out.append(bytes, sizeof(T));
}

// ---- file access --------------------------------------------------------------------------------

/// The whole file; throws InvalidInput for a missing or empty file, IoError if it cannot be read.
std::string readWholeFile(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    throw InvalidInput("mesh file not found: " + quoted(path) + "; check the path");
  }
  if (fs::is_directory(path, ec)) {
    throw InvalidInput("mesh path is a folder, not a file: " + quoted(path) +
                       "; pass an .stl or .obj file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw IoError("cannot open mesh file " + quoted(path) + ": " + std::strerror(errno) +
                  "; check its permissions");
  }
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  if (size < 0) throw IoError("cannot determine the size of mesh file " + quoted(path));
  std::string data(static_cast<std::size_t>(size), '\0');
  if (size > 0 && !in.read(data.data(), size)) {
    throw IoError("reading mesh file " + quoted(path) + " failed; check the disk and permissions");
  }
  if (data.empty()) {
    throw InvalidInput("mesh file is empty (0 bytes): " + quoted(path) + "; re-export the model");
  }
  return data;
}

bool hasExtension(const fs::path& path, std::string_view ext) {
  std::string e = path.extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e == ext;
}

// ---- text scanning ------------------------------------------------------------------------------

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/// Splits a buffer into lines (without '\n' or a trailing '\r') and each line into tokens.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}

  /// Advances to the next line; false at the end of the text.
  bool next() {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line_ = text_.substr(pos_, stop - pos_);
    pos_ = end == std::string_view::npos ? text_.size() : end + 1;
    ++number_;
    cursor_ = 0;
    return true;
  }
  /// The next whitespace-separated token of the current line (empty at its end).
  std::string_view token() {
    while (cursor_ < line_.size() && isSpace(line_[cursor_])) ++cursor_;
    const std::size_t begin = cursor_;
    while (cursor_ < line_.size() && !isSpace(line_[cursor_])) ++cursor_;
    return line_.substr(begin, cursor_ - begin);
  }
  std::size_t lineNumber() const { return number_; }

 private:
  std::string_view text_;
  std::string_view line_;
  std::size_t pos_ = 0;
  std::size_t cursor_ = 0;
  std::size_t number_ = 0;
};

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i]))) {
      return false;
    }
  }
  return true;
}

/// Parses a whole token as a double ("nan"/"inf" included; the caller checks finiteness).
bool parseDouble(std::string_view token, double& value) {
  if (token.empty()) return false;
  if (token.front() == '+') token.remove_prefix(1);  // from_chars rejects a leading '+'
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && end == token.data() + token.size();
}

std::string shown(std::string_view token) {
  if (token.empty()) return "end of line";
  std::string s(token.substr(0, 40));
  return "'" + s + (token.size() > 40 ? "...'" : "'");
}

std::string formatDouble(double v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, ec == std::errc() ? end : buf);
}

/// Text starts with "solid" (after optional whitespace) and holds no NUL or other binary bytes
/// in its first kilobyte.
bool looksLikeAsciiStl(std::string_view data) {
  std::size_t i = 0;
  while (i < data.size() && std::isspace(static_cast<unsigned char>(data[i]))) ++i;
  if (data.size() - i < 5 || !equalsIgnoreCase(data.substr(i, 5), "solid")) return false;
  const std::size_t probe = std::min<std::size_t>(data.size(), 1024);
  for (std::size_t k = 0; k < probe; ++k) {
    const auto c = static_cast<unsigned char>(data[k]);
    if (c == 0 || (c < 32 && !std::isspace(c))) return false;
  }
  return true;
}

/// Plain text whose first statement is an OBJ keyword.
bool looksLikeObj(std::string_view data) {
  const std::size_t probe = std::min<std::size_t>(data.size(), 4096);
  for (std::size_t k = 0; k < probe; ++k) {
    const auto c = static_cast<unsigned char>(data[k]);
    if (c == 0 || (c < 32 && !std::isspace(c))) return false;
  }
  LineReader lines(data.substr(0, probe));
  while (lines.next()) {
    const std::string_view key = lines.token();
    if (key.empty() || key.front() == '#') continue;
    return key == "v" || key == "vt" || key == "vn" || key == "vp" || key == "f" || key == "o" ||
           key == "g" || key == "s" || key == "mtllib" || key == "usemtl";
  }
  return false;
}

bool binaryStlSizeMatches(std::string_view data) {
  if (data.size() < kStlHeaderBytes) return false;
  const auto count = fromLittleEndian<std::uint32_t>(data.data() + 80);
  return data.size() == kStlHeaderBytes + kStlRecordBytes * std::uint64_t{count};
}

/// The CAD exchange format `data` is in (STEP, BREP, IGES), or null: CAD files hold surfaces,
/// not triangles, and read as a mesh they would be taken for a corrupt binary STL.
const char* cadFormatOf(std::string_view data) {
  std::size_t i = 0;
  while (i < data.size() && i < 64 && std::isspace(static_cast<unsigned char>(data[i]))) ++i;
  const std::string_view head = data.substr(i, 32);
  if (head.starts_with("ISO-10303-21")) return "STEP";
  if (head.starts_with("DBRep_DrawableShape") || head.starts_with("CASCADE Topology")) {
    return "OpenCASCADE BREP";
  }
  if (data.size() >= 80 && data.substr(72, 1) == "S" && data.substr(73, 7) == "      1") {
    return "IGES";
  }
  return nullptr;
}

MeshFormat detectFormat(std::string_view data, const fs::path& path) {
  if (const char* cad = cadFormatOf(data)) {
    throw InvalidInput(quoted(path) + " is " + (cad[0] == 'O' ? "an " : "a ") + cad +
                       " file (CAD surfaces), not a triangle mesh (STL or OBJ); pass CAD models "
                       "as the part (with --start faces:N to start from its faces), or export "
                       "this surface as STL");
  }
  if (binaryStlSizeMatches(data)) return MeshFormat::StlBinary;
  if (looksLikeAsciiStl(data)) return MeshFormat::StlAscii;
  if (hasExtension(path, ".obj") || looksLikeObj(data)) return MeshFormat::Obj;
  return MeshFormat::StlBinary;  // reported as a size mismatch / truncated binary STL
}

/// Largest coordinate magnitude accepted, mm (1000 km): beyond it differences and volumes of the
/// model overflow or lose all precision, and no part to be welded is that large.
constexpr double kMaxCoordinate = 1e9;

void requireFinite(const Vec3& p, const fs::path& path, const std::string& where) {
  const std::string point =
      "(" + formatDouble(p.x()) + ", " + formatDouble(p.y()) + ", " + formatDouble(p.z()) + ")";
  if (!p.allFinite()) {
    throw InvalidInput("non-finite coordinate " + point + " at " + where + " of " + quoted(path) +
                       "; repair or re-export the model");
  }
  if (p.cwiseAbs().maxCoeff() > kMaxCoordinate) {
    throw InvalidInput("coordinate beyond ±1e9 mm " + point + " at " + where + " of " +
                       quoted(path) + "; check the model's units or re-export it");
  }
}

// ---- STL ----------------------------------------------------------------------------------------

TriMesh readBinaryStl(std::string_view data, const fs::path& path) {
  if (data.size() < kStlHeaderBytes) {
    throw InvalidInput("binary STL is truncated: " + quoted(path) + " has " +
                       std::to_string(data.size()) +
                       " bytes, fewer than the 84-byte header; re-export the model");
  }
  const auto count = fromLittleEndian<std::uint32_t>(data.data() + 80);
  const std::uint64_t expected = kStlHeaderBytes + kStlRecordBytes * std::uint64_t{count};
  if (data.size() != expected) {
    throw InvalidInput("binary STL size disagrees with its triangle count: " + quoted(path) +
                       " declares " + std::to_string(count) + " triangles, expected size " +
                       std::to_string(expected) + " bytes, actual size " +
                       std::to_string(data.size()) +
                       " bytes; the file is truncated or corrupt, re-export it");
  }
  if (count == 0) {
    throw InvalidInput("mesh has no triangles: " + quoted(path) +
                       " declares 0 triangles; export the solid with its surface");
  }
  TriMesh mesh;
  mesh.vertices.resize(std::size_t{count} * 3);
  mesh.triangles.resize(count);
  mesh.faceIds.resize(count);
  const char* record = data.data() + kStlHeaderBytes;
  for (std::uint32_t t = 0; t < count; ++t, record += kStlRecordBytes) {
    float xyz[9];
    if constexpr (std::endian::native == std::endian::little) {
      std::memcpy(xyz, record + 12, sizeof xyz);
    } else {
      for (int k = 0; k < 9; ++k) xyz[k] = fromLittleEndian<float>(record + 12 + 4 * k);
    }
    for (int k = 0; k < 3; ++k) {
      const Vec3 p(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
      if (!p.allFinite()) {
        requireFinite(p, path, "triangle " + std::to_string(t) + " vertex " + std::to_string(k));
      }
      mesh.vertices[3 * std::size_t{t} + k] = p;
    }
    const int base = static_cast<int>(3 * t);
    mesh.triangles[t] = Vec3i(base, base + 1, base + 2);
    mesh.faceIds[t] = static_cast<int>(t);
  }
  return mesh;
}

TriMesh readAsciiStl(std::string_view data, const fs::path& path) {
  LineReader lines(data);
  TriMesh mesh;
  auto fail = [&](const std::string& what) -> void {
    throw InvalidInput("ASCII STL parse error in " + quoted(path) + " at line " +
                       std::to_string(lines.lineNumber()) + ": " + what +
                       "; fix or re-export the file");
  };
  auto truncated = [&](const std::string& inside) -> void {
    throw InvalidInput("ASCII STL is truncated: " + quoted(path) + " ends at line " +
                       std::to_string(lines.lineNumber()) + " inside " + inside +
                       "; re-export the model");
  };
  // Next non-empty line's first token.
  auto keyword = [&]() -> std::string_view {
    while (lines.next()) {
      const std::string_view key = lines.token();
      if (!key.empty()) return key;
    }
    return {};
  };
  auto expectWord = [&](std::string_view got, std::string_view want) {
    if (!equalsIgnoreCase(got, want)) {
      fail("expected '" + std::string(want) + "', found " + shown(got));
    }
  };
  enum class State { Outside, InSolid };
  State state = State::Outside;
  for (std::string_view key = keyword(); !key.empty(); key = keyword()) {
    if (state == State::Outside) {
      expectWord(key, "solid");  // the rest of the line is the solid's name
      state = State::InSolid;
      continue;
    }
    if (equalsIgnoreCase(key, "endsolid")) {
      state = State::Outside;
      continue;
    }
    expectWord(key, "facet");
    // "facet normal nx ny nz": the normal is ignored (recomputed from the vertices).
    std::vector<Vec3> loop;
    key = keyword();
    if (key.empty()) truncated("a facet");
    expectWord(key, "outer");
    expectWord(lines.token(), "loop");
    for (;;) {
      key = keyword();
      if (key.empty()) truncated("a facet");
      if (equalsIgnoreCase(key, "endloop")) break;
      expectWord(key, "vertex");
      Vec3 p;
      for (int a = 0; a < 3; ++a) {
        const std::string_view tok = lines.token();
        if (!parseDouble(tok, p[a])) fail("expected a number, found " + shown(tok));
      }
      const std::string_view extra = lines.token();
      if (!extra.empty()) fail("expected end of line after vertex, found " + shown(extra));
      requireFinite(p, path,
                    "line " + std::to_string(lines.lineNumber()) + " (triangle " +
                        std::to_string(mesh.triangles.size()) + ")");
      loop.push_back(p);
    }
    if (loop.size() < 3) {
      fail("a facet needs 3 vertices, found " + std::to_string(loop.size()));
    }
    key = keyword();
    if (key.empty()) truncated("a facet");
    expectWord(key, "endfacet");
    // Polygonal facets (rare) are fan-triangulated.
    const int base = static_cast<int>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), loop.begin(), loop.end());
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
      mesh.faceIds.push_back(static_cast<int>(mesh.triangles.size()));
      mesh.triangles.emplace_back(base, base + static_cast<int>(k), base + static_cast<int>(k) + 1);
    }
  }
  if (state == State::InSolid) truncated("a solid (no 'endsolid')");
  return mesh;
}

// ---- OBJ ----------------------------------------------------------------------------------------

TriMesh readObj(std::string_view data, const fs::path& path) {
  LineReader lines(data);
  TriMesh mesh;
  std::vector<std::size_t> faceLine;  // line of each triangle, for index errors
  std::vector<long long> corners;
  auto fail = [&](const std::string& what) -> void {
    throw InvalidInput("OBJ parse error in " + quoted(path) + " at line " +
                       std::to_string(lines.lineNumber()) + ": " + what +
                       "; fix or re-export the file");
  };
  while (lines.next()) {
    const std::string_view key = lines.token();
    if (key == "v") {
      Vec3 p;
      for (int a = 0; a < 3; ++a) {
        const std::string_view tok = lines.token();
        if (!parseDouble(tok, p[a])) fail("expected a vertex coordinate, found " + shown(tok));
      }
      requireFinite(p, path,
                    "vertex " + std::to_string(mesh.vertices.size() + 1) + " (line " +
                        std::to_string(lines.lineNumber()) + ")");
      mesh.vertices.push_back(p);
    } else if (key == "f") {
      corners.clear();
      for (std::string_view tok = lines.token(); !tok.empty(); tok = lines.token()) {
        // "i", "i/t", "i//n" or "i/t/n": only the position index i is used.
        const std::string_view first = tok.substr(0, tok.find('/'));
        long long index = 0;
        const auto [end, ec] = std::from_chars(first.data(), first.data() + first.size(), index);
        if (ec != std::errc() || end != first.data() + first.size() || index == 0) {
          fail("expected a vertex index (1-based, or negative from the end), found " + shown(tok));
        }
        if (index < 0) {  // relative to the vertices read so far: -1 is the last
          const long long resolved = static_cast<long long>(mesh.vertices.size()) + index + 1;
          if (resolved < 1) {
            fail("OBJ index out of range: " + std::to_string(index) + " with only " +
                 std::to_string(mesh.vertices.size()) + " vertices defined before it");
          }
          index = resolved;
        }
        corners.push_back(index - 1);
      }
      if (corners.size() < 3) {
        fail("a face needs at least 3 vertices, found " + std::to_string(corners.size()));
      }
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        // Positive indices may refer to vertices defined later; checked at the end.
        mesh.triangles.emplace_back(
            static_cast<int>(std::min<long long>(corners[0], INT32_MAX)),
            static_cast<int>(std::min<long long>(corners[k], INT32_MAX)),
            static_cast<int>(std::min<long long>(corners[k + 1], INT32_MAX)));
        faceLine.push_back(lines.lineNumber());
      }
    }
    // Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, comments) is ignored.
  }
  const auto n = static_cast<long long>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.triangles[t][k] >= n) {
        throw InvalidInput("OBJ index out of range in " + quoted(path) + " at line " +
                           std::to_string(faceLine[t]) + ": vertex " +
                           std::to_string(static_cast<long long>(mesh.triangles[t][k]) + 1) +
                           " but the file has " + std::to_string(n) +
                           " vertices; fix or re-export the file");
      }
    }
  }
  mesh.faceIds.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.faceIds.size(); ++t) mesh.faceIds[t] = static_cast<int>(t);
  return mesh;
}

// ---- writers ------------------------------------------------------------------------------------

void validateForWriting(const TriMesh& mesh, const fs::path& path) {
  const auto n = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3i& tri = mesh.triangles[t];
    if ((tri.array() < 0).any() || (tri.array() >= n).any()) {
      throw InvalidInput("triangle " + std::to_string(t) + " has a vertex index out of range (" +
                         std::to_string(tri[0]) + ", " + std::to_string(tri[1]) + ", " +
                         std::to_string(tri[2]) + ") for " + std::to_string(n) +
                         " vertices; not writing " + quoted(path));
    }
  }
}

Vec3 unitNormal(const TriMesh& mesh, std::size_t t) {
  const Vec3 n = mesh.areaNormal(t);
  const double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

std::string binaryStl(const TriMesh& mesh) {
  std::string out;
  out.reserve(kStlHeaderBytes + kStlRecordBytes * mesh.triangles.size());
  std::string header = "binary STL written by CurvedSlicer";
  header.resize(80, ' ');  // spaces, and not "solid", so no reader takes it for ASCII
  out += header;
  appendLittleEndian(out, static_cast<std::uint32_t>(mesh.triangles.size()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3 n = unitNormal(mesh, t);
    for (int a = 0; a < 3; ++a) appendLittleEndian(out, static_cast<float>(n[a]));
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) appendLittleEndian(out, static_cast<float>(mesh.corner(t, k)[a]));
    }
    appendLittleEndian(out, std::uint16_t{0});
  }
  return out;
}

std::string asciiStl(const TriMesh& mesh) {
  std::string out = "solid curvedslicer\n";
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3 n = unitNormal(mesh, t);
    out += "  facet normal " + formatDouble(n.x()) + " " + formatDouble(n.y()) + " " +
           formatDouble(n.z()) + "\n    outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.corner(t, k);
      out += "      vertex " + formatDouble(p.x()) + " " + formatDouble(p.y()) + " " +
             formatDouble(p.z()) + "\n";
    }
    out += "    endloop\n  endfacet\n";
  }
  out += "endsolid curvedslicer\n";
  return out;
}

std::string obj(const TriMesh& mesh) {
  std::string out = "# written by CurvedSlicer\n";
  for (const Vec3& p : mesh.vertices) {
    out +=
        "v " + formatDouble(p.x()) + " " + formatDouble(p.y()) + " " + formatDouble(p.z()) + "\n";
  }
  for (const Vec3i& t : mesh.triangles) {
    out += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
           std::to_string(t[2] + 1) + "\n";
  }
  return out;
}

/// PLY with double vertices and, when the mesh has face ids, an int `face_id` per face.
std::string ply(const TriMesh& mesh, bool binary) {
  const bool ids = !mesh.faceIds.empty() && mesh.faceIds.size() == mesh.triangles.size();
  std::string out = "ply\nformat ";
  out += binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  out += "comment written by CurvedSlicer (mm, part frame)\n";
  out += "element vertex " + std::to_string(mesh.vertices.size()) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  out += "element face " + std::to_string(mesh.triangles.size()) + "\n";
  out += "property list uchar int vertex_indices\n";
  if (ids) out += "property int face_id\n";
  out += "end_header\n";
  if (binary) {
    for (const Vec3& p : mesh.vertices) {
      for (int a = 0; a < 3; ++a) appendLittleEndian(out, p[a]);
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      appendLittleEndian(out, std::uint8_t{3});
      for (int k = 0; k < 3; ++k) appendLittleEndian(out, std::int32_t{mesh.triangles[t][k]});
      if (ids) appendLittleEndian(out, std::int32_t{mesh.faceIds[t]});
    }
  } else {
    for (const Vec3& p : mesh.vertices) {
      out += formatDouble(p.x()) + " " + formatDouble(p.y()) + " " + formatDouble(p.z()) + "\n";
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Vec3i& tri = mesh.triangles[t];
      out += "3 " + std::to_string(tri[0]) + " " + std::to_string(tri[1]) + " " +
             std::to_string(tri[2]);
      if (ids) out += " " + std::to_string(mesh.faceIds[t]);
      out += "\n";
    }
  }
  return out;
}

}  // namespace

MeshFormat detectMeshFormat(const fs::path& path) {
  return detectFormat(readWholeFile(path), path);
}

TriMesh readMesh(const fs::path& path, MeshFormat format) {
  return parseMesh(readWholeFile(path), path, format);
}

TriMesh parseMesh(std::string_view data, const fs::path& path, MeshFormat format) {
  if (format == MeshFormat::Auto) format = detectFormat(data, path);
  TriMesh mesh;
  switch (format) {
    case MeshFormat::StlBinary:
      mesh = readBinaryStl(data, path);
      break;
    case MeshFormat::StlAscii:
      mesh = readAsciiStl(data, path);
      break;
    case MeshFormat::Obj:
      mesh = readObj(data, path);
      break;
    case MeshFormat::Ply:
    case MeshFormat::PlyAscii:
    case MeshFormat::Auto:
      throw InvalidInput("reading PLY is not supported: " + quoted(path) +
                         "; convert the mesh to STL or OBJ");
  }
  if (mesh.triangles.empty()) {
    throw InvalidInput("mesh has no triangles: " + quoted(path) +
                       "; export the solid with its surface");
  }
  return mesh;
}

void writeMesh(const fs::path& path, const TriMesh& mesh, MeshFormat format) {
  if (format == MeshFormat::Auto) {
    if (hasExtension(path, ".stl")) {
      format = MeshFormat::StlBinary;
    } else if (hasExtension(path, ".obj")) {
      format = MeshFormat::Obj;
    } else if (hasExtension(path, ".ply")) {
      format = MeshFormat::Ply;
    } else {
      throw InvalidInput("unknown mesh file extension: " + quoted(path) +
                         "; use .stl, .obj or .ply, or pass the format explicitly");
    }
  }
  validateForWriting(mesh, path);
  std::string content;
  bool binary = false;
  switch (format) {
    case MeshFormat::StlBinary:
      content = binaryStl(mesh);
      binary = true;
      break;
    case MeshFormat::StlAscii:
      content = asciiStl(mesh);
      break;
    case MeshFormat::Obj:
      content = obj(mesh);
      break;
    case MeshFormat::Ply:
      content = ply(mesh, true);
      binary = true;
      break;
    case MeshFormat::PlyAscii:
      content = ply(mesh, false);
      break;
    case MeshFormat::Auto:
      break;  // resolved above
  }
  writeFileAtomically(
      path, [&](std::ostream& out) { out.write(content.data(), content.size()); }, binary);
}

}  // namespace curvedslicer
