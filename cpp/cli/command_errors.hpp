// How the command-line commands end on an error: the exception a command's work throws is mapped
// to its exit code (layers_command.hpp, ExitCode) and printed as one "curvedslicer: error: ..."
// line after the progress line is closed. An interrupt (SIGINT/SIGTERM, which makes the core throw
// Cancelled) exits with 128 + the signal number and says that nothing was written.
// Shared by `layers`, `plan` and `export`, so the same failure gives the same code everywhere.
#pragma once

#include <string>
#include <vector>

#include "terminal_progress.hpp"

namespace curvedslicer::cli {

/// The out-of-memory message of the jobs that build a voxel grid (`layers`, `plan`).
inline const std::string kJobOutOfMemoryMessage =
    "out of memory: the job needs more memory than is available; use a larger voxel size "
    "(--voxel) or set --memory-budget to what the machine can spare";

/// Ends the progress line, prints "curvedslicer: error: <message>" on stderr, returns `code`.
int reportFailure(TerminalProgress& display, int code, const std::string& message);

/// Prints each of the job's warnings as "curvedslicer: warning: <warning>" on stderr (also with
/// --quiet: they say where the part may differ from the model).
void printWarnings(const std::vector<std::string>& warnings);

/// Call only inside a `catch (...)` block: maps the exception being handled to its exit code and
/// message — Cancelled (interrupt → 128 + signal, "nothing was written to '<output>'"),
/// InvalidInput → 2, IoError and filesystem errors → 3, ResourceLimit → 4, NumericalFailure → 5,
/// std::bad_alloc → 4 with `outOfMemoryMessage`, anything else → 1.
/// @param output  the output file or folder the command was writing, for the interrupt message
int failWithCurrentException(TerminalProgress& display, const std::string& output,
                             const std::string& outOfMemoryMessage);

}  // namespace curvedslicer::cli
