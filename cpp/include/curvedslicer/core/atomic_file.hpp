// Writing output files so that a reader never sees a half-written file: data goes to a temporary
// file in the same folder, which is renamed over the target only after a successful close.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <string_view>

namespace curvedslicer {

/// The path a finished output file is renamed onto in place of `path`: `path` itself when nothing
/// is there or a regular file is; the regular file a symbolic link resolves to when `path` is such
/// a link (the link stays, its target is replaced). Never a device, FIFO, socket or folder.
/// @throws InvalidInput for an empty path or one that names no file ("out/").
/// @throws IoError naming the path for anything else (a device, FIFO, socket, folder, a link to
///         one of those or a dangling link). The check precedes the rename by a moment: it guards
///         against mistakes, not against a concurrent process swapping the path.
std::filesystem::path resolveOutputPath(const std::filesystem::path& path);

/// The temporary file a new version of the output `path` (already resolved) is written to before
/// it is renamed over it: "NAME.tmp-PID-N" beside it, NAME cut so the whole stays within the file
/// system's name limit. Also removes the temporaries of `path` that killed runs left (their
/// process no longer exists).
/// @throws InvalidInput when the output's own name is longer than the file system allows.
std::filesystem::path prepareTemporaryFor(const std::filesystem::path& path);

/// Writes `path` atomically (onto `resolveOutputPath(path)`): `write` fills the stream of a
/// temporary sibling file, which then replaces `path`. On any exception (from `write` or the file
/// system) the temporary file is removed, `path` is left as it was, and the exception propagates
/// (file-system errors as `IoError` naming the path).
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write, bool binary = false);

/// Convenience: atomically writes a string.
void writeTextFileAtomically(const std::filesystem::path& path, std::string_view text);

/// Creates `dir` (and parents) if missing; throws IoError naming the folder if that fails or
/// if it exists as a non-folder.
void ensureDirectory(const std::filesystem::path& dir);

}  // namespace curvedslicer
