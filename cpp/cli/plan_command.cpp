#include "plan_command.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_errors.hpp"
#include "curvedslicer/core/atomic_file.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "curvedslicer/mesh/mesh_io.hpp"
#include "curvedslicer/mesh/mesh_repair.hpp"
#include "curvedslicer/paths/planner.hpp"
#include "curvedslicer/pipeline/layer_output.hpp"
#include "curvedslicer/pipeline/layer_pipeline.hpp"
#include "curvedslicer/pipeline/option_parsing.hpp"
#include "curvedslicer/pipeline/report_json.hpp"
#include "curvedslicer/plan/plan_io.hpp"
#include "terminal_progress.hpp"

namespace curvedslicer::cli {

namespace fs = std::filesystem;

namespace {

constexpr const char* kVoxelSetsFile = "voxel_sets.ply";
constexpr const char* kReportFile = "report.json";
constexpr const char* kPlanJsonFile = "plan.json";
constexpr const char* kPlanCsvFile = "plan.csv";

using Json = nlohmann::ordered_json;

/// "a,b,c[,…]" with exactly `count` numbers.
std::vector<double> parseNumberList(std::string_view text, std::size_t count, std::string_view what,
                                    std::string_view example) {
  std::vector<double> values;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t comma = text.find(',', begin);
    const std::string_view item = text.substr(
        begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin);
    const double v = parseLength(item, what);
    if (!std::isfinite(v)) {
      throw InvalidInput(std::string(what) + " needs finite numbers: '" + std::string(text) +
                         "'; pass e.g. " + std::string(example));
    }
    values.push_back(v);
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  if (values.size() != count) {
    throw InvalidInput(std::string(what) + " needs " + std::to_string(count) +
                       " comma-separated numbers: '" + std::string(text) + "'; pass e.g. " +
                       std::string(example));
  }
  return values;
}

SurfaceGeodesicMethod parseSurfaceMethod(std::string_view name) {
  if (name == "accurate") return SurfaceGeodesicMethod::Accurate;
  if (name == "paper") return SurfaceGeodesicMethod::Paper;
  throw InvalidInput("unknown surface geodesic method: '" + std::string(name) +
                     "'; choose accurate or paper");
}

/// Parses --initial-curve; a mesh: file is read here.
InitialCurve parseInitialCurve(std::string_view text) {
  InitialCurve curve;
  if (text == "boundary") return curve;
  if (text.rfind("plane:", 0) == 0) {
    const auto v = parseNumberList(text.substr(6), 6, "initial plane", "plane:0,0,0,1,0,0");
    curve.kind = InitialCurveKind::Plane;
    curve.planePoint = Vec3(v[0], v[1], v[2]);
    curve.planeNormal = Vec3(v[3], v[4], v[5]);
    if (!(curve.planeNormal.norm() > 0.0)) {
      throw InvalidInput("initial plane normal is zero: '" + std::string(text) +
                         "'; pass a non-zero normal, e.g. plane:0,0,0,1,0,0");
    }
    return curve;
  }
  if (text.rfind("mesh:", 0) == 0 && text.size() > 5) {
    curve.kind = InitialCurveKind::Surface;
    try {
      curve.surface = cleanMesh(readMesh(fs::path(std::string(text.substr(5))))).mesh;
    } catch (const InvalidInput& e) {
      throw InvalidInput(std::string("initial surface mesh: ") + e.what());
    }
    return curve;
  }
  throw InvalidInput("unknown initial curve: '" + std::string(text) +
                     "'; choose boundary, plane:X,Y,Z,NX,NY,NZ or mesh:FILE");
}

/// Parses --thin-wall: lowest | lowest:AX,AY,AZ | nearest:X,Y,Z.
void parseThinWallEdge(std::string_view text, ThinWallOptions& options) {
  if (text == "lowest") {
    options.edge = WallEdgeKind::LowestAlongAxis;
    options.axis = Vec3::UnitZ();
  } else if (text.rfind("lowest:", 0) == 0) {
    const auto v = parseNumberList(text.substr(7), 3, "thin-wall axis", "lowest:0,0,1");
    options.edge = WallEdgeKind::LowestAlongAxis;
    options.axis = Vec3(v[0], v[1], v[2]);
  } else if (text.rfind("nearest:", 0) == 0) {
    const auto v = parseNumberList(text.substr(8), 3, "thin-wall edge point", "nearest:0,0,0");
    options.edge = WallEdgeKind::NearestToPoint;
    options.point = Vec3(v[0], v[1], v[2]);
  } else {
    throw InvalidInput("unknown thin-wall edge: '" + std::string(text) +
                       "'; choose lowest, lowest:AX,AY,AZ or nearest:X,Y,Z");
  }
}

Json planReport(const PlanResult& result) {
  Json j;
  const PlanStats& s = result.stats;
  j["paths"] = result.plan.pathCount();
  j["points"] = result.plan.pointCount();
  j["arc_length_mm"] = s.arcLength;
  j["travel_mm"] = s.travel;
  j["layers_without_paths"] = s.layersWithoutPaths;
  j["dropped_fragments"] = s.droppedFragments;
  j["seams_too_close"] = s.seamsTooClose;
  j["max_fit_deviation_mm"] = s.maxFitDeviation;
  const DepositionStats& d = s.deposition;
  j["deposition"] =
      Json{{"points", d.points},
           {"towards_surface", d.towardsSurface},
           {"towards_beads", d.towardsBeads},
           {"normal_fallbacks", d.normalFallbacks},
           {"min_distance_mm", std::isfinite(d.minDistance) ? Json(d.minDistance) : Json(nullptr)},
           {"max_distance_mm", d.maxDistance}};
  Json times = Json::array();
  for (const PlanStageTime& t : s.stageTimes) {
    times.push_back(Json{{"stage", t.name}, {"seconds", t.seconds}});
  }
  j["stage_times"] = times;
  Json layers = Json::array();
  for (const PlanLayer& layer : result.plan.layers) {
    double length = 0.0;
    std::size_t points = 0;
    for (const PlanPath& p : layer.paths) {
      length += p.length;
      points += p.points.size();
    }
    layers.push_back(Json{{"index", layer.index},
                          {"height_mm", layer.height},
                          {"paths", layer.paths.size()},
                          {"points", points},
                          {"arc_length_mm", length},
                          {"warnings", layer.warnings}});
  }
  j["layers"] = layers;
  return j;
}

void printLayerWarnings(const Plan& plan) {
  std::size_t count = 0;
  for (const PlanLayer& layer : plan.layers) {
    if (layer.paths.empty()) ++count;
  }
  if (count == 0) return;
  for (const PlanLayer& layer : plan.layers) {
    if (!layer.paths.empty() || layer.warnings.empty()) continue;
    std::fprintf(stderr, "curvedslicer: warning: layer %d has no paths: %s\n", layer.index,
                 layer.warnings.front().c_str());
  }
}

double checkedLength(const std::string& text, const char* what) {
  return parseLength(text, what);  // range checks in validatePlannerOptions / ThinWall
}

}  // namespace

int runPlanCommand(const PlanArguments& args) {
  installInterruptHandlers();
  const LayersArguments& la = args.layers;
  TerminalProgress display(!la.quiet);
  const fs::path outputDir(la.output);
  try {
    using Clock = std::chrono::steady_clock;
    const bool thinWall = !args.thinWall.empty();
    // ---- parse and check every argument before touching a file ---------------------------------
    PlannerOptions planner;
    planner.beadSpacing = checkedLength(args.beadSpacing, "bead spacing");
    planner.pointSpacing = checkedLength(args.pointSpacing, "point spacing");
    planner.fitTolerance = checkedLength(args.fitTolerance, "fit tolerance");
    planner.cornerAngle = parseAngle(args.cornerAngle, "corner angle");
    planner.geodesic.method = parseSurfaceMethod(args.surfaceMethod);
    planner.narrowStrips = parseNarrowStripMode(args.narrowStrips);
    ThinWallOptions wall;
    LayerJobOptions job;
    StartSurfaceSpec start;
    LayerFileFormat format = LayerFileFormat::Ply;
    if (thinWall) {
      wall.beadSpacing = planner.beadSpacing;
      wall.pointSpacing = planner.pointSpacing;
      wall.fitTolerance = planner.fitTolerance;
      wall.cornerAngle = planner.cornerAngle;
      wall.geodesic = planner.geodesic;
      parseThinWallEdge(args.thinWall, wall);
      validateThinWallOptions(wall);
      if (args.initialCurve != "boundary") {
        throw InvalidInput("--initial-curve does not apply with --thin-wall: '" +
                           args.initialCurve + "'; the wall's edge is the initial curve");
      }
    } else {
      if (la.layerThickness.empty() || la.voxelSize.empty()) {
        throw InvalidInput(std::string("missing ") +
                           (la.layerThickness.empty() ? "--layer-thickness" : "--voxel") +
                           ": required unless --thin-wall; pass e.g. --layer-thickness 1.5 "
                           "--voxel 0.5");
      }
      job.layers.layerThickness = parseLength(la.layerThickness, "layer thickness");
      job.voxelize.voxelSize = parseLength(la.voxelSize, "voxel size");
      job.geodesic.method = parseGeodesicMethod(la.method);
      job.voxelize.alignment = parseGridAlignment(la.grid);
      format = parseLayerFileFormat(la.format);
      start = parseStartSurfaceSpec(la.start);
      const double budgetMb = parseLength(la.memoryBudgetMb, "memory budget");
      if (!std::isfinite(budgetMb) || budgetMb < 0.0) {
        throw InvalidInput("memory budget must be 0 (automatic) or a positive number of MB: '" +
                           la.memoryBudgetMb + "'; pass e.g. --memory-budget 4096");
      }
      job.voxelize.memoryBudgetBytes = budgetMb * 1024.0 * 1024.0;
      job.capHoles = la.capHoles;
      validateLayerJobOptions(job);
      validatePlannerOptions(planner);  // the initial curve is checked after reading it
    }
    checkOutputFolder(outputDir);

    const Progress progress([&display](double fraction, std::string_view stage) {
      return display.update(fraction, stage);
    });

    // ---- read ----------------------------------------------------------------------------------
    progress.report(0.0, "read");
    const auto readBegin = Clock::now();
    const TriMesh model = readMesh(fs::path(la.model));
    if (!thinWall) {
      job.start = loadStartSurface(start);
      planner.initialCurve = parseInitialCurve(args.initialCurve);
      validatePlannerOptions(planner);
    }
    const double readSeconds = std::chrono::duration<double>(Clock::now() - readBegin).count();

    OutputStaging staging(outputDir);
    Json report;
    PlanResult planned;
    std::vector<std::string> layerFiles;
    if (thinWall) {
      // ---- thin wall: plan directly on the surface -------------------------------------------
      const TriMesh surface = cleanMesh(model).mesh;
      planned = planThinWall(surface, wall, progress.sub(0.0, 0.95));
      planned.plan.model = la.model;
      planned.plan.start = "thin-wall:" + args.thinWall;
      report["inputs"] = Json{{"model", la.model},
                              {"thin_wall_edge", args.thinWall},
                              {"bead_spacing_mm", wall.beadSpacing},
                              {"point_spacing_mm", wall.pointSpacing},
                              {"fit_tolerance_mm", wall.fitTolerance},
                              {"corner_angle_deg", wall.cornerAngle},
                              {"surface_method", args.surfaceMethod},
                              {"version", CURVEDSLICER_VERSION}};
      report["stage_times"] = Json::array({Json{{"stage", "read"}, {"seconds", readSeconds}}});
    } else {
      // ---- volume layers, then paths ------------------------------------------------------------
      LayerJobResult result = runLayerJob(model, job, progress.sub(0.0, 0.6));
      result.stageTimes.insert(result.stageTimes.begin(), StageTime{"read", readSeconds});
      result.totalSeconds += readSeconds;
      const auto planBegin = Clock::now();
      planned = planLayers(result.layers.surfaces, result.source, planner, progress.sub(0.6, 0.95));
      const double planSeconds = std::chrono::duration<double>(Clock::now() - planBegin).count();
      result.stageTimes.push_back(StageTime{"plan", planSeconds});
      result.totalSeconds += planSeconds;
      Plan& plan = planned.plan;
      plan.model = la.model;
      plan.start = la.start;
      plan.parameters.layerThickness = job.layers.layerThickness;
      plan.parameters.voxelSize = job.voxelize.voxelSize;
      plan.parameters.fieldMethod = std::string(toString(result.field.method));
      layerFiles = layerFileNames(result.layers, format);
      for (std::size_t k = 0; k < plan.layers.size() && k < layerFiles.size(); ++k) {
        plan.layers[k].surface = layerFiles[k];
      }

      const Progress writeProgress = progress.sub(0.95, 1.0);
      writeProgress.report(0.0, "write");
      const MeshFormat meshFormat =
          format == LayerFileFormat::Ply ? MeshFormat::Ply : MeshFormat::Obj;
      const auto& surfaces = result.layers.surfaces;
      for (std::size_t k = 0; k < surfaces.size(); ++k) {
        staging.stage(layerFiles[k],
                      [&](const fs::path& path) { writeMesh(path, surfaces[k].mesh, meshFormat); });
        writeProgress.report(0.8 * static_cast<double>(k + 1) / surfaces.size(), "write");
      }
      staging.stage(kVoxelSetsFile, [&](const fs::path& path) {
        writeFileAtomically(
            path,
            [&](std::ostream& out) { writeVoxelSetsPly(out, result.layers, result.field.field); },
            /*binary=*/true);
      });
      LayerReportInputs reportInputs;
      reportInputs.modelPath = la.model;
      reportInputs.modelFileTriangles = model.triangleCount();
      reportInputs.startSpec = la.start;
      reportInputs.layerFormat = format;
      reportInputs.layerFiles = layerFiles;
      reportInputs.voxelSetsFile = kVoxelSetsFile;
      result.peakMemoryBytes = peakResidentMemoryBytes();
      report = makeLayerReport(reportInputs, job, result);
    }

    // ---- plan files and report -----------------------------------------------------------------
    Json planSection = planReport(planned);
    planSection["inputs"] = Json{{"bead_spacing_mm", planned.plan.parameters.beadSpacing},
                                 {"point_spacing_mm", planned.plan.parameters.pointSpacing},
                                 {"fit_tolerance_mm", planned.plan.parameters.fitTolerance},
                                 {"corner_angle_deg", planner.cornerAngle},
                                 {"initial_curve", planned.plan.parameters.initialCurve},
                                 {"surface_method", planned.plan.parameters.surfaceMethod}};
    if (!planned.plan.parameters.narrowStrips.empty()) {
      planSection["inputs"]["narrow_strips"] = planned.plan.parameters.narrowStrips;
    }
    planSection["files"] = Json{{"json", kPlanJsonFile}, {"csv", kPlanCsvFile}};
    report["plan"] = planSection;
    const std::string planJson = formatPlanJson(planned.plan);
    const std::string planCsv = formatPlanCsv(planned.plan);
    staging.stage(kPlanJsonFile,
                  [&](const fs::path& path) { writeTextFileAtomically(path, planJson); });
    staging.stage(kPlanCsvFile,
                  [&](const fs::path& path) { writeTextFileAtomically(path, planCsv); });
    const std::string reportText = formatLayerReport(report);
    staging.stage(kReportFile,
                  [&](const fs::path& path) { writeTextFileAtomically(path, reportText); });
    progress.report(1.0, "write");  // last chance to cancel: nothing is in place yet
    staging.commit(isLayerFileName);
    display.finishLine();

    if (!la.quiet) {
      printLayerWarnings(planned.plan);
      std::printf(
          "curvedslicer: wrote a plan of %zu paths (%zu points) on %zu layers to %s "
          "(%s, %s, %s%s)\n",
          planned.plan.pathCount(), planned.plan.pointCount(), planned.plan.layers.size(),
          outputDir.string().c_str(), kPlanJsonFile, kPlanCsvFile, kReportFile,
          layerFiles.empty() ? "" : ", layer files");
    }
    return kExitOk;
  } catch (...) {
    return failWithCurrentException(display, outputDir.string(), kJobOutOfMemoryMessage);
  }
}

}  // namespace curvedslicer::cli
