// Options of `curvedslicer plan` (see plan_command.hpp for what the command does).
#include <memory>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "curvedslicer/core/error.hpp"
#include "curvedslicer/field/geodesic_field.hpp"
#include "plan_command.hpp"

namespace curvedslicer::cli {

namespace {

constexpr const char* kPlanFooter = R"(
Examples:
  curvedslicer plan part.stl --layer-thickness 1.5 --voxel 0.5 --bead-spacing 3.7 -o out/part
  curvedslicer plan blade.obj --start mesh:base.obj --cap-holes --layer-thickness 1.5 \
      --voxel 0.5 --bead-spacing 3.7 --initial-curve plane:0,0,0,1,0,0 -o out/blade
  curvedslicer plan base_wall.stl --thin-wall lowest --bead-spacing 1.65 -o out/base

Output (all files appear together, or none on any error):
  DIR/layer_0001.ply ...  one surface per layer (not with --thin-wall)
  DIR/voxel_sets.ply      the voxel layer sets of the paper's eq. 13 (not with --thin-wall)
  DIR/plan.json           the deposition plan: layers, paths in deposition order, per point the
                          position, layer normal, deposition direction and bead width,
                          per layer the bead coverage (schema:
                          resources/schema/plan.schema.json)
  DIR/plan.csv            the same points as a table: layer,path,point,closed,x,y,z,n,v,w
  DIR/report.json         the layer report plus a "plan" section (per-layer paths and warnings,
                          stage times, deposition statistics, coverage per layer and in total)

Exit codes: 0 success, 2 invalid input (including usage errors), 3 file I/O error,
4 resource limit (memory budget), 5 numerical failure, 130 interrupted (Ctrl-C), 1 other.)";

void addLayerJobDetails(CLI::App& plan, LayersArguments& l);

/// The planner's options: one line each (see docs/ADDING-AN-OPTION.md).
void addPlannerOptions(CLI::App& plan, OptionBindings<PlannerOptions>& b) {
  b.add(plan, "--bead-spacing",
        "Bead spacing s in mm (> 0), required: distance between neighbouring\n"
        "bead centre lines along the layer (with --thin-wall: between beads\n"
        "along the wall, the bead height).",
        "MM",
        [](std::string_view text, PlannerOptions& o) {
          o.beadSpacing = parseLength(text, "bead spacing");
        })
      ->required();
  b.addLength(plan, "--point-spacing", &PlannerOptions::pointSpacing, "point spacing",
              "Largest distance between robot points along a path, mm");
  b.addLength(plan, "--fit-tolerance", &PlannerOptions::fitTolerance, "fit tolerance",
              "Spline fit tolerance, mm");
  b.addAngle(plan, "--corner-angle", &PlannerOptions::cornerAngle, "corner angle",
             "Where a path turns by more than this within 0.2 mm, the spline fit\n"
             "keeps the raw vertex as an exact corner, degrees in (0, 180];\n"
             "180 keeps no corners, every path one smooth spline");
  b.add(plan, "--surface-method",
        "Surface geodesic distance: accurate (the curve inserted into the\n"
        "layer mesh, fast marching) or paper (eq. 15); default " +
            formatDefault(toString(PlannerOptions{}.geodesic.method)) + ".",
        "NAME", [](std::string_view text, PlannerOptions& o) {
          o.geodesic.method = parseSurfaceGeodesicMethod(text);
        });
  b.add(plan, "--narrow-strips",
        "Where paths of one level come closer than 0.95*s (the innermost\n"
        "ring of a thin region, a hole's front meeting the rim's):\n"
        "  centre_bead  one bead on the strip's centre line instead,\n"
        "               joined to the ring piece it continues; every\n"
        "               change is reported per layer\n"
        "  overlap      keep the paths; their beads overlap there\n"
        "Default " +
            narrowStripModeName(PlannerOptions{}.narrowStrips) + ".",
        "MODE", [](std::string_view text, PlannerOptions& o) {
          o.narrowStrips = parseNarrowStripMode(std::string(text));
        });
  b.add(plan, "--deposition-direction",
        "The deposition direction V of every path point (positioner and torch\n"
        "follow it):\n"
        "  growth   the paper's V (towards the nearest deposited material)\n"
        "           where it is within 30 deg of the layer's growth\n"
        "           direction (-normal, or the layer below's V where the\n"
        "           normal disagrees with it, e.g. on tiny layer fragments),\n"
        "           else the growth direction\n"
        "  nearest  the paper's V everywhere (paper section 3.2)\n"
        "Default " +
            std::string(depositionMethodName(PlannerOptions{}.deposition.method)) + ".",
        "NAME", [](std::string_view text, PlannerOptions& o) {
          o.deposition.method = parseDepositionMethod(std::string(text));
        });
  b.add(plan, "--min-feature-width",
        "Regions narrower than one bead but at least this wide get a single\n"
        "bead on their centre line (with a note of the shortfall); narrower\n"
        "ones are left out and reported, mm > 0 (default s/2).",
        "MM", [](std::string_view text, PlannerOptions& o) {
          // The struct's "< 0 = s/2" is this option's absence: a given value must be > 0.
          const double w = parseLength(text, "minimum feature width (--min-feature-width)");
          if (!(w > 0.0)) {
            throw InvalidInput(
                "minimum feature width (--min-feature-width) must be a positive "
                "number of mm: " +
                std::string(text) + "; pass e.g. 1.85, or leave it out for half the bead spacing");
          }
          o.minFeatureWidth = w;
        });
  b.add(
      plan, "--bead-width-range",
      "Adaptive bead width: per-point widths between MIN*s and MAX*s,\n"
      "0 < MIN <= 1 <= MAX (e.g. 0.7,1.3); off = fixed width s (default " +
          std::string(PlannerOptions{}.widthMin == 1.0 && PlannerOptions{}.widthMax == 1.0 ? "off"
                                                                                           : "on") +
          ").",
      "MIN,MAX|off",
      [](std::string_view text, PlannerOptions& o) { parseBeadWidthRange(text, o); });
  b.addFlag(plan, "--no-connect-insets", &PlannerOptions::connectInsets, false,
            "Deposit every ring as its own arc-on path instead of joining\n"
            "consecutive rings of one region with a short step-over.");
  b.addFlag(plan, "--no-gap-fill", &PlannerOptions::fillGaps, false,
            "Leave uncovered strips between beads empty instead of giving\n"
            "each strip at least the minimum feature width wide a centre-line bead\n"
            "and widening the beads beside narrower strips into them.");
  b.add(plan, "--min-gap-area",
        "Gap fill: smallest uncovered patch that gets a fill bead, mm²\n"
        "(> 0; default s²).",
        "MM2", [](std::string_view text, PlannerOptions& o) {
          const double a = parseLength(text, "minimum gap area (--min-gap-area)");
          if (!(a > 0.0)) {
            throw InvalidInput(
                "minimum gap area (--min-gap-area) must be a positive number of "
                "mm²: " +
                std::string(text) + "; pass e.g. 4, or leave it out for the bead spacing squared");
          }
          o.minGapArea = a;
        });
  b.addFlag(plan, "--no-corner-fill", &PlannerOptions::cornerFill, false,
            "Keep the outer ring at half a bead from the edge in acute corners\n"
            "instead of dipping it toward the corner (the corner's wedge stays void).");
  b.addAngle(plan, "--corner-fill-angle", &PlannerOptions::cornerFillAngle,
             "corner fill angle (--corner-fill-angle)",
             "Corner fill: fill corners of the layer boundary sharper than this,\n"
             "degrees in (0, 180); the default takes acute corners");
  b.add(plan, "--corner-overdeposit",
        "Corner fill: how far a bead's edge may pass the layer boundary in\n"
        "mm (>= 0; default s/4).",
        "MM", [](std::string_view text, PlannerOptions& o) {
          const double d = parseLength(text, "corner overdeposit (--corner-overdeposit)");
          if (!(d >= 0.0)) {
            throw InvalidInput(
                "corner overdeposit (--corner-overdeposit) must be a non-negative number of mm: " +
                std::string(text) +
                "; pass e.g. 0.9, or leave it out for a quarter of the bead "
                "spacing");
          }
          o.cornerOverdeposit = d;
        });
  b.addFlag(plan, "--no-coverage", &PlannerOptions::measureCoverage, false,
            "Do not measure the layers' bead coverage (void and overlap\n"
            "shares in plan.json, report.json and the summary).");
}

/// The model, the layer job's options (as `layers`), the initial curve, the thin wall, output.
void addPlanOptions(CLI::App& plan, PlanArguments& args) {
  LayersArguments& l = args.layers;
  plan.add_option("MODEL", l.model,
                  "The part, in mm: a closed triangle mesh (STL or OBJ) or a CAD solid\n"
                  "(STEP, IGES, BREP; see `layers --help`); with --thin-wall the wall's\n"
                  "(open) surface.")
      ->required()
      ->type_name("FILE");
  plan.add_option("--start", l.start,
                  "Start surface, as for `layers` (default " + l.start +
                      "); faces:IDS are\n"
                      "0-based triangle positions for STL/OBJ, FreeCAD face numbers\n"
                      "(1-based) for CAD.")
      ->type_name("SPEC");
  plan.add_option("--layer-thickness", l.layerThickness,
                  "Layer thickness h in mm (> 0); required unless --thin-wall.")
      ->type_name("MM");
  plan.add_option("--voxel", l.voxelSize,
                  "Voxel edge length L in mm (> 0); required unless --thin-wall.")
      ->type_name("MM");
  addPlannerOptions(plan, args.planner);
  plan.add_option("--initial-curve", args.initialCurve,
                  "Initial curve of every layer (paths are equidistant from it):\n"
                  "  boundary             the layer's edge; contour-parallel paths\n"
                  "                       inward, the outer bead's edge on the part\n"
                  "                       edge\n"
                  "  plane:X,Y,Z,NX,NY,NZ the section with the plane through X,Y,Z with\n"
                  "                       normal NX,NY,NZ (mm, model coordinates);\n"
                  "                       parallel paths on both sides\n"
                  "  mesh:FILE            the section with a surface mesh (STL/OBJ)\n"
                  "Default " +
                      args.initialCurve + ".")
      ->type_name("SPEC");
  plan.add_option("--thin-wall", args.thinWall,
                  "Thin-wall mode (the paper's turbine base): MODEL is the wall's\n"
                  "surface; beads are curves along it at k*s from an edge:\n"
                  "  lowest           the boundary loop lowest along z\n"
                  "  lowest:AX,AY,AZ  lowest along the axis AX,AY,AZ\n"
                  "  nearest:X,Y,Z    the boundary loop nearest to X,Y,Z (mm)\n"
                  "No volume layers are computed (--voxel, --layer-thickness unused).")
      ->type_name("EDGE");
  addLayerJobDetails(plan, l);
  plan.footer(kPlanFooter);
}

/// --method, --grid, --format, --memory-budget, --tessellation-tolerance, flags and output.
void addLayerJobDetails(CLI::App& plan, LayersArguments& l) {
  const LayerJobOptions defaults;
  plan.add_option("--method", l.method,
                  "Volume geodesic method: anyangle (also 'exact') or paper (default " +
                      formatDefault(toString(defaults.geodesic.method)) + ").")
      ->type_name("NAME");
  plan.add_option("--grid", l.grid,
                  "Voxel grid orientation: pca or model (default " +
                      formatDefault(toString(defaults.voxelize.alignment)) + ").")
      ->type_name("NAME");
  plan.add_option("--format", l.format,
                  "Layer file format: ply or obj (default " +
                      formatDefault(toString(LayerJobArguments{}.format)) + ").")
      ->type_name("NAME");
  plan.add_option("--memory-budget", l.memoryBudgetMb,
                  "Memory the job may use, MB (default 0 = 80 % of physical memory).")
      ->type_name("MB");
  addTessellationOption(plan, l);
  addLayerSimplificationOptions(plan, l);
  plan.add_flag("--cap-holes", l.capHoles, "Close the holes of an open model first (as `layers`).");
  plan.add_flag("-q,--quiet", l.quiet, "No progress and no summary; errors still go to stderr.");
  plan.add_option("-o,--output", l.output,
                  "Output folder (created if missing), required; see Output below.")
      ->required()
      ->type_name("DIR");
}

}  // namespace

void addPlanCommand(CLI::App& app, CommandList& commands) {
  auto args = std::make_shared<PlanArguments>();
  CLI::App* plan = app.add_subcommand(
      "plan",
      "Slice a solid into curved layers and plan equidistant deposition paths on them (or plan "
      "the beads of a thin wall), with deposition directions; writes plan.json and plan.csv.");
  addPlanOptions(*plan, *args);
  commands.push_back({plan, [args] { return runPlanCommand(*args); }});
}

}  // namespace curvedslicer::cli
