// Options of `curvedslicer export` (see export_command.hpp for what the command does).
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "curvedslicer/export/exporter.hpp"
#include "export_command.hpp"

namespace curvedslicer::cli {

namespace {

constexpr const char* kExportFooter = R"(
Example:
  curvedslicer export out/part/plan.json --format jbi -o out/part/WAAM.JBI
  curvedslicer export plan.json --cell resources/cells/motoman_hp20d_tilt_rotate.json \
      --format krl -o part.src

Output:
  jbi    Yaskawa INFORM job; when the program exceeds the cell's max_lines_per_job it is split
         into sub-jobs: FILE holds the main job (NOP, CALL JOB:<NAME><k> ..., END) and the
         sub-jobs are written next to it as <NAME><k>.JBI. Load all files onto the controller.
  ls     Fanuc .LS (ArcTool); split at the cell's controller/ls max_lines_per_program into
         <NAME><k>.LS called from the main program in FILE.
  krl    KUKA .src; rapid: ABB .mod; gcode: tilt-rotate table G-code (--gcode-mode,
         --gcode-dialect);
  csv, json  every motion point (layer, path, xyz, normal, V, a1, a2, joints, speed, arc,
         wire feed, weld schedule, bead width).
Names: the program is named after FILE (its name without extension) unless --name is given;
each format cuts the name to its rules (JBI: upper case, the cell's max_name_length). The
main file and the program inside it must agree: `--name CYLINDER_PART -o CYL.JBI` is refused
(the job would be CYLINDER) with the file name to use; letter case may differ.
All files appear together, or none on any error (each is written to a temporary file first).
Files of an earlier run with other sub-job names are not removed.

Summary: the part's placement on the table (table_to_part), notes (e.g. defaults taken for an
older cell file), where the weld speed drops below the cell's (and which axis limits it) and,
with --allow-collisions, the remaining collisions.

Cells: resources/cells/ has one per vendor (yaskawa, kuka, abb, fanuc); a cell's language is
jbi, krl, rapid or ls (gcode, csv and json fit every cell).

Exit codes: 0 success, 2 invalid input (bad plan or cell, unreachable point, joint limit,
part below the table or outside the working volume, collision, another vendor's language
without --allow-foreign-cell; including usage errors),
3 file I/O error, 130 interrupted (Ctrl-C), 1 other.)";

/// "Output format, required: jbi (Yaskawa INFORM), krl (KUKA KRL), ..." from exportFormats(),
/// wrapped to the help's width.
std::string formatHelp() {
  std::string help = "Output format, required:";
  std::size_t line = help.size();
  const auto& formats = exportFormats();
  for (std::size_t i = 0; i < formats.size(); ++i) {
    const std::string item = " " + std::string(formats[i].name) + " (" +
                             std::string(formats[i].description) +
                             (i + 1 < formats.size() ? ")," : ").");
    if (line + item.size() > 66) {
      help += "\n";
      line = 0;
    }
    help += line == 0 ? item.substr(1) : item;
    line += line == 0 ? item.size() - 1 : item.size();
  }
  return help;
}

/// The motion planner's options: one line each (see docs/ADDING-AN-OPTION.md).
void addMotionOptions(CLI::App& cmd, OptionBindings<MotionOptions>& b) {
  b.addLength(cmd, "--clearance", &MotionOptions::clearance, "clearance",
              "Arc-off moves leave back up the torch's axis to this height above\n"
              "the part and everything deposited so far, travel there and approach\n"
              "down the torch's axis, mm");
  b.addFlag(cmd, "--allow-collisions", &MotionOptions::allowCollisions, true,
            "Write the program although torch or positioner still collide with the\n"
            "part or the deposit after re-routing: each collision becomes a warning\n"
            "naming the move (default: stop with an error naming it).");
  b.addFlag(cmd, "--no-home", &MotionOptions::addHome, false,
            "Do not start and end the program at the cell's home pose (default:\n"
            "the cell's `home`).");
  b.addLength(cmd, "--merge-tolerance", &MotionOptions::mergeTolerance, "merge tolerance",
              "Consecutive path points closer than this are merged into one,\n"
              "mm");
  b.addAngleInRadians(cmd, "--max-a2-step", &MotionOptions::maxA2Step, "maximum a2 step",
                      "Largest turn of the positioner's rotation a2 between consecutive\n"
                      "points of a weld; points are inserted where it turns faster,\n"
                      "degrees");
  b.add(cmd, "--placement",
        "Where the part sits on the table:\n"
        "  rest  the cell's table_to_part rotation and xy, moved along the\n"
        "        table z so the lowest bead bottom (a bead: one layer thickness\n"
        "        below its weld point along the layer normal, half a bead\n"
        "        spacing to each side) lies on the fixture's top (the cell's\n"
        "        positioner/fixture: riser and substrate plate), else the table's\n"
        "  cell  the cell's positioner/table_to_part as given\n"
        "  auto  rest, on the lowest riser that keeps the torch clear of the\n"
        "        table on every move (the cell's riser diameter, else the\n"
        "        plate's side, else the first layer's footprint); says the\n"
        "        height it chose\n"
        "Default " +
            formatDefault(toString(MotionOptions{}.placement)) +
            ". A weld point below the fixture's top or outside the\n"
            "positioner's working volume stops the export (exit code 2).",
        "MODE",
        [](std::string_view text, MotionOptions& o) { o.placement = parsePartPlacement(text); });
}

void addExportOptions(CLI::App& cmd, ExportArguments& args) {
  cmd.add_option("PLAN", args.plan, "The plan: plan.json written by `curvedslicer plan`.")
      ->required()
      ->type_name("FILE");
  cmd.add_option("--cell", args.cell,
                 "Cell description (JSON: robot, tool, positioner, process, export\n"
                 "options; see resources/cells/). Default: the paper's cell, a Yaskawa\n"
                 "Motoman HP20D with a two-axis tilt-rotate positioner.")
      ->type_name("FILE");
  cmd.add_option("--format", args.format, formatHelp())->required()->type_name("NAME");
  cmd.add_option("-o,--output", args.output,
                 "Output file, required (its folder must exist). For a split JBI\n"
                 "program the sub-jobs go next to it; see Output below.")
      ->required()
      ->type_name("FILE");
  cmd.add_option("--name", args.name,
                 "Program / job name (default: the output file's name without\n"
                 "extension); cut to the controller's character set and length. The\n"
                 "output file must carry the name the program gets (see Output).")
      ->type_name("NAME");
  cmd.add_option("--gcode-mode", args.gcodeMode,
                 "G-code coordinates: tcp (default; part X Y Z + A C, the controller's\n"
                 "TCP control on) or machine (X Y Z through the table kinematics,\n"
                 "inverse-time feed G93 keeping the weld speed relative to the part).")
      ->type_name("MODE");
  cmd.add_option("--gcode-dialect", args.gcodeDialect,
                 "G-code controller: generic (default; ISO/Fanuc-style 5-axis table:\n"
                 "G4 P in ms, TCP G43.4/G49, M30) or linuxcnc (G4 P in seconds, TCP by\n"
                 "switchkins M429/M428, M2).")
      ->type_name("NAME");
  cmd.add_option("--gcode-lines-per-file", args.gcodeLinesPerFile,
                 "G-code lines per file before the program is split into sub-programs\n"
                 "called from FILE (linuxcnc o<name_k> call, generic M98 P<n>); 0 =\n"
                 "never. Default " +
                     std::to_string(ExportOptions{}.gcodeMaxLinesPerFile) + ".")
      ->check(CLI::NonNegativeNumber)
      ->type_name("N");
  cmd.add_option("--date", args.date,
                 "Date written into program headers, \"YYYY/MM/DD HH:MM\". Default: a\n"
                 "fixed date (2000/01/01 00:00), so the same plan gives identical files.")
      ->type_name("DATE");
  cmd.add_flag("--allow-foreign-cell", args.allowForeignCell,
               "Write a vendor's program language for another vendor's cell (jbi:\n"
               "yaskawa, krl: kuka, rapid: abb, ls: fanuc; the cell's \"vendor\"). Default:\n"
               "stop with exit code 2 naming the cell's vendor and the format.");
  cmd.add_flag("--allow-unreachable", args.warnUnreachable,
               "Do not stop at points the robot cannot reach: keep the closest pose and\n"
               "warn (default: stop with an error naming the points). A point beyond a\n"
               "joint limit is still refused by every exporter.");
  addMotionOptions(cmd, args.motion);
  cmd.add_flag("-q,--quiet", args.quiet, "No progress and no summary; errors still go to stderr.");
  cmd.footer(kExportFooter);
}

}  // namespace

void addExportCommand(CLI::App& app, CommandList& commands) {
  auto args = std::make_shared<ExportArguments>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Write a robot program (JBI, KRL, RAPID, LS, G-code) or a neutral CSV/JSON from a plan.");
  addExportOptions(*cmd, *args);
  commands.push_back({cmd, [args] { return runExportCommand(*args); }});
}

}  // namespace curvedslicer::cli
