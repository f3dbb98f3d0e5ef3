// Options of `curvedslicer layers` (see layers_command.hpp for what the command does).
#include <memory>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "curvedslicer/occ/shape_tessellation.hpp"
#include "layers_command.hpp"
#include "option_binding.hpp"

namespace curvedslicer::cli {

namespace {

constexpr const char* kLayersFooter = R"(
Example:
  curvedslicer layers part.stl --layer-thickness 1.5 --voxel 0.5 -o out/part
  curvedslicer layers geom.obj --start mesh:base.obj --cap-holes --layer-thickness 1.5 \
      --voxel 0.5 -o out/geom

Output (all files appear together, or none on any error):
  DIR/layer_0001.ply ...  one surface per layer (mm, model coordinates)
  DIR/voxel_sets.ply      binary PLY point cloud of the voxel layer sets of the paper's eq. 13:
                          x y z (voxel centre, model coordinates, mm), layer, distance (mm)
  DIR/report.json         inputs, mesh diagnostics, grid, field, timings, per-layer statistics
Layer files of an earlier run in DIR are replaced.

Exit codes: 0 success, 2 invalid input (including usage errors), 3 file I/O error,
4 resource limit (memory budget), 5 numerical failure, 130 interrupted (Ctrl-C), 1 other.)";

}  // namespace

void addTessellationOption(CLI::App& command, LayersArguments& args) {
  command
      .add_option("--tessellation-tolerance", args.tessellationTolerance,
                  "CAD models only: chord error of the tessellation, mm (> 0);\n"
                  "default a quarter of the voxel size (with --thin-wall " +
                      formatDefault(TessellationOptions{}.linearDeflection) +
                      ");\nangular deflection " +
                      formatDefault(TessellationOptions{}.angularDeflection) + " rad.")
      ->type_name("MM");
}

void addLayerSimplificationOptions(CLI::App& command, LayersArguments& args) {
  const bool simplifiedByDefault = LayerSimplificationOptions{}.enabled;
  command.add_flag("--simplify-layers", args.simplifyLayers,
                   "Simplify each layer surface by edge collapse within " +
                       formatDefault(kDefaultLayerToleranceVoxels) +
                       " x voxel\nof the full-resolution surface, no edge longer than " +
                       formatDefault(kDefaultLayerMaxEdgeVoxels) +
                       " x voxel\n(the rim on the part surface is kept as it is). " +
                       (simplifiedByDefault ? "The default." : "Default: off."));
  command
      .add_option("--layer-tolerance", args.layerTolerance,
                  "Simplify the layer surfaces (as --simplify-layers) within this\n"
                  "distance of the full-resolution surface, mm (> 0).")
      ->type_name("MM");
  command.add_flag("--full-resolution-layers", args.fullResolutionLayers,
                   "Keep the layer surfaces as marching tetrahedra give them (about\n"
                   "4-5 triangles per voxel crossed; no simplification)." +
                       std::string(simplifiedByDefault ? "" : " The default."));
}

namespace {

/// --method, --grid, --format: the enum choices, the default read from the options structs.
void addLayersMethodOptions(CLI::App& layers, LayersArguments& args) {
  layers
      .add_option("--method", args.method,
                  "Geodesic distance method: " +
                      describeChoices(
                          {{"anyangle",
                            "any-angle\npropagation with exact line-of-sight\ntests; also 'exact'"},
                           {"paper", "the paper's\nneighbourhood search, section 2.2"}},
                          toString(LayerJobOptions{}.geodesic.method)) +
                      ".")
      ->type_name("NAME");
  layers
      .add_option("--grid", args.grid,
                  "Voxel grid orientation: " +
                      describeChoices({{"pca", "principal axes of the\nmodel, paper section 2.1"},
                                       {"model", "the model's x, y, z axes"}},
                                      toString(LayerJobOptions{}.voxelize.alignment)) +
                      ".")
      ->type_name("NAME");
  layers
      .add_option(
          "--format", args.format,
          "Layer file format: " +
              describeChoices({{"ply", "binary little-endian\nPLY"}, {"obj", "Wavefront OBJ"}},
                              toString(LayerJobArguments{}.format)) +
              ".")
      ->type_name("NAME");
}

void addLayersOptions(CLI::App& layers, LayersArguments& args) {
  layers
      .add_option("MODEL", args.model,
                  "The part, in mm: a closed triangle mesh, STL (binary or ASCII) or\n"
                  "OBJ, or a CAD solid, STEP (.step/.stp), IGES (.iges/.igs) or BREP\n"
                  "(.brep/.brp), tessellated with --tessellation-tolerance.")
      ->required()
      ->type_name("FILE");
  layers
      .add_option("--start", args.start,
                  "Start surface the layers grow from (geodesic distance 0):\n"
                  "  plane:bottom  the build plate under the model: the plane\n"
                  "                z = lowest z of the model (default)\n"
                  "  plane:z=MM    the horizontal plane at height MM (mm, model\n"
                  "                coordinates)\n"
                  "  faces:IDS     faces of the model, a comma list with ranges, e.g.\n"
                  "                faces:0-9,15: for STL/OBJ 0-based triangle positions\n"
                  "                in the file; for a CAD model FreeCAD's face numbers\n"
                  "                (Face1 = 1, 1-based)\n"
                  "  mesh:FILE     a separate surface mesh (STL or OBJ, mm, model\n"
                  "                coordinates), e.g. a curved base plate")
      ->type_name("SPEC");
  layers
      .add_option("--layer-thickness", args.layerThickness,
                  "Layer thickness h in mm (> 0), required: layer i is the surface at\n"
                  "geodesic distance i*h from the start surface.")
      ->required()
      ->type_name("MM");
  layers
      .add_option("--voxel", args.voxelSize,
                  "Voxel edge length L in mm (> 0), required. Smaller is more\n"
                  "accurate; time and memory grow as 1/L^3.")
      ->required()
      ->type_name("MM");
  addLayersMethodOptions(layers, args);
  layers
      .add_option("--memory-budget", args.memoryBudgetMb,
                  "Memory the job may use, in MB (2^20 bytes); a voxel grid that\n"
                  "would not fit is refused before it is allocated.\n"
                  "Default 0 = 80 % of physical memory.")
      ->type_name("MB");
  addTessellationOption(layers, args);
  addLayerSimplificationOptions(layers, args);
  layers.add_flag("--cap-holes", args.capHoles,
                  "Close the holes of an open model before slicing (default: off;\n"
                  "an open model the voxelizer cannot resolve is an error). Holes\n"
                  "on the start surface are capped on it, e.g. where a part sits on\n"
                  "a curved base.");
  layers.add_flag("-q,--quiet", args.quiet,
                  "No progress and no summary; errors still go to stderr.\n"
                  "Default: progress on stderr, summary on stdout.");
  layers
      .add_option("-o,--output", args.output,
                  "Output folder (created if missing), required; see Output below.")
      ->required()
      ->type_name("DIR");
  layers.footer(kLayersFooter);
}

}  // namespace

void addLayersCommand(CLI::App& app, CommandList& commands) {
  auto args = std::make_shared<LayersArguments>();
  CLI::App* layers = app.add_subcommand(
      "layers", "Slice a solid into curved layers of equal thickness grown from a start surface.");
  addLayersOptions(*layers, *args);
  commands.push_back({layers, [args] { return runLayersCommand(*args); }});
}

}  // namespace curvedslicer::cli
