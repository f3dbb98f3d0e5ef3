// Registry of the command line's subcommands. Each subcommand lives in its own
// <name>_command.cpp / <name>_options.cpp pair and adds itself to the app here; main.cpp parses
// and runs the one that was given.
#pragma once

#include <functional>
#include <utility>
#include <vector>

namespace CLI {
class App;
}

namespace curvedslicer::cli {

/// A registered subcommand and the function that runs it after parsing (returns the exit code).
using CommandList = std::vector<std::pair<CLI::App*, std::function<int()>>>;

void addLayersCommand(CLI::App& app, CommandList& commands);  // layers_options.cpp
void addPlanCommand(CLI::App& app, CommandList& commands);    // plan_options.cpp
void addExportCommand(CLI::App& app, CommandList& commands);  // export_options.cpp
void addCellCommand(CLI::App& app, CommandList& commands);    // cell_command.cpp

/// Registers every subcommand, in the order `--help` lists them.
inline void addAllCommands(CLI::App& app, CommandList& commands) {
  addLayersCommand(app, commands);
  addPlanCommand(app, commands);
  addExportCommand(app, commands);
  addCellCommand(app, commands);
}

}  // namespace curvedslicer::cli
