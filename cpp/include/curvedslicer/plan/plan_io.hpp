// Reading and writing a deposition plan (plan/plan.hpp): the versioned JSON document (plan.json)
// and a flat CSV table of the path points (plan.csv).
//
// JSON layout (format "curvedslicer-plan", version Plan::kFormatVersion = 2; JSON Schema in
// resources/schema/plan.schema.json; keys in this fixed order, units in the key names):
//   {
//     "format": "curvedslicer-plan", "version": 2,
//     "model": "...", "start": "...",
//     "parameters": {"layer_thickness_mm", "voxel_size_mm", "bead_spacing_mm",
//                    "point_spacing_mm", "fit_tolerance_mm", "field_method", "surface_method",
//                    "initial_curve", and "narrow_strips", "corner_angle_deg",
//                    "min_feature_width_mm", "bead_width_range" [min, max] (fractions of the bead
//                    spacing), "connect_insets" when set},
//     "point_fields": ["x","y","z","nx","ny","nz","vx","vy","vz","w"],
//     "layers": [ {"index", "height_mm", "surface", "warnings": [..],
//                  "coverage": {"area_mm2", "void_share", "overlap_share", "bead_width_mm",
//                               "arc_starts", "voids": [{"area_mm2", "centre_mm": [x,y,z],
//                               "size_mm"}, ..]}   (when measured: paths/coverage.hpp),
//                  "paths": [ {"layer", "index", "closed", "length_mm", "dwell_s" (when > 0),
//                              "points": [[x,y,z, nx,ny,nz, vx,vy,vz, w], ...]} ]} ]
//   }
// Position in mm (part frame), n the unit layer normal, v the unit deposition direction, w the
// bead width in mm (a point of width 0 in memory — "the bead spacing" — is written as the bead
// spacing). A path is arc-on from its first to its last point (and back to the first when
// "closed"); moves between consecutive paths and layers are travel with the arc off; a path with
// "dwell_s" keeps the arc on at its first point that long (a spot deposit).
//
// Version 1 (no "w", no "dwell_s", no "coverage", none of the bead coverage parameters) is still
// read: every point gets the bead spacing as its width and no layer's coverage is measured; it is
// written back as version 2.
//
// Numbers are written in the shortest form that reads back to the same double, so JSON written →
// read → written is byte-identical. Two-space indentation; arrays of plain values on one line.
//
// The reader validates everything the schema states plus what it cannot (layer and path indices
// equal their positions, path.layer equals its layer's index, unit vectors within 1e-6, finite
// numbers, at least 2 points per path, no unknown keys) and throws InvalidInput naming the JSON
// location (RFC 6901 pointer) of the first problem, e.g.
//   "plan.json: /layers/2/paths/0/points/7 has 8 numbers: expected 10 (x y z nx ny nz vx vy vz w);
//    regenerate the plan with `curvedslicer plan`".
//
// CSV: header "layer,path,point,closed,x_mm,y_mm,z_mm,nx,ny,nz,vx,vy,vz,w_mm", one row per point in
// deposition order, numbers in the same shortest round-trip form, '\n' line endings.
//
// Cost: O(points) time; the reader holds the parsed JSON document (about 10× the file size) until
// it returns.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <string_view>

#include "curvedslicer/plan/plan.hpp"

namespace curvedslicer {

/// The value of the JSON "format" key.
inline constexpr std::string_view kPlanFormatName = "curvedslicer-plan";

/// Checks what the reader checks on a plan in memory (indices equal positions, path.layer equals
/// its layer's index, finite numbers, unit normals and deposition directions within 1e-6, at
/// least 2 points per path, non-negative lengths and heights).
/// @throws InvalidInput naming the first problem by its JSON pointer, e.g. "/layers/0/paths/3".
void validatePlan(const Plan& plan);

/// The plan as JSON text (see the file comment), ending with a newline.
/// @throws InvalidInput as validatePlan (a plan that would not read back is never written).
std::string formatPlanJson(const Plan& plan);

/// Writes formatPlanJson(plan) to `out`. @throws IoError if the stream fails.
void writePlanJson(std::ostream& out, const Plan& plan);

/// Writes the JSON atomically to `path` (core/atomic_file.hpp).
/// @throws IoError naming the path; InvalidInput as formatPlanJson.
void writePlanJson(const std::filesystem::path& path, const Plan& plan);

/// Parses and validates plan JSON text.
/// @param origin  name used in messages (a file name, "plan.json")
/// @throws InvalidInput — not JSON (with line and column), wrong "format", unsupported "version"
///         (newer than this build: update curvedslicer), or any violation listed in the file
///         comment, naming its JSON pointer.
Plan parsePlanJson(std::string_view text, std::string_view origin = "plan");

/// Reads a plan from a stream (see parsePlanJson).
Plan readPlanJson(std::istream& in, std::string_view origin = "plan");

/// Reads a plan file. @throws IoError if it cannot be read; InvalidInput as parsePlanJson, with
/// the file name as origin.
Plan readPlanJson(const std::filesystem::path& path);

/// The CSV table (see the file comment).
std::string formatPlanCsv(const Plan& plan);

/// Writes formatPlanCsv(plan) to `out`. @throws IoError if the stream fails.
void writePlanCsv(std::ostream& out, const Plan& plan);

/// Writes the CSV atomically to `path`. @throws IoError naming the path.
void writePlanCsv(const std::filesystem::path& path, const Plan& plan);

}  // namespace curvedslicer
