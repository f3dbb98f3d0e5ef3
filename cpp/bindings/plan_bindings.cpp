// Python bindings of plan JSON, robot cell, motion planning and program export: thin
// conversions only. The planners are in job_bindings.cpp.
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
#include "curvedslicer/paths/coverage.hpp"
#include "curvedslicer/pipeline/export_job.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/configuration.hpp"
#include "curvedslicer/robot/motion.hpp"
#include "curvedslicer/robot/positioner.hpp"
#include "curvedslicer/robot/robot_kinematics.hpp"

namespace curvedslicer::bindings {

namespace {

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

py::dict estimateDict(const MotionEstimate& e) {
  py::dict d;
  d["bead_length_mm"] = e.beadLength;
  d["arc_time_s"] = e.arcTime;
  d["travel_length_mm"] = e.travelLength;
  d["travel_time_s"] = e.travelTime;
  d["dwell_time_s"] = e.dwellTime;
  d["cooling_wait_s"] = e.coolingWait;  // of dwell_time_s: waits for the minimum layer time
  d["cooled_layers"] = e.cooledLayers;
  d["total_time_s"] = e.totalTime;
  d["wire_length_mm"] = e.wireLength;
  d["deposited_volume_mm3"] = e.depositedVolume;
  d["deposited_mass_g"] = e.depositedMass;
  d["paths"] = e.paths;
  d["points"] = e.points;
  d["max_torch_angle"] = e.maxTorchAngle;              // rad
  d["max_gravity_deviation"] = e.maxGravityDeviation;  // rad
  return d;
}

py::dict configurationDict(const RobotConfiguration& c) {
  py::dict d;
  d["branch"] = c.branch;
  d["quadrant"] = c.quadrant;
  d["turn"] = c.turn;
  d["negative"] = c.negative;
  d["beyond180"] = c.beyond180;
  return d;
}

py::list pathSpanList(const std::vector<MotionPathSpan>& spans) {
  py::list out;
  for (const MotionPathSpan& s : spans) {
    py::dict d;
    d["layer"] = s.layer;
    d["path"] = s.path;
    d["begin"] = s.begin;
    d["end"] = s.end;
    d["configuration"] = configurationDict(s.configuration);
    out.append(d);
  }
  return out;
}

py::list speedReductionList(const std::vector<SpeedReduction>& reductions) {
  py::list out;
  for (const SpeedReduction& r : reductions) {
    py::dict d;
    d["layer"] = r.layer;
    d["path"] = r.path;
    d["first_index"] = r.firstIndex;
    d["last_index"] = r.lastIndex;
    d["min_speed"] = r.minSpeed;
    d["axis"] = r.axis;
    out.append(d);
  }
  return out;
}

py::list collisionList(const std::vector<CollisionReport>& collisions) {
  py::list out;
  for (const CollisionReport& c : collisions) {
    py::dict d;
    d["point"] = c.point;
    d["what"] = c.what;
    d["depth"] = c.depth;
    out.append(d);
  }
  return out;
}

// Motion points as columns: ints (n,) and vectors (n, 3), so 10^5 points stay cheap.
// Options arrive by value: the call runs without the GIL, so it must not share them with Python.
py::dict planMotionPy(const std::string& planJson, const std::string& cellJson,
                      MotionOptions options, const py::object& progress) {
  const Plan plan = parsePlanJson(planJson, "plan");
  const Cell cell = parseCell(cellJson, "cell");
  const MotionPlan motion = runWithProgress(
      progress, [&](Progress p) { return planMotion(plan, cell, options, std::move(p)); });
  const auto n = static_cast<py::ssize_t>(motion.points.size());
  py::array_t<std::int32_t> layer(n), path(n), index(n), flags(n), kind(n);
  py::array_t<double> a1(n), a2(n), residual(n), speed(n), time(n);
  py::array_t<double> torchAngle(n), travelAngle(n), workAngle(n);
  py::array_t<double> joints({n, py::ssize_t{6}});
  py::array_t<bool> arcOn(n), pathStart(n), pathEnd(n);
  py::array_t<double> position({n, py::ssize_t{3}}), deposition({n, py::ssize_t{3}}),
      used({n, py::ssize_t{3}}), normal({n, py::ssize_t{3}});
  py::array_t<double> toolInWorld({n, py::ssize_t{4}, py::ssize_t{4}});
  py::array_t<std::int32_t> configuration(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    const MotionPoint& p = motion.points[static_cast<std::size_t>(i)];
    layer.mutable_at(i) = p.layer;
    path.mutable_at(i) = p.path;
    index.mutable_at(i) = p.index;
    flags.mutable_at(i) = static_cast<std::int32_t>(p.flags);
    a1.mutable_at(i) = p.a1;
    a2.mutable_at(i) = p.a2;
    residual.mutable_at(i) = p.residual;
    torchAngle.mutable_at(i) = p.torchAngle;
    travelAngle.mutable_at(i) = p.travelAngle;
    workAngle.mutable_at(i) = p.workAngle;
    speed.mutable_at(i) = p.speed;
    time.mutable_at(i) = p.time;
    kind.mutable_at(i) = static_cast<std::int32_t>(p.kind);
    for (py::ssize_t k = 0; k < 6; ++k)
      joints.mutable_at(i, k) = p.joints[static_cast<std::size_t>(k)];
    arcOn.mutable_at(i) = p.arcOn;
    pathStart.mutable_at(i) = p.pathStart;
    pathEnd.mutable_at(i) = p.pathEnd;
    for (py::ssize_t k = 0; k < 3; ++k) {
      position.mutable_at(i, k) = p.position[k];
      deposition.mutable_at(i, k) = p.deposition[k];
      used.mutable_at(i, k) = p.usedDeposition[k];
      normal.mutable_at(i, k) = p.normal[k];
    }
    const Eigen::Matrix4d tool = p.toolInWorld.matrix();
    for (py::ssize_t r = 0; r < 4; ++r)
      for (py::ssize_t c = 0; c < 4; ++c) toolInWorld.mutable_at(i, r, c) = tool(r, c);
    configuration.mutable_at(i) = p.configuration;
  }
  py::dict d;
  d["layer"] = layer;
  d["path"] = path;
  d["index"] = index;
  d["flags"] = flags;
  d["a1"] = a1;
  d["a2"] = a2;
  d["residual"] = residual;
  d["torch_angle"] = torchAngle;
  d["travel_angle"] = travelAngle;
  d["work_angle"] = workAngle;
  d["speed"] = speed;
  d["time"] = time;
  d["kind"] = kind;
  d["kind_names"] = py::make_tuple("path", "retract", "travel", "approach", "home");
  d["joints"] = joints;
  d["arc_on"] = arcOn;
  d["path_start"] = pathStart;
  d["path_end"] = pathEnd;
  d["position"] = position;
  d["deposition"] = deposition;
  d["used_deposition"] = used;
  d["normal"] = normal;
  d["tool_in_world"] = toolInWorld;
  d["configuration"] = configuration;
  d["warnings"] = motion.warnings;
  d["max_residual"] = motion.maxResidual;
  d["singular_points"] = motion.singularPoints;
  d["limited_points"] = motion.limitedPoints;
  d["total"] = estimateDict(motion.total);
  py::list layers;
  for (const MotionEstimate& e : motion.layers) layers.append(estimateDict(e));
  d["layers"] = layers;
  d["table_to_part"] = poseMatrix(motion.tableToPart);  // the placement used (4x4, mm)
  py::dict fixture;  // the riser and plate used (placement auto: the riser it chose), mm
  fixture["riser_height_mm"] = motion.fixture.riserHeight;
  fixture["riser_diameter_mm"] = motion.fixture.riserDiameter;
  fixture["substrate_thickness_mm"] = motion.fixture.substrateThickness;
  fixture["substrate_size_mm"] = motion.fixture.substrateSize;
  d["fixture"] = fixture;
  d["near_singular_band"] = motion.nearSingularBand;
  d["notes"] = motion.notes;
  d["paths"] = pathSpanList(motion.paths);
  d["speed_reductions"] = speedReductionList(motion.speedReductions);
  d["collisions"] = collisionList(motion.collisions);
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

// The export job (pipeline/export_job.hpp): plans the motion and writes the program into
// memory; with `path`, also writes the files all or nothing, so nothing is written unless every
// step succeeded.
py::dict exportProgramPy(const std::string& planJson, const std::string& cellJson,
                         const std::string& format, const std::optional<std::string>& path,
                         ExportOptions options, MotionOptions motion, bool allowForeignCell,
                         const py::object& progress) {
  ExportJobOptions job;
  job.format = parseExportFormat(format);
  if (path) options.programName = programNameForFile(*path, options.programName);  // name rule
  job.program = options;
  job.motion = motion;
  job.allowForeignCell = allowForeignCell;
  const Plan plan = parsePlanJson(planJson, "plan");
  const Cell cell = parseCell(cellJson, "cell");
  std::optional<std::filesystem::path> output;
  if (path) output = std::filesystem::path(*path);
  const ExportJobResult result = runWithProgress(
      progress, [&](Progress p) { return runExportJob(plan, cell, job, output, std::move(p)); });
  return exportResultDict(result.program);
}

/// A layer's coverage as a dict, or None when not measured.
py::object coverageDict(const LayerCoverage& c) {
  if (!c.measured) return py::none();
  py::dict d;
  d["area_mm2"] = c.area;
  d["void_share"] = c.voidShare;
  d["overlap_share"] = c.overlapShare;
  d["bead_width_mm"] = c.beadWidth;
  d["arc_starts"] = c.arcStarts;
  py::list voids;
  for (const CoverageVoid& v : c.voids) {
    py::dict vd;
    vd["area_mm2"] = v.area;
    vd["centre_mm"] = py::make_tuple(v.centre.x(), v.centre.y(), v.centre.z());
    vd["size_mm"] = v.size;
    voids.append(vd);
  }
  d["voids"] = voids;
  return d;
}

/// The plan's coverage in total (paths/coverage.hpp summarizeCoverage).
py::dict coverageTotalsDict(const Plan& plan) {
  const PlanCoverageSummary s = summarizeCoverage(plan, 3);
  py::dict d;
  d["measured_layers"] = s.measuredLayers;
  d["area_mm2"] = s.area;
  d["void_share"] = s.voidShare;
  d["overlap_share"] = s.overlapShare;
  d["arc_starts"] = s.arcStarts;
  d["worst_layers"] = s.worstLayers;
  return d;
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
    l["coverage"] = coverageDict(layer.coverage);
    perLayer.append(l);
  }
  d["per_layer"] = perLayer;
  d["coverage"] = coverageTotalsDict(plan);
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
  if (!p.depositionDirection.empty()) params["deposition_direction"] = p.depositionDirection;
  if (p.cornerAngle) params["corner_angle_deg"] = *p.cornerAngle;
  if (p.minFeatureWidth) params["min_feature_width_mm"] = *p.minFeatureWidth;
  if (p.beadWidthRange) {
    params["bead_width_range"] = py::make_tuple((*p.beadWidthRange)[0], (*p.beadWidthRange)[1]);
  }
  if (p.connectInsets) params["connect_insets"] = *p.connectInsets;
  if (p.fillGaps) params["fill_gaps"] = *p.fillGaps;
  if (p.minGapArea) params["min_gap_area_mm2"] = *p.minGapArea;
  if (p.cornerOverdeposit) params["corner_overdeposit_mm"] = *p.cornerOverdeposit;
  if (p.cornerFillAngle) params["corner_fill_angle_deg"] = *p.cornerFillAngle;
  d["parameters"] = params;
  return d;
}

// Every path as (layer, index, closed, points (k, 3), normals (k, 3), deposition (k, 3)), and
// with_widths: also widths (k,) mm (0 in memory = the bead spacing, as the file writes it) and
// dwell (s).
py::list planPathsPy(const std::string& planJson, bool withWidths) {
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
      if (!withWidths) {
        out.append(py::make_tuple(path.layer, path.index, path.closed, pts, nrm, dep));
        continue;
      }
      py::array_t<double> widths(k);
      for (py::ssize_t i = 0; i < k; ++i) {
        const double w = path.points[static_cast<std::size_t>(i)].width;
        widths.mutable_at(i) = w > 0.0 ? w : plan.parameters.beadSpacing;
      }
      out.append(
          py::make_tuple(path.layer, path.index, path.closed, pts, nrm, dep, widths, path.dwell));
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

// The robot arm's joint points in world (mm) for controller joints (rad): for drawing the arm.
py::dict robotArmPointsPy(const std::string& cellJson, const JointVector& joints) {
  const Cell cell = parseCell(cellJson, "cell");
  const ArmPoints arm = computeArmPoints(cell.robot, joints);
  const Pose base = cell.robot.base;
  const Pose tcp = base * computeFlangePose(cell.robot, joints) * cell.tool.tcp;
  auto point = [](const Vec3& v) { return py::make_tuple(v.x(), v.y(), v.z()); };
  py::dict d;
  d["base"] = point(base * arm.base);
  d["shoulder"] = point(base * arm.shoulder);
  d["elbow"] = point(base * arm.elbow);
  d["wrist"] = point(base * arm.wrist);
  d["flange"] = point(base * arm.flange);
  d["tcp"] = poseMatrix(tcp);
  return d;
}

}  // namespace

void registerPlanBindings(py::module_& m) {
  m.def(
      "format_plan_json",
      [](const std::string& text) { return formatPlanJson(parsePlanJson(text, "plan")); },
      "Parses, validates and re-formats plan JSON (canonical text; identical for canonical "
      "input).",
      py::arg("plan_json"));
  m.def("plan_summary", &planSummaryPy,
        "Validated plan JSON -> {model, start, layers, paths, points, per_layer (index, height, "
        "paths, warnings, coverage: None or {area_mm2, void_share, overlap_share, bead_width_mm, "
        "arc_starts, voids: [{area_mm2, centre_mm, size_mm}]}), coverage (totals: "
        "measured_layers, area_mm2, void_share, overlap_share (area-weighted), arc_starts, "
        "worst_layers), parameters}.",
        py::arg("plan_json"));
  m.def("plan_paths", &planPathsPy,
        "Validated plan JSON -> [(layer, index, closed, points (k,3) mm, normals (k,3), "
        "deposition (k,3))] in deposition order; with_widths=True appends widths (k,) mm and "
        "dwell (s) to every tuple.",
        py::arg("plan_json"), py::arg("with_widths") = false);
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

  m.def(
      "plan_motion", &planMotionPy,
      "Positioner angles and robot joints per path point (robot/motion.hpp planMotion, paper "
      "eq. 16) with options: MotionOptions (unreachable='warn' keeps unreachable points with "
      "a warning instead of raising InvalidInput; tool_along_travel: tool x along the travel "
      "direction, else a fixed world x, turned about the torch axis per path so joint 6 stays "
      "away from +-180 deg). Returns columns over the motion points: layer, path, index, kind "
      "(codes into kind_names: path, retract, travel, approach, home), a1, a2 (rad), joints "
      "(n,6, rad), residual (rad: the gravity deviation of the deposit), torch_angle, "
      "travel_angle (push > 0), work_angle (rad: the torch off gravity to clear deposit, table "
      "and fixture), speed (mm/s of the arriving move), time (s from the start, "
      "axis speed limits respected), arc_on, path_start, path_end, flags, "
      "position/normal/deposition/used_deposition (n,3) in the part frame, tool_in_world (n,4,4 "
      "mm: the TCP pose in world), configuration (IK branch bits: 1 back, 2 elbow down, 4 "
      "wrist flip); warnings, notes, "
      "max_residual, singular_points, limited_points, near_singular_band (rad), paths "
      "(layer, path, begin, end, configuration), speed_reductions (layer, path, first_index, "
      "last_index, min_speed, axis), collisions (point, what, depth), total (estimates; "
      "total_time_s = the last point's time plus the dwell after it; max_torch_angle and "
      "max_gravity_deviation in rad), layers (the same per plan layer), table_to_part (4x4 mm: the "
      "part placement used, MotionOptions.placement), fixture (riser_height_mm, riser_diameter_mm, "
      "substrate_thickness_mm, substrate_size_mm: the fixture used; placement \"auto\" "
      "chooses the riser's height).",
      py::arg("plan_json"), py::arg("cell_json"), py::kw_only(),
      py::arg("options") = MotionOptions{}, py::arg("progress") = py::none());

  m.def("robot_arm_points", &robotArmPointsPy,
        "Forward kinematics of the cell's robot for controller joints (rad, 6): joint points in "
        "world (mm) base, shoulder, elbow, wrist (centre), flange, and tcp (4x4, mm: the tool "
        "centre point's pose in world).",
        py::arg("cell_json"), py::arg("joints"));

  m.def(
      "export_formats",
      []() {
        py::list out;
        for (const ExportFormatInfo& f : exportFormats()) {
          out.append(py::make_tuple(std::string(f.name), std::string(f.extension)));
        }
        return out;
      },
      "[(name, main file extension)] of every program format.");

  m.def("export_program", &exportProgramPy,
        "Plans the motion of plan_json in cell_json (motion: MotionOptions) and writes the "
        "program of `format` (jbi, krl, rapid, ls, gcode, csv, json) with options: "
        "ExportOptions (its default date is fixed, so re-exports are byte-identical). Returns "
        "{format, files [(name, bytes, lines)], motion_count, arc_count, warnings, "
        "total_bytes}. With path: also writes the files all or nothing (path receives the main "
        "file, others go beside it). A vendor's language (jbi yaskawa, krl kuka, rapid abb, ls "
        "fanuc) for another vendor's cell raises InvalidInput unless allow_foreign_cell.",
        py::arg("plan_json"), py::arg("cell_json"), py::kw_only(), py::arg("format") = "jbi",
        py::arg("path") = py::none(), py::arg("options") = ExportOptions{},
        py::arg("motion") = MotionOptions{}, py::arg("allow_foreign_cell") = false,
        py::arg("progress") = py::none());
}

}  // namespace curvedslicer::bindings
