// Reading and writing triangle meshes: STL (binary and ASCII, detected from the content — a binary
// file may begin with "solid"), OBJ (polygons fan-triangulated), PLY (write only).
//
// Readers return the triangles as stored (no welding; see mesh_repair.hpp) with `faceIds[t] = t`,
// the triangle's 0-based position in the file (for OBJ: of the triangle after triangulation, in
// file order). Writers are atomic (temporary file + rename). PLY stores double coordinates and,
// when the mesh has face ids, an int `face_id` per face; ASCII STL and OBJ print the shortest
// decimal that reads back to the same double. Files are read whole into memory (a 1 MB binary
// STL takes about a millisecond).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "curvedslicer/mesh/tri_mesh.hpp"

namespace curvedslicer {

enum class MeshFormat {
  Auto,  ///< from the content when reading, from the extension when writing
  StlBinary,
  StlAscii,
  Obj,
  Ply,  ///< binary little-endian PLY
  PlyAscii,
};

/// Reads an STL or OBJ file.
/// @throws InvalidInput (missing/empty/truncated file, a binary STL whose triangle count disagrees
///         with its size, a parse error with its line number, NaN/inf coordinates, an OBJ index out
///         of range, no triangles) — the message names the file and what to do.
TriMesh readMesh(const std::filesystem::path& path, MeshFormat format = MeshFormat::Auto);

/// Reads STL or OBJ content already in memory, as `readMesh` reads a file's; `path` only names
/// the data in messages and, with `Auto`, lets the ".obj" extension choose OBJ. Same errors.
TriMesh parseMesh(std::string_view data, const std::filesystem::path& path,
                  MeshFormat format = MeshFormat::Auto);

/// The format `readMesh` would use for this file (by content; OBJ by extension or content).
MeshFormat detectMeshFormat(const std::filesystem::path& path);

/// Writes a mesh atomically. `Auto` chooses from the extension (.stl binary, .obj, .ply binary).
/// @throws InvalidInput for an unknown extension with Auto, IoError for file-system failures.
void writeMesh(const std::filesystem::path& path, const TriMesh& mesh,
               MeshFormat format = MeshFormat::Auto);

}  // namespace curvedslicer
