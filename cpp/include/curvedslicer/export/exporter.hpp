// Robot programs and neutral files from a motion plan (robot/motion.hpp): one writer per format
// behind a common interface, and an all-or-nothing writer for the resulting files.
//
// Formats (each in its own header/source pair under export/, details there):
//   jbi    Yaskawa Motoman INFORM job(s), station ST1 with EC positions, SMOVL … +MOVJ EC,
//          ARCON/ARCOF, sub-jobs at the cell's line limit called from a main job (jbi_writer.hpp)
//   krl    KUKA KRL .src + .dat pairs with E1/E2, split at the cell's line limit, arc by the
//          cell's output and arc-established input (krl_writer.hpp)
//   rapid  ABB RAPID modules with declared tooldata/wobjdata, extax, split into modules called
//          from main, arc by the cell's signals (rapid_writer.hpp)
//   ls     Fanuc TP .LS with GP1/GP2, COORD, /APPL ARC, programs at the cell's line limit
//          called from a main program (ls_writer.hpp)
//   gcode  G-code for a tilt-rotate table, TCP or machine mode (inverse-time feed), dialects
//          generic and linuxcnc (gcode_writer.hpp)
//   csv, json  every motion point with all its data (neutral_writer.hpp)
// Every writer is a pure function of (MotionPlan, Cell, ExportOptions): the same inputs give
// byte-identical files (no clock, no locale; the date written into headers is an option).
// Every writer writes every motion point (MotionPoint::kind): welds, the arc-off retract, travel
// and approach moves as linear moves at their speed, moves to the home pose as joint moves; the
// arc goes on after a path's first point and off after its last. Robot configuration bits / turn
// numbers are the weld's (MotionPathSpan::configuration) on every point of a weld and the
// point's own (configurationOf) at arc-off points, so they never change between arc on and off.
//
// Preconditions: the motion plan was made for the same cell (planMotion). Cost: O(points),
// about 100–300 bytes of text per point.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/core/progress.hpp"
#include "curvedslicer/robot/cell.hpp"
#include "curvedslicer/robot/motion.hpp"

