// Parsing the textual job options of the command line (and of scripts): start-surface specs such
// as "plane:bottom", "plane:z=12.5", "faces:0-9,15", "mesh:base.obj"; initial-curve specs
// ("boundary", "plane:X,Y,Z,NX,NY,NZ", "mesh:FILE"); thin-wall edge specs ("lowest",
// "lowest:AX,AY,AZ", "nearest:X,Y,Z"); id lists; lengths; the layer file format. The names of the
// option enums are parsed and formatted next to each enum (GeodesicMethod, GridAlignment,
// SurfaceGeodesicMethod, NarrowStripMode, ExportFormat, GcodeMode). Pure string handling,
// O(length of the text) apart from expanding id ranges; no file is read except by
// `loadStartSurface` and `loadInitialCurve`.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/field/start_surface.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/voxel/frame.hpp"

namespace curvedslicer {

/// Largest number of ids an id list may expand to (guards against "0-2000000000").
inline constexpr std::size_t kMaxIdListSize = 50'000'000;

/// Parses a list of non-negative integers with ranges: "0-9,15, 20-22". Spaces around items are
/// allowed; a range a-b needs a <= b. The result keeps the order given, duplicates removed.
/// @throws InvalidInput naming the offending item, for empty items, signs, non-digits, reversed
///         ranges, values above INT_MAX and lists longer than kMaxIdListSize.
std::vector<int> parseIdList(std::string_view text);

/// A start surface as given on the command line. For kind Mesh the surface mesh is not loaded
/// yet: `meshFile` names it (see loadStartSurface).
struct StartSurfaceSpec {
  std::string text;                ///< the spec as given, e.g. "faces:0-9,15"
  StartSurface surface;            ///< kind and parameters (Mesh: empty mesh)
  std::filesystem::path meshFile;  ///< Mesh only: the surface file
};

/// Parses "plane:bottom" (the build plate under the model, z = model min z), "plane:z=MM"
/// (horizontal plane at z = MM, part frame), "faces:IDS" (0-based triangle positions in the model
/// file; see parseIdList) or "mesh:FILE" (a surface mesh, STL or OBJ, part frame, mm).
/// @throws InvalidInput listing the accepted forms.
StartSurfaceSpec parseStartSurfaceSpec(std::string_view text);

/// The spec's StartSurface, with the mesh file read for kind Mesh.
/// @throws InvalidInput from reading the file, prefixed with "start surface mesh".
StartSurface loadStartSurface(const StartSurfaceSpec& spec);

/// An initial curve as given on the command line. For kind Surface the mesh is not loaded yet:
/// `meshFile` names it (see loadInitialCurve).
struct InitialCurveSpec {
  std::string text;                ///< the spec as given, e.g. "plane:0,0,0,1,0,0"
  InitialCurve curve;              ///< kind and parameters (Surface: empty mesh)
  std::filesystem::path meshFile;  ///< Surface only: the surface file
};

/// Parses "boundary" (the layer's edge), "plane:X,Y,Z,NX,NY,NZ" (the section with the plane
/// through X,Y,Z with normal NX,NY,NZ; part frame, mm; the normal is checked by
/// validatePlannerOptions) or "mesh:FILE" (the section with a surface mesh, STL or OBJ).
/// @throws InvalidInput listing the accepted forms, or naming a malformed number list.
InitialCurveSpec parseInitialCurveSpec(std::string_view text);

/// The spec's InitialCurve, with the mesh file read (and cleaned) for kind Surface.
/// @throws InvalidInput from reading the file, prefixed with "initial surface mesh".
InitialCurve loadInitialCurve(const InitialCurveSpec& spec);

/// Parses a thin wall's edge into `options` (edge, axis or point): "lowest" (the boundary loop
/// lowest along z), "lowest:AX,AY,AZ" (lowest along that axis) or "nearest:X,Y,Z" (the loop
/// nearest to that point, part frame, mm). Other fields of `options` are left as they are.
/// @throws InvalidInput listing the accepted forms.
void parseThinWallEdge(std::string_view text, ThinWallOptions& options);

/// The edge of `options` in the form parseThinWallEdge reads ("lowest" for the z axis).
std::string formatThinWallEdge(const ThinWallOptions& options);

/// Parses a length in mm ("1.5", "2e-1"). Non-finite spellings ("nan", "inf") are returned as
/// such so that range checks can report them.
/// @param what  the parameter's name for the message, e.g. "layer thickness"
/// @throws InvalidInput if the text is not a number.
double parseLength(std::string_view text, std::string_view what);

/// Parses an angle in degrees ("30", "22.5"), as parseLength (range checks are the caller's).
/// @throws InvalidInput if the text is not a number.
double parseAngle(std::string_view text, std::string_view what);

/// Parses the adaptive bead width range (PlannerOptions::widthMin / widthMax, fractions of the
/// bead spacing): "MIN,MAX" (e.g. "0.7,1.3") or "off" (fixed width: 1,1). Range checks are
/// validatePlannerOptions'.
/// @throws InvalidInput naming --bead-width-range if the text is neither form.
void parseBeadWidthRange(std::string_view text, PlannerOptions& options);

/// File format of the layer surfaces.
enum class LayerFileFormat {
  Ply,  ///< binary little-endian PLY
  Obj,  ///< Wavefront OBJ
};

/// "ply" or "obj". @throws InvalidInput listing the choices.
LayerFileFormat parseLayerFileFormat(std::string_view name);
std::string_view toString(LayerFileFormat format);

}  // namespace curvedslicer
