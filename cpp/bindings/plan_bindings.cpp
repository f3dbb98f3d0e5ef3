// Python bindings of paths, plan JSON, robot cell, motion planning and program export (issue 5,
// round two): thin conversions only.
//
// Plans cross the boundary as their versioned JSON text (plan/plan_io.hpp), cells as the JSON
// text readCell/parseCell read (robot/cell.hpp), so the workbench stores both verbatim in the
// document and a reopened document re-exports byte-identical programs. Layer surfaces come in as
// numpy arrays (vertices (n, 3) float64 mm, part frame; triangles (m, 3) int). Long calls release
// the GIL and take `progress(stage, fraction) -> bool | None` (binding_helpers.hpp).
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "binding_helpers.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "curvedslicer/layers/layer_extraction.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/positioner.hpp"

namespace curvedslicer::bindings {

namespace {

SurfaceGeodesicMethod surfaceMethodFromName(const std::string& name) {
  if (name == "accurate") return SurfaceGeodesicMethod::Accurate;
  if (name == "paper") return SurfaceGeodesicMethod::Paper;
  throw InvalidInput("unknown surface geodesic method: '" + name + "'; use 'accurate' or 'paper'");
}

Vec3 vec3From(const std::vector<double>& v, const char* what) {
  if (v.size() != 3) {
    throw InvalidInput(std::string(what) + " needs 3 numbers: " + std::to_string(v.size()) +
                       " given; pass e.g. (0, 0, 1)");
  }
  return Vec3(v[0], v[1], v[2]);
}

py::list poseMatrix(const Pose& pose) {
  py::list rows;
  const Eigen::Matrix4d m = pose.matrix();
  for (int r = 0; r < 4; ++r) {
    py::list row;
    for (int c = 0; c < 4; ++c) row.append(m(r, c));
    rows.append(row);
  }
  return rows;
}

py::dict planStatsDict(const PlanResult& result) {
  const PlanStats& s = result.stats;
  py::dict d;
  d["paths"] = result.plan.pathCount();
  d["points"] = result.plan.pointCount();
  d["arc_length_mm"] = s.arcLength;
  d["travel_mm"] = s.travel;
  d["layers_without_paths"] = s.layersWithoutPaths;
  d["dropped_fragments"] = s.droppedFragments;
  d["seams_too_close"] = s.seamsTooClose;
  d["max_fit_deviation_mm"] = s.maxFitDeviation;
  d["deposition_fallbacks"] = s.deposition.normalFallbacks;
  py::list times;
  for (const PlanStageTime& t : s.stageTimes) times.append(py::make_tuple(t.name, t.seconds));
  d["stage_times"] = times;
  return d;
}

py::dict planResultDict(PlanResult& result, const std::string& model, const std::string& start) {
  result.plan.model = model;
  result.plan.start = start;
  py::dict d;
  d["plan_json"] = formatPlanJson(result.plan);
  d["stats"] = planStatsDict(result);
  return d;
}

py::dict planLayersPy(const py::list& layers, const std::optional<DoubleArray>& startVertices,
                      const std::optional<IntArray>& startTriangles, double beadSpacing,
                      double pointSpacing, double fitTolerance, double cornerAngle,
                      const std::string& initialCurve,
                      const std::optional<std::vector<double>>& planePoint,
                      const std::optional<std::vector<double>>& planeNormal,
                      const std::optional<DoubleArray>& surfaceVertices,
                      const std::optional<IntArray>& surfaceTriangles,
                      const std::string& surfaceMethod, const std::string& narrowStrips,
                      double layerThickness, double voxelSize, const std::string& fieldMethod,
                      const std::string& model, const std::string& start,
                      const py::object& progress) {
  PlannerOptions options;
  options.beadSpacing = beadSpacing;
  options.pointSpacing = pointSpacing;
  options.fitTolerance = fitTolerance;
  options.cornerAngle = cornerAngle;
  options.geodesic.method = surfaceMethodFromName(surfaceMethod);
  options.narrowStrips = parseNarrowStripMode(narrowStrips);
  if (initialCurve == "boundary") {
    options.initialCurve.kind = InitialCurveKind::Boundary;
  } else if (initialCurve == "plane") {
    if (!planePoint || !planeNormal) {
      throw InvalidInput(
          "initial curve 'plane' needs plane_point and plane_normal: missing; pass e.g. "
          "plane_point=(0, 0, 0), plane_normal=(1, 0, 0)");
    }
    options.initialCurve.kind = InitialCurveKind::Plane;
    options.initialCurve.planePoint = vec3From(*planePoint, "plane_point");
    options.initialCurve.planeNormal = vec3From(*planeNormal, "plane_normal");
    if (!(options.initialCurve.planeNormal.norm() > 0.0)) {
      throw InvalidInput("initial plane normal is zero: (0, 0, 0); pass a non-zero normal");
    }
  } else if (initialCurve == "surface") {
    if (!surfaceVertices || !surfaceTriangles) {
      throw InvalidInput(
          "initial curve 'surface' needs surface_vertices and surface_triangles: missing; "
          "pass the user surface as numpy arrays");
    }
    options.initialCurve.kind = InitialCurveKind::Surface;
    options.initialCurve.surface =
        cleanMesh(toTriMesh(*surfaceVertices, *surfaceTriangles, std::nullopt, "initial surface"))
            .mesh;
  } else {
    throw InvalidInput("unknown initial curve: '" + initialCurve +
                       "'; use 'boundary', 'plane' or 'surface'");
  }
  validatePlannerOptions(options);

  std::vector<LayerSurface> surfaces;
  surfaces.reserve(layers.size());
  for (const py::handle& item : layers) {
    const py::dict layer = py::reinterpret_borrow<py::dict>(item);
    LayerSurface s;
    s.index = layer["index"].cast<int>();
    s.level = layer["height"].cast<double>();
    s.mesh = toTriMesh(layer["vertices"].cast<DoubleArray>(), layer["triangles"].cast<IntArray>(),
                       std::nullopt, "layer");
    surfaces.push_back(std::move(s));
  }
  TriMesh startSurface;
  if (startVertices && startTriangles) {
    startSurface = toTriMesh(*startVertices, *startTriangles, std::nullopt, "start surface");
  }
  PlanResult result = runWithProgress(progress, [&](Progress p) {
    return planLayers(surfaces, startSurface, options, std::move(p));
  });
  result.plan.parameters.layerThickness = layerThickness;
  result.plan.parameters.voxelSize = voxelSize;
  result.plan.parameters.fieldMethod = fieldMethod;
  return planResultDict(result, model, start);
}

py::dict planThinWallPy(const DoubleArray& vertices, const IntArray& triangles, double beadSpacing,
                        double pointSpacing, double fitTolerance, double cornerAngle,
                        const std::string& edge, const std::vector<double>& axis,
                        const std::vector<double>& point, const std::string& surfaceMethod,
                        const std::string& model, const py::object& progress) {
  ThinWallOptions options;
  options.beadSpacing = beadSpacing;
  options.pointSpacing = pointSpacing;
  options.fitTolerance = fitTolerance;
  options.cornerAngle = cornerAngle;
  options.geodesic.method = surfaceMethodFromName(surfaceMethod);
  std::string start;
  if (edge == "lowest") {
    options.edge = WallEdgeKind::LowestAlongAxis;
    options.axis = vec3From(axis, "axis");
    start = "thin-wall:lowest:" + std::to_string(options.axis.x()) + "," +
            std::to_string(options.axis.y()) + "," + std::to_string(options.axis.z());
  } else if (edge == "nearest") {
    options.edge = WallEdgeKind::NearestToPoint;
    options.point = vec3From(point, "point");
    start = "thin-wall:nearest:" + std::to_string(options.point.x()) + "," +
            std::to_string(options.point.y()) + "," + std::to_string(options.point.z());
  } else {
    throw InvalidInput("unknown thin-wall edge: '" + edge + "'; use 'lowest' or 'nearest'");
  }
  validateThinWallOptions(options);
  const TriMesh surface =
      cleanMesh(toTriMesh(vertices, triangles, std::nullopt, "wall surface")).mesh;
  PlanResult result = runWithProgress(
      progress, [&](Progress p) { return planThinWall(surface, options, std::move(p)); });
  return planResultDict(result, model, start);
}

MotionOptions motionOptions(bool warnUnreachable, bool toolAlongTravel) {
  MotionOptions options;
  if (warnUnreachable) options.unreachable = UnreachablePolicy::Warn;
  options.toolAlongTravel = toolAlongTravel;
  return options;
}

py::dict estimateDict(const MotionEstimate& e) {
  py::dict d;
  d["bead_length_mm"] = e.beadLength;
  d["arc_time_s"] = e.arcTime;
  d["travel_length_mm"] = e.travelLength;
  d["travel_time_s"] = e.travelTime;
  d["dwell_time_s"] = e.dwellTime;
  d["total_time_s"] = e.totalTime;
  d["wire_length_mm"] = e.wireLength;
  d["deposited_volume_mm3"] = e.depositedVolume;
  d["deposited_mass_g"] = e.depositedMass;
  d["paths"] = e.paths;
  d["points"] = e.points;
  return d;
}

// Motion points as columns: ints (n,) and vectors (n, 3), so 10^5 points stay cheap.
py::dict planMotionPy(const std::string& planJson, const std::string& cellJson,
                      bool warnUnreachable, bool toolAlongTravel, const py::object& progress) {
  const Plan plan = parsePlanJson(planJson, "plan");
  const Cell cell = parseCell(cellJson, "cell");
  const MotionOptions options = motionOptions(warnUnreachable, toolAlongTravel);
  const MotionPlan motion = runWithProgress(
      progress, [&](Progress p) { return planMotion(plan, cell, options, std::move(p)); });
  const auto n = static_cast<py::ssize_t>(motion.points.size());
  py::array_t<std::int32_t> layer(n), path(n), index(n), flags(n);
  py::array_t<double> a1(n), a2(n), residual(n), speed(n);
  py::array_t<bool> arcOn(n), pathStart(n), pathEnd(n);
  py::array_t<double> position({n, py::ssize_t{3}}), deposition({n, py::ssize_t{3}}),
      used({n, py::ssize_t{3}}), normal({n, py::ssize_t{3}});
  for (py::ssize_t i = 0; i < n; ++i) {
    const MotionPoint& p = motion.points[static_cast<std::size_t>(i)];
    layer.mutable_at(i) = p.layer;
    path.mutable_at(i) = p.path;
    index.mutable_at(i) = p.index;
    flags.mutable_at(i) = static_cast<std::int32_t>(p.flags);
    a1.mutable_at(i) = p.a1;
    a2.mutable_at(i) = p.a2;
    residual.mutable_at(i) = p.residual;
    speed.mutable_at(i) = p.speed;
    arcOn.mutable_at(i) = p.arcOn;
    pathStart.mutable_at(i) = p.pathStart;
    pathEnd.mutable_at(i) = p.pathEnd;
    for (py::ssize_t k = 0; k < 3; ++k) {
      position.mutable_at(i, k) = p.position[k];
      deposition.mutable_at(i, k) = p.deposition[k];
      used.mutable_at(i, k) = p.usedDeposition[k];
      normal.mutable_at(i, k) = p.normal[k];
    }
  }
  py::dict d;
  d["layer"] = layer;
  d["path"] = path;
  d["index"] = index;
  d["flags"] = flags;
  d["a1"] = a1;
  d["a2"] = a2;
  d["residual"] = residual;
  d["speed"] = speed;
  d["arc_on"] = arcOn;
  d["path_start"] = pathStart;
  d["path_end"] = pathEnd;
  d["position"] = position;
  d["deposition"] = deposition;
  d["used_deposition"] = used;
  d["normal"] = normal;
  d["warnings"] = motion.warnings;
  d["max_residual"] = motion.maxResidual;
  d["singular_points"] = motion.singularPoints;
  d["limited_points"] = motion.limitedPoints;
  d["total"] = estimateDict(motion.total);
  return d;
}

py::dict exportResultDict(const ExportResult& result) {
  py::dict d;
  d["format"] = std::string(toString(result.format));
  py::list files;
  for (const ExportFile& f : result.files) {
    files.append(py::make_tuple(f.name, py::bytes(f.text), f.lines));
  }
  d["files"] = files;
  d["motion_count"] = result.motionCount;
  d["arc_count"] = result.arcCount;
  d["warnings"] = result.warnings;
  d["total_bytes"] = result.totalBytes();
  return d;
}

ExportOptions exportOptions(const std::string& programName, const std::string& date,
                            const std::string& gcodeMode, int arcOutput) {
  ExportOptions options;
  options.programName = programName;
  if (!date.empty()) options.date = date;
  if (gcodeMode == "tcp") {
    options.gcodeMode = GcodeMode::Tcp;
  } else if (gcodeMode == "machine") {
    options.gcodeMode = GcodeMode::Machine;
  } else {
    throw InvalidInput("unknown G-code mode: '" + gcodeMode + "'; use 'tcp' or 'machine'");
  }
  options.arcOutput = arcOutput;
  return options;
}

// Plans the motion and writes the program into memory; with `path`, also writes the files all or
// nothing (writeExportFiles), so nothing is written unless every step succeeded.
py::dict exportProgramPy(const std::string& planJson, const std::string& cellJson,
                         const std::string& format, const std::optional<std::string>& path,
                         const std::string& programName, const std::string& date,
                         const std::string& gcodeMode, int arcOutput, bool warnUnreachable,
                         bool toolAlongTravel, const py::object& progress) {
  const ExportFormat f = parseExportFormat(format);
  const ExportOptions options = exportOptions(programName, date, gcodeMode, arcOutput);
  const Plan plan = parsePlanJson(planJson, "plan");
  const Cell cell = parseCell(cellJson, "cell");
  const MotionOptions motion = motionOptions(warnUnreachable, toolAlongTravel);
  const ExportResult result = runWithProgress(progress, [&](Progress p) {
    const MotionPlan planned = planMotion(plan, cell, motion, p.sub(0.0, 0.7));
    ExportResult r = exportProgram(planned, cell, f, options, p.sub(0.7, 0.95));
    if (path) writeExportFiles(r, std::filesystem::path(*path));
    p.report(1.0, "export");
    return r;
  });
  return exportResultDict(result);
}

py::dict planSummaryPy(const std::string& planJson) {
  const Plan plan = parsePlanJson(planJson, "plan");
  py::dict d;
  d["model"] = plan.model;
  d["start"] = plan.start;
  d["layers"] = plan.layers.size();
  d["paths"] = plan.pathCount();
  d["points"] = plan.pointCount();
  py::list perLayer;
  for (const PlanLayer& layer : plan.layers) {
    py::dict l;
    l["index"] = layer.index;
    l["height"] = layer.height;
    l["paths"] = layer.paths.size();
    l["warnings"] = layer.warnings;
    perLayer.append(l);
  }
  d["per_layer"] = perLayer;
  const PlanParameters& p = plan.parameters;
  py::dict params;
  params["layer_thickness_mm"] = p.layerThickness;
  params["voxel_size_mm"] = p.voxelSize;
  params["bead_spacing_mm"] = p.beadSpacing;
  params["point_spacing_mm"] = p.pointSpacing;
  params["fit_tolerance_mm"] = p.fitTolerance;
  params["field_method"] = p.fieldMethod;
  params["surface_method"] = p.surfaceMethod;
  params["initial_curve"] = p.initialCurve;
  if (!p.narrowStrips.empty()) params["narrow_strips"] = p.narrowStrips;
  if (p.cornerAngle) params["corner_angle_deg"] = *p.cornerAngle;
  d["parameters"] = params;
  return d;
}

// Every path as (layer, index, closed, points (k, 3), normals (k, 3), deposition (k, 3)).
py::list planPathsPy(const std::string& planJson) {
  const Plan plan = parsePlanJson(planJson, "plan");
  py::list out;
  for (const PlanLayer& layer : plan.layers) {
    for (const PlanPath& path : layer.paths) {
      const auto k = static_cast<py::ssize_t>(path.points.size());
      py::array_t<double> pts({k, py::ssize_t{3}}), nrm({k, py::ssize_t{3}}),
          dep({k, py::ssize_t{3}});
      for (py::ssize_t i = 0; i < k; ++i) {
        const PathPoint& p = path.points[static_cast<std::size_t>(i)];
        for (py::ssize_t c = 0; c < 3; ++c) {
          pts.mutable_at(i, c) = p.position[c];
          nrm.mutable_at(i, c) = p.normal[c];
          dep.mutable_at(i, c) = p.deposition[c];
        }
      }
      out.append(py::make_tuple(path.layer, path.index, path.closed, pts, nrm, dep));
    }
  }
  return out;
}

py::dict positionerFramesPy(const std::string& cellJson, double a1, double a2) {
  const Cell cell = parseCell(cellJson, "cell");
  const PositionerDescription& p = cell.positioner;
  py::dict d;
  d["base"] = poseMatrix(p.base);
  d["cradle"] = poseMatrix(computeTableInWorld(p, a1, 0.0));
  d["table"] = poseMatrix(computeTableInWorld(p, a1, a2));
  d["part"] = poseMatrix(computePartInWorld(p, a1, a2));
  d["table_zero"] = poseMatrix(computeTableInWorld(p, 0.0, 0.0));
  d["gravity"] = py::make_tuple(cell.gravity.x(), cell.gravity.y(), cell.gravity.z());
  return d;
}

}  // namespace

void registerPlanBindings(py::module_& m) {
  m.def("plan_layers", &planLayersPy,
        "Paths on curved layers (paths/planner.hpp planLayers, paper §3.1). layers: list of "
        "dicts {index (1-based), height mm, vertices (n,3), triangles (m,3)} bottom to top; "
        "start_vertices/start_triangles: the start surface (deposited material under layer 1, "
        "may be None); initial_curve 'boundary' | 'plane' (plane_point, plane_normal) | "
        "'surface' (surface_vertices, surface_triangles); surface_method 'accurate' | 'paper'; "
        "narrow_strips 'centre_bead' (one bead where paths of one level come closer than "
        "0.95·s) | 'overlap'; corner_angle: degrees in (0, 180], turns sharper than this "
        "within 0.2 mm are kept as exact corners by the fit (180: none). "
        "layer_thickness, voxel_size, field_method, model and start are recorded in the plan. "
        "Returns {plan_json, stats}.",
        py::arg("layers"), py::kw_only(), py::arg("start_vertices") = py::none(),
        py::arg("start_triangles") = py::none(), py::arg("bead_spacing") = 3.7,
        py::arg("point_spacing") = 2.0, py::arg("fit_tolerance") = 0.05,
        py::arg("corner_angle") = 30.0, py::arg("initial_curve") = "boundary",
        py::arg("plane_point") = py::none(), py::arg("plane_normal") = py::none(),
        py::arg("surface_vertices") = py::none(), py::arg("surface_triangles") = py::none(),
        py::arg("surface_method") = "accurate", py::arg("narrow_strips") = "centre_bead",
        py::arg("layer_thickness") = 0.0, py::arg("voxel_size") = 0.0, py::arg("field_method") = "",
        py::arg("model") = "", py::arg("start") = "", py::arg("progress") = py::none());

  m.def("plan_thin_wall", &planThinWallPy,
        "Paths of a thin wall (planThinWall, the paper's turbine base): one bead per plan layer "
        "at geodesic distance k·bead_spacing from the wall's edge. edge 'lowest' (the boundary "
        "loop lowest along axis) | 'nearest' (the loop nearest to point); corner_angle as for "
        "plan_layers. Returns {plan_json, stats}.",
        py::arg("vertices"), py::arg("triangles"), py::kw_only(), py::arg("bead_spacing") = 1.65,
        py::arg("point_spacing") = 2.0, py::arg("fit_tolerance") = 0.05,
        py::arg("corner_angle") = 30.0, py::arg("edge") = "lowest",
        py::arg("axis") = std::vector<double>{0, 0, 1},
        py::arg("point") = std::vector<double>{0, 0, 0}, py::arg("surface_method") = "accurate",
        py::arg("model") = "", py::arg("progress") = py::none());

  m.def(
      "format_plan_json",
      [](const std::string& text) { return formatPlanJson(parsePlanJson(text, "plan")); },
      "Parses, validates and re-formats plan JSON (canonical text; identical for canonical "
      "input).",
      py::arg("plan_json"));
  m.def("plan_summary", &planSummaryPy,
        "Validated plan JSON -> {model, start, layers, paths, points, per_layer, parameters}.",
        py::arg("plan_json"));
  m.def("plan_paths", &planPathsPy,
        "Validated plan JSON -> [(layer, index, closed, points (k,3) mm, normals (k,3), "
        "deposition (k,3))] in deposition order.",
        py::arg("plan_json"));
  m.def(
      "plan_csv", [](const std::string& text) { return formatPlanCsv(parsePlanJson(text)); },
      "The plan's CSV table (plan_io.hpp).", py::arg("plan_json"));

  m.def(
      "default_cell_json", []() { return writeCellJson(defaultCell()); },
      "The paper's cell (Motoman HP20D + tilt-rotate positioner) as cell JSON.");
  m.def(
      "read_cell_json",
      [](const std::string& path) { return writeCellJson(readCell(std::filesystem::path(path))); },
      "Reads and validates a cell file; returns it as canonical cell JSON.", py::arg("path"));
  m.def(
      "parse_cell_json",
      [](const std::string& text) { return writeCellJson(parseCell(text, "cell")); },
      "Validates cell JSON text; returns the canonical form.", py::arg("cell_json"));
  m.def("positioner_frames", &positionerFramesPy,
        "Positioner frames in world for tilt a1 and rotation a2 (rad, model convention): 4x4 "
        "matrices (mm) base, cradle (turns with a1 only), table, part, table_zero; and gravity.",
        py::arg("cell_json"), py::arg("a1"), py::arg("a2"));

  m.def("plan_motion", &planMotionPy,
        "Positioner angles and robot joints per path point (robot/motion.hpp planMotion, paper "
        "eq. 16). Returns columns over the motion points: layer, path, index, a1, a2 (rad), "
        "residual (rad), speed, arc_on, path_start, path_end, flags, position/normal/"
        "deposition/used_deposition (n,3) in the part frame; warnings, max_residual, "
        "singular_points, limited_points, total (estimates). warn_unreachable: keep unreachable "
        "points with a warning instead of raising InvalidInput. tool_along_travel: tool x along "
        "the travel direction (else a fixed world x: the torch keeps its orientation while the "
        "positioner turns the part).",
        py::arg("plan_json"), py::arg("cell_json"), py::kw_only(),
        py::arg("warn_unreachable") = false,
        py::arg("tool_along_travel") = MotionOptions{}.toolAlongTravel,
        py::arg("progress") = py::none());

  m.def(
      "export_formats",
      []() {
        py::list out;
        for (ExportFormat f :
             {ExportFormat::Jbi, ExportFormat::Krl, ExportFormat::Rapid, ExportFormat::Ls,
              ExportFormat::Gcode, ExportFormat::Csv, ExportFormat::Json}) {
          out.append(py::make_tuple(std::string(toString(f)), std::string(fileExtension(f))));
        }
        return out;
      },
      "[(name, main file extension)] of every program format.");

  m.def("export_program", &exportProgramPy,
        "Plans the motion of plan_json in cell_json and writes the program of `format` (jbi, "
        "krl, rapid, ls, gcode, csv, json). Returns {format, files [(name, bytes, lines)], "
        "motion_count, arc_count, warnings, total_bytes}. With path: also writes the files all "
        "or nothing (path receives the main file, others go beside it). date fixes the header "
        "date ('' = the exporter's fixed default) so re-exports are byte-identical.",
        py::arg("plan_json"), py::arg("cell_json"), py::kw_only(), py::arg("format") = "jbi",
        py::arg("path") = py::none(), py::arg("program_name") = "", py::arg("date") = "",
        py::arg("gcode_mode") = "tcp", py::arg("arc_output") = 1,
        py::arg("warn_unreachable") = false,
        py::arg("tool_along_travel") = MotionOptions{}.toolAlongTravel,
        py::arg("progress") = py::none());
}

}  // namespace curvedslicer::bindings
