// The core's options structs as Python classes (options_binder.hpp): StartSurface,
// VoxelizeOptions, LayerJobOptions, InitialCurve, PlannerOptions, ThinWallOptions, PlanJobOptions,
// MotionOptions and ExportOptions. Names are the snake_case of the C++ fields; LayerJobOptions,
// PlannerOptions and ThinWallOptions list the fields of their nested structs flat
// (`LayerJobOptions(layer_thickness=1.5, voxel_size=0.5, method="anyangle")`), PlanJobOptions
// keeps its three parts as objects. Defaults are those of the C++ structs; lengths in mm, angles
// as the field says (degrees for corner_angle, radians for motion), part frame.
#include <string>
#include <utility>
#include <vector>

#include "binding_helpers.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/pipeline/plan_job.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "options_binder.hpp"

namespace curvedslicer::bindings {

Vec3 castVec3(py::handle value, const std::string& where) {
  const auto v = castOption<std::vector<double>>(value, where);
  if (v.size() != 3) {
    throw InvalidInput(where + " needs 3 numbers: " + std::to_string(v.size()) +
                       " given; pass e.g. (0, 0, 1)");
  }
  return Vec3(v[0], v[1], v[2]);
}

TriMesh castMesh(py::handle value, const std::string& where) {
  py::object vertices, triangles;
  if (py::isinstance<py::dict>(value)) {
    const auto d = py::reinterpret_borrow<py::dict>(value);
    if (d.contains("vertices") && d.contains("triangles")) {
      vertices = d["vertices"];
      triangles = d["triangles"];
    }
  } else if (py::isinstance<py::sequence>(value) && !py::isinstance<py::str>(value) &&
             py::len(value) == 2) {
    const auto s = py::reinterpret_borrow<py::sequence>(value);
    vertices = s[0];
    triangles = s[1];
  }
  if (!vertices || !triangles) {
    throw py::type_error(where + " needs a mesh: " + std::string(py::repr(value)) +
                         "; pass (vertices (n, 3), triangles (m, 3)) or a dict with 'vertices' "
                         "and 'triangles'");
  }
  return toTriMesh(castOption<DoubleArray>(vertices, where + " vertices"),
                   castOption<IntArray>(triangles, where + " triangles"), std::nullopt,
                   where.c_str());
}

std::string describeMesh(const TriMesh& mesh) {
  return "mesh(" + std::to_string(mesh.vertices.size()) + " vertices, " +
         std::to_string(mesh.triangles.size()) + " triangles)";
}

namespace {

using Kind = StartSurface::Kind;

TriMesh cleanInitialSurface(TriMesh mesh) {
  return cleanMesh(mesh).mesh;
}

void bindStartSurface(py::module_& m) {
  OptionsClass<StartSurface> c(
      m, "StartSurface",
      "Where the geodesic field is zero (field/start_surface.hpp): a plane (by default the build "
      "plate under the model), faces of the model, or a separate surface mesh.");
  c.choice(
       "kind", member(&StartSurface::kind), parseStartSurfaceKind,
       [](Kind k) { return toString(k); }, "'plane' | 'faces' | 'mesh'")
      .value("plane_at_model_bottom", member(&StartSurface::planeAtModelBottom),
             "plane: z = the model's min z, normal +z (else plane_point, plane_normal)")
      .vec3("plane_point", member(&StartSurface::planePoint), "plane: a point, part frame, mm")
      .vec3("plane_normal", member(&StartSurface::planeNormal),
            "plane: its normal (need not be unit length)")
      .value("face_ids", member(&StartSurface::faceIds),
             "faces: ids matched against the model's face ids (FreeCAD FaceN for CAD shapes, "
             "triangle positions for mesh files)")
      .mesh("mesh", member(&StartSurface::mesh), "mesh: the surface, part frame, mm");
  c.finish();
  c.cls()
      .def_static("build_plate", &StartSurface::buildPlate,
                  "The plane z = model min z (the default).")
      .def_static("horizontal_plane", &StartSurface::horizontalPlane, "The plane z = z (mm).",
                  py::arg("z"))
      .def_static(
          "plane",
          [](py::handle point, py::handle normal) {
            return StartSurface::plane(castVec3(point, "StartSurface.plane point"),
                                       castVec3(normal, "StartSurface.plane normal"));
          },
          "A plane through point (mm) with normal.", py::arg("point"), py::arg("normal"))
      .def_static("faces", &StartSurface::faces, "The model's faces with these ids.",
                  py::arg("ids"))
      .def_static(
          "surface",
          [](const DoubleArray& vertices, const IntArray& triangles) {
            return StartSurface::surface(
                toTriMesh(vertices, triangles, std::nullopt, "start surface"));
          },
          "A surface mesh: vertices (n, 3) mm, triangles (m, 3).", py::arg("vertices"),
          py::arg("triangles"))
      .def("describe", &StartSurface::describe, "The report's description, e.g. 'plane z=0 mm'.");
}

void bindVoxelizeOptions(py::module_& m) {
  OptionsClass<VoxelizeOptions> c(m, "VoxelizeOptions",
                                  "The voxel grid (voxel/voxelize.hpp, paper §2.1).");
  c.value("voxel_size", member(&VoxelizeOptions::voxelSize), "L, mm (> 0)")
      .choice(
          "alignment", member(&VoxelizeOptions::alignment), parseGridAlignment,
          [](GridAlignment a) { return toString(a); },
          "'pca' (principal axes) | 'model' (the model's axes)")
      .value("padding", member(&VoxelizeOptions::padding),
             "empty cells around the model's box on each side (>= 1)")
      .value("memory_budget_bytes", member(&VoxelizeOptions::memoryBudgetBytes),
             "bytes the whole job may use; 0 = 80 % of physical memory")
      .value("bytes_per_cell", member(&VoxelizeOptions::bytesPerCell),
             "bytes the job needs per grid cell");
  c.finish();
}

void bindLayerJobOptions(py::module_& m) {
  using O = LayerJobOptions;
  OptionsClass<O> c(m, "LayerJobOptions",
                    "The layer job (pipeline/layer_pipeline.hpp, paper §2): start surface, voxel "
                    "grid, geodesic field and layers, flat.");
  c.nested("start", member(&O::start), "StartSurface (default: the build plate)")
      .value("voxel_size", member(&O::voxelize, &VoxelizeOptions::voxelSize), "L, mm (> 0)")
      .choice(
          "alignment", member(&O::voxelize, &VoxelizeOptions::alignment), parseGridAlignment,
          [](GridAlignment a) { return toString(a); }, "grid axes: 'pca' | 'model'")
      .value("padding", member(&O::voxelize, &VoxelizeOptions::padding),
             "empty cells around the model's box on each side (>= 1)")
      .value("memory_budget_bytes", member(&O::voxelize, &VoxelizeOptions::memoryBudgetBytes),
             "bytes the job may use; 0 = 80 % of physical memory")
      .value("bytes_per_cell", member(&O::voxelize, &VoxelizeOptions::bytesPerCell),
             "bytes needed per grid cell")
      .choice(
          "method", member(&O::geodesic, &GeodesicOptions::method), parseGeodesicMethod,
          [](GeodesicMethod g) { return toString(g); },
          "geodesic field: 'anyangle' (accurate; also 'exact') | 'paper' (paper §2.2.3)")
      .value("seed_band", member(&O::geodesic, &GeodesicOptions::seedBand),
             "mm; voxels this close to the start surface are exact seeds; <= 0: sqrt(3)·L")
      .value("paper_search_radius", member(&O::geodesic, &GeodesicOptions::paperSearchRadius),
             "paper method: search radius in units of L; <= 0: 2·sqrt(3)")
      .value("layer_thickness", member(&O::layers, &LayerOptions::layerThickness), "h, mm (> 0)")
      .value("clip_to_solid", member(&O::layers, &LayerOptions::clipToSolid),
             "clip the surfaces to the model")
      .value("max_layers", member(&O::layers, &LayerOptions::maxLayers),
             "more layers is an InvalidInput error")
      .value("thickness_samples", member(&O::layers, &LayerOptions::thicknessSamples),
             "vertices per layer measured for the thickness; 0 all, < 0 none")
      .value("batch_crossings", member(&O::layers, &LayerOptions::batchCrossings),
             "layer batch size in crossed cubes; 0 automatic")
      .value(
          "simplify_layers", [](O& o) -> bool& { return o.layers.simplification.enabled; },
          "simplify each layer surface within layer_tolerance (False: full resolution)")
      .value(
          "layer_tolerance", [](O& o) -> double& { return o.layers.simplification.tolerance; },
          "ε, mm, of the layer simplification (>= 0); 0 = 0.05 × voxel size")
      .value("relative_weld_tolerance", member(&O::clean, &CleanOptions::relativeWeldTolerance),
             "cleaning: weld distance as a fraction of the bounding-box diagonal")
      .value("remove_degenerate", member(&O::clean, &CleanOptions::removeDegenerate),
             "cleaning: drop degenerate triangles")
      .value("remove_duplicates", member(&O::clean, &CleanOptions::removeDuplicates),
             "cleaning: drop duplicate triangles")
      .value("cap_holes", member(&O::capHoles), "close an open model's holes first")
      .value("min_inside_voxels", member(&O::minInsideVoxels),
             "fewer inside voxels means the voxel size is too coarse")
      .value("max_unresolved_fraction", member(&O::maxUnresolvedFraction),
             "above this fraction of unclassified voxels the mesh is open beyond repair");
  c.finish();
}

void bindInitialCurve(py::module_& m) {
  OptionsClass<InitialCurve> c(
      m, "InitialCurve",
      "The initial curve of every layer (paths/planner.hpp): the layer's boundary, or its "
      "section with a plane or a surface.");
  c.choice(
       "kind", member(&InitialCurve::kind), parseInitialCurveKind,
       [](InitialCurveKind k) { return toString(k); }, "'boundary' | 'plane' | 'surface'")
      .vec3("plane_point", member(&InitialCurve::planePoint), "plane: a point, part frame, mm")
      .vec3("plane_normal", member(&InitialCurve::planeNormal),
            "plane: its normal (need not be unit length)")
      .mesh("surface", member(&InitialCurve::surface),
            "surface: the user surface, part frame, mm (cleaned: welded, degenerate and "
            "duplicate triangles dropped)",
            cleanInitialSurface);
  c.finish();
  c.cls()
      .def_static(
          "boundary", []() { return InitialCurve{}; }, "The layer boundary (default).")
      .def_static(
          "plane",
          [](py::handle point, py::handle normal) {
            InitialCurve curve;
            curve.kind = InitialCurveKind::Plane;
            curve.planePoint = castVec3(point, "InitialCurve.plane point");
            curve.planeNormal = castVec3(normal, "InitialCurve.plane normal");
            return curve;
          },
          "The section with the plane through point (mm) with normal (for a surface: "
          "InitialCurve(kind='surface', surface=(vertices, triangles))).",
          py::arg("point"), py::arg("normal"))
      .def("describe", &InitialCurve::describe,
           "As the plan records it, e.g. 'boundary', 'plane:0,0,0,1,0,0'.");
}

// The fields PlannerOptions and ThinWallOptions share, in the same order.
template <class O>
void bindPathFitFields(OptionsClass<O>& c) {
  c.value("point_spacing", member(&O::pointSpacing), "mm, largest distance between points (> 0)")
      .value("fit_tolerance", member(&O::fitTolerance), "mm, spline fit tolerance (> 0)")
      .value("corner_angle", member(&O::cornerAngle),
             "degrees in (0, 180]: sharper turns within 0.2 mm stay exact corners (180: none)");
}

template <class O>
void bindPathOrderFields(OptionsClass<O>& c) {
  c.choice(
       "surface_method", member(&O::geodesic, &SurfaceGeodesicOptions::method),
       parseSurfaceGeodesicMethod, [](SurfaceGeodesicMethod s) { return toString(s); },
       "geodesic distance on the layer: 'accurate' | 'paper' (paper §3.1, eq. 15)")
      .value("curve_tolerance", member(&O::geodesic, &SurfaceGeodesicOptions::curveTolerance),
             "mm, largest distance of an initial-curve point from the surface")
      .value("min_path_length", member(&O::minPathLength),
             "mm; shorter pieces are not deposited; < 0: the bead spacing")
      .value("seam_separation", member(&O::seamSeparation),
             "mm between seams of consecutive layers; < 0: 2 × the bead spacing")
      .value("improvement_passes", member(&O::improvementPasses), "2-opt passes of the ordering")
      .choice(
          "deposition_direction", member(&O::deposition, &DepositionOptions::method),
          [](const std::string& s) { return parseDepositionMethod(s); }, depositionMethodName,
          "V: 'growth' (the paper's V where it follows the layer's growth direction, else that "
          "direction) | 'nearest' (the paper's V everywhere, paper §3.2)")
      .value("deposition_max_deviation", member(&O::deposition, &DepositionOptions::maxDeviation),
             "rad; growth: largest angle of the paper's V from the growth direction")
      .value("contact_tolerance", member(&O::deposition, &DepositionOptions::contactTolerance),
             "mm; closer to the deposited material, V = -normal")
      .value("deposition_grid_cell", member(&O::deposition, &DepositionOptions::gridCell),
             "mm, cell of the bead-segment grid; <= 0: the longest bead segment");
}

void bindPlannerOptions(py::module_& m) {
  using O = PlannerOptions;
  OptionsClass<O> c(m, "PlannerOptions",
                    "Paths on curved layers (paths/planner.hpp planLayers, paper §3.1).");
  c.value("bead_spacing", member(&O::beadSpacing),
          "s, mm between neighbouring bead centre lines (> 0)");
  bindPathFitFields(c);
  c.nested("initial_curve", member(&O::initialCurve), "InitialCurve (default: the boundary)")
      .choice(
          "narrow_strips", member(&O::narrowStrips),
          [](const std::string& s) { return parseNarrowStripMode(s); }, narrowStripModeName,
          "where paths of one level come closer than 0.95·s: 'centre_bead' | 'overlap'")
      .value("min_feature_width", member(&O::minFeatureWidth),
             "mm; regions narrower than a bead but at least this wide get one centre bead; "
             "narrower ones are left out and reported; < 0: half the bead spacing")
      .value("width_min", member(&O::widthMin),
             "adaptive bead width: smallest width as a fraction of the bead spacing, in (0, 1]")
      .value("width_max", member(&O::widthMax),
             "adaptive bead width: largest width as a fraction of the bead spacing, >= 1 "
             "(width_min = width_max = 1: fixed width)")
      .value("connect_insets", member(&O::connectInsets),
             "join consecutive rings of one region into one arc-on path (fewer arc starts)")
      .value("fill_gaps", member(&O::fillGaps),
             "give uncovered strips between beads (at least min_feature_width wide) a "
             "centre-line bead, and widen the beads beside narrower strips into them")
      .value("min_gap_area", member(&O::minGapArea),
             "mm², smallest uncovered patch that gets a fill bead (> 0); < 0: the bead spacing "
             "squared")
      .value("corner_fill", member(&O::cornerFill),
             "dip the outer ring toward the layer's acute convex corners so its bead covers "
             "the corner's wedge")
      .value("corner_fill_angle", member(&O::cornerFillAngle),
             "degrees in (0, 180): corner fill takes boundary corners sharper than this")
      .value("corner_overdeposit", member(&O::cornerOverdeposit),
             "mm, how far a corner-fill bead's edge may pass the layer boundary; < 0: a "
             "quarter of the bead spacing")
      .value("measure_coverage", member(&O::measureCoverage),
             "measure every layer's bead coverage (void and overlap shares) into the plan");
  bindPathOrderFields(c);
  c.finish();
}

void bindThinWallOptions(py::module_& m) {
  using O = ThinWallOptions;
  OptionsClass<O> c(m, "ThinWallOptions",
                    "A thin wall (paths/planner.hpp planThinWall, the paper's turbine base): one "
                    "bead per plan layer at k·bead_spacing from the wall's edge.");
  c.value("bead_spacing", member(&O::beadSpacing), "mm between beads along the surface (> 0)");
  bindPathFitFields(c);
  c.choice(
       "edge", member(&O::edge), parseWallEdgeKind, [](WallEdgeKind k) { return toString(k); },
       "'lowest' (the boundary loop lowest along axis) | 'nearest' (the loop nearest to "
       "point)")
      .vec3("axis", member(&O::axis), "lowest: the up direction, part frame")
      .vec3("point", member(&O::point), "nearest: a point, part frame, mm");
  bindPathOrderFields(c);
  c.finish();
}

void bindPlanJobOptions(py::module_& m) {
  using O = PlanJobOptions;
  OptionsClass<O> c(m, "PlanJobOptions",
                    "The plan job (pipeline/plan_job.hpp): layers, then paths on them; or a thin "
                    "wall. Records the plan's parameters and provenance.");
  c.nested("layer_job", member(&O::layerJob), "LayerJobOptions (unused for a thin wall)")
      .nested("planner", member(&O::planner), "PlannerOptions")
      .optional("thin_wall", member(&O::thinWall),
                "None, or ThinWallOptions: plan the model's surface as a thin wall (reads as a "
                "copy: assign a new value to change it)")
      .value("model_name", member(&O::modelName), "the model's name, recorded in the plan")
      .value("start_spec", member(&O::startSpec),
             "the start as the user gave it, recorded in the plan")
      .choice(
          "layer_format", member(&O::layerFormat), parseLayerFileFormat,
          [](LayerFileFormat f) { return toString(f); },
          "'ply' | 'obj': the layer file names the plan records");
  c.finish();
}

void bindMotionOptions(py::module_& m) {
  using O = MotionOptions;
  OptionsClass<O> c(m, "MotionOptions",
                    "Positioner angles and robot joints (robot/motion.hpp planMotion, paper eq. "
                    "16).");
  c.value("near_singular_band", member(&O::nearSingularBand),
          "rad: V this close to the rotation axis gets a blended a2; outside, V stays this close "
          "to gravity")
      .value("initial_a2", member(&O::initialA2), "rad, a2 when the first points are singular")
      .value("prefer_positive_tilt", member(&O::preferPositiveTilt), "a1 >= 0 if feasible")
      .value("smoothing_length", member(&O::smoothingLength),
             "mm, Gaussian sigma along the path for V; 0 = none")
      .value("max_smoothing_deviation", member(&O::maxSmoothingDeviation),
             "rad, smoothed V against the plan's V")
      .value("tool_along_travel", member(&O::toolAlongTravel),
             "tool x along the travel direction (else a fixed world x)")
      .choice(
          "unreachable", member(&O::unreachable), parseUnreachablePolicy,
          [](UnreachablePolicy u) { return toString(u); },
          "'throw' (InvalidInput naming the points) | 'warn' (closest pose, a warning)")
      .value("residual_warning", member(&O::residualWarning), "rad: warn above this residual")
      .value("clearance", member(&O::clearance),
             "mm, arc-off moves travel this high above the part and the deposit")
      .value("allow_collisions", member(&O::allowCollisions),
             "remaining collisions are warnings (MotionPlan collisions) instead of errors")
      .value("add_home", member(&O::addHome), "start and end at the cell's home pose")
      .value("merge_tolerance", member(&O::mergeTolerance),
             "mm, consecutive path points closer than this are merged")
      .value("max_a2_step", member(&O::maxA2Step),
             "rad, largest a2 step between consecutive points of a weld (points inserted)")
      .value("time_parameterise", member(&O::timeParameterise),
             "respect every axis's maximum speed (else nominal speeds only)")
      .choice(
          "placement", member(&O::placement), parsePartPlacement,
          [](PartPlacement p) { return toString(p); },
          "'rest' (lowest bead bottom on the fixture's top, else the table's) | 'cell' (the "
          "cell's table_to_part) | 'auto' (rest, on the lowest riser that keeps the torch clear "
          "of the table)");
  c.finish();
}

void bindExportOptions(py::module_& m) {
  using O = ExportOptions;
  OptionsClass<O> c(m, "ExportOptions", "Program export (export/exporter.hpp).");
  c.value("program_name", member(&O::programName), "job name; '' = the cell's")
      .value("date", member(&O::date), "header date 'YYYY/MM/DD HH:MM' (fixed by default)")
      .choice(
          "gcode_mode", member(&O::gcodeMode), parseGcodeMode,
          [](GcodeMode g) { return toString(g); }, "G-code only: 'tcp' | 'machine'")
      .choice(
          "gcode_dialect", member(&O::gcodeDialect), parseGcodeDialect,
          [](GcodeDialect d) { return toString(d); }, "G-code only: 'generic' | 'linuxcnc'")
      .value("gcode_max_lines_per_file", member(&O::gcodeMaxLinesPerFile),
             "G-code only: lines per file before splitting into sub-programs; 0 = never")
      .value("arc_output", member(&O::arcOutput), "digital output switching the arc on");
  c.finish();
}

}  // namespace

void registerOptionBindings(py::module_& m) {
  bindStartSurface(m);
  bindVoxelizeOptions(m);
  bindLayerJobOptions(m);
  bindInitialCurve(m);
  bindPlannerOptions(m);
  bindThinWallOptions(m);
  bindPlanJobOptions(m);
  bindMotionOptions(m);
  bindExportOptions(m);
}

}  // namespace curvedslicer::bindings
