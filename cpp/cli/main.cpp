// The `curvedslicer` command line. Every subcommand registers itself in commands.hpp:
//   curvedslicer layers MODEL --layer-thickness MM --voxel MM -o DIR [options]
//   curvedslicer cell check CELL.json
//   curvedslicer --version
// See `curvedslicer <command> --help` and README.md.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "layers_command.hpp"

int main(int argc, char** argv) {
  using namespace curvedslicer::cli;
  CLI::App app{
      "curvedslicer: equal-thickness curved layers for wire-arc additive manufacturing, from "
      "geodesic distances in a voxelized solid."};
  app.set_version_flag("--version", std::string("curvedslicer ") + CURVEDSLICER_VERSION);
  app.require_subcommand(1);
  CommandList commands;
  addAllCommands(app, commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string command = "curvedslicer";
    for (const auto& [sub, run] : commands) {
      if (sub->parsed()) command += " " + sub->get_name();
    }
    std::fprintf(stderr, "curvedslicer: error: %s; run '%s --help' for the options\n", e.what(),
                 command.c_str());
    return kExitInvalidInput;
  }
  for (const auto& [sub, run] : commands) {
    if (sub->parsed()) return run();
  }
  return kExitInvalidInput;
}