namespace curvedslicer {

enum class ExportFormat { Jbi, Krl, Rapid, Ls, Gcode, Csv, Json };

/// G-code coordinates (gcode_writer.hpp).
enum class GcodeMode {
  Tcp,      ///< part-frame X Y Z plus table angles A C; the controller does the kinematics
  Machine,  ///< X Y Z already transformed by the table's forward kinematics (positioner base)
};

/// G-code controller conventions (gcode_writer.hpp).
enum class GcodeDialect {
  Generic,   ///< ISO / Fanuc-style 5-axis tilt-rotate table: G4 P in ms, TCP G43.4, end M30
  LinuxCnc,  ///< LinuxCNC (xyzac-trt): G4 P in seconds, TCP by switchkins M429/M428, end M2
};

struct ExportOptions {
  /// Program / job name; empty = the cell's exportOptions.jobName. Each format cuts it to its
  /// character set and length (JBI: the cell's maxNameLength).
  std::string programName;
  /// Date written into program headers (JBI ///DATE), "YYYY/MM/DD HH:MM". Fixed by default so a
  /// saved plan re-exports byte-identical programs.
  std::string date = "2000/01/01 00:00";
  GcodeMode gcodeMode = GcodeMode::Tcp;               ///< G-code only
  GcodeDialect gcodeDialect = GcodeDialect::Generic;  ///< G-code only
  /// G-code only: lines per sub-program file (about 60 bytes each; 0 or >= 10) when the program
  /// is split into sub-programs called from the main file; 0 = never split.
  int gcodeMaxLinesPerFile = 40000;
  /// Not used by the writers any more: KRL and RAPID take the arc output from the cell's
  /// "controller" section (krl/arc_on_output, rapid/arc_signal); kept for the bindings.
  int arcOutput = 1;
};

/// One output file.
struct ExportFile {
  std::string name;       ///< plain file name (no folder); the first file is the main program
  std::string text;       ///< complete contents
  std::size_t lines = 0;  ///< number of lines
};

struct ExportResult {
  ExportFormat format = ExportFormat::Jbi;
  std::vector<ExportFile> files;  ///< files[0] is the main program (or the only file)
  std::size_t motionCount = 0;    ///< motion instructions / rows written
  std::size_t arcCount = 0;       ///< arc-on segments (paths) written
  std::vector<std::string> warnings;
  std::size_t totalBytes() const {
    std::size_t n = 0;
    for (const auto& f : files) n += f.text.size();
    return n;
  }
};

/// A program writer for one format.
class ProgramExporter {
 public:
  virtual ~ProgramExporter() = default;
  virtual ExportFormat format() const = 0;
  /// Writes the program(s) into memory.
  /// @param motion  the motion plan (planMotion) for `cell`; at least one point
  /// @param progress  progress and cancel ("export" stage)
  /// @throws InvalidInput for an empty plan, a point beyond a joint limit of the cell (which
  ///         point, which joint, by how much), a cell the format cannot express; Cancelled.
  virtual ExportResult write(const MotionPlan& motion, const Cell& cell,
                             const ExportOptions& options, const Progress& progress) const = 0;
};

/// One program format: its name (as the command line and the workbench take it), the extension
/// of its main file and what it is for.
struct ExportFormatInfo {
  ExportFormat format = ExportFormat::Jbi;
  std::string_view name;         ///< "jbi"
  std::string_view extension;    ///< ".JBI"
  std::string_view description;  ///< "Yaskawa INFORM"
};

/// Every program format, in the order front ends list them: the one table that format names,
/// file extensions, the command line's help and the workbench's choices come from.
const std::vector<ExportFormatInfo>& exportFormats();

/// "jbi", "krl", "rapid", "ls", "gcode", "csv", "json" (exportFormats()).
std::string_view toString(ExportFormat format);

/// Parses a format name (case-insensitive). @throws InvalidInput listing the valid names
/// (exportFormats()).
ExportFormat parseExportFormat(std::string_view name);

/// "tcp" | "machine".
std::string_view toString(GcodeMode mode);

/// Parses a G-code mode name ("tcp" or "machine"). @throws InvalidInput listing the choices.
GcodeMode parseGcodeMode(std::string_view name);

/// "generic" | "linuxcnc".
std::string_view toString(GcodeDialect dialect);

/// Parses a G-code dialect name ("generic" or "linuxcnc"). @throws InvalidInput listing them.
GcodeDialect parseGcodeDialect(std::string_view name);

/// The usual file extension of the main file, with the dot (".JBI", ".src", ".mod", ".LS",
/// ".ngc", ".csv", ".json"; exportFormats()).
std::string_view fileExtension(ExportFormat format);

/// The writer of `format`.
std::unique_ptr<ProgramExporter> makeExporter(ExportFormat format);

/// Program text per motion point, bytes: the upper end of the writers' 100–300 (file comment).
inline constexpr double kExportTextBytesPerPoint = 300.0;

/// Refuses, before the motion is planned, an export whose motion points (sizeof(MotionPoint))
/// and program text (kExportTextBytesPerPoint) for `points` plan points would not fit the budget.
/// @param memoryBudgetBytes  bytes; 0 = 80 % of physical memory
/// @throws ResourceLimit naming the points, the memory and the budget.
void checkExportSize(std::size_t points, double memoryBudgetBytes = 0.0);

/// Checks the options every writer relies on: the date must be "YYYY/MM/DD HH:MM" (digits where
/// the pattern has them), so no header line can be broken or injected through it.
/// @throws InvalidInput quoting the value (control characters escaped, long values cut).
void validateExportOptions(const ExportOptions& options);

/// validateExportOptions(options), then makeExporter(format)->write(…).
ExportResult exportProgram(const MotionPlan& motion, const Cell& cell, ExportFormat format,
                           const ExportOptions& options = {}, const Progress& progress = {});

/// Checks every point of `motion` against the cell's joint limits (robot joints, the robot's
/// interference limits and positioner axes, with 1e-9 rad slack); the robot and positioner must
/// never be asked to cross a limit.
/// @throws InvalidInput naming the first offending point (layer, path, point), the joint, its
///         angle and the limit in degrees, and how far beyond it is.
void checkJointLimits(const MotionPlan& motion, const Cell& cell);

/// The file-name rule: a program's main file and the name inside it agree. The program name of an
/// export to `mainFile` is `requested` when not empty, else the file's stem ("out/CYL.JBI" →
/// "CYL"); each format then cuts it to its rules (character set, case, length).
std::string programNameForFile(const std::filesystem::path& mainFile, std::string_view requested);

/// Checks the file-name rule on a written export: the stem of `mainFile` must equal the stem of
/// files[0].name, the name the writer gave the main program, up to letter case (controller file
/// systems ignore case); the extension is free. CSV and JSON carry no internal name and pass.
/// @throws InvalidInput naming both and the file name to use (e.g. `--name CYLINDER_PART -o
///         CYL.JBI`: the JBI job is CYLINDER, so "name the file CYLINDER.JBI").
void checkMainFileName(const ExportResult& result, const std::filesystem::path& mainFile);

/// Writes the files all or nothing: `mainFile` receives files[0].text, every further file goes
/// next to it under its own name. Each file is written to a temporary sibling first; only when
/// all are complete are they renamed into place. On any error no target file is changed and the
/// temporaries are removed. Checks the file-name rule first (checkMainFileName).
/// @throws IoError naming the file; InvalidInput if a further file's name equals the main file's
///         or the main file's name disagrees with the program's.
void writeExportFiles(const ExportResult& result, const std::filesystem::path& mainFile);

}  // namespace curvedslicer
