// JSON reading that hostile files cannot drive into unbounded recursion or endless messages: the
// nesting depth is checked by a flat scan before the document is built, every library error
// (syntax, number overflow such as 1e999, bad UTF-8) becomes an InvalidInput naming the file, the
// line and the column, and values echoed in messages are cut to a few dozen characters.
// Internal to the readers of plan.json and cell files (cpp/src/plan, cpp/src/robot).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace curvedslicer {

/// Deepest nesting of arrays and objects the readers accept (plan.json needs 5, a cell file 4).
inline constexpr int kMaxJsonDepth = 64;

/// Longest echo of a JSON value in an error message, in characters (before the "...").
inline constexpr std::size_t kMaxEchoedJson = 60;

/// Largest cell file the reader takes, bytes (16 MiB; a cell is a few kB with its bead model).
inline constexpr std::uintmax_t kMaxCellFileBytes = std::uintmax_t{16} << 20;

/// Largest plan.json the reader takes, bytes (4 GiB; a bunny at 0.5 mm is about 0.2 GB).
inline constexpr std::uintmax_t kMaxPlanFileBytes = std::uintmax_t{4} << 30;

/// The whole text of `path` for a JSON reader: only a regular file (a symbolic link to one is
/// followed) of at most `maxBytes`. What it is is checked before the file is opened, so a FIFO
/// (whose opening would block), a device (/dev/zero, endless), a socket or a folder is refused
/// without reading; so is a larger file. `what` names the file in messages ("cell file").
/// @throws IoError naming the path when it does not exist or cannot be opened or read
/// @throws InvalidInput naming the path, what it is or its size, and what to pass instead
std::string readInputFile(const std::filesystem::path& path, std::string_view what,
                          std::uintmax_t maxBytes);

/// Parses `text` (UTF-8 JSON) into a document.
/// Throws InvalidInput "<lead>: <problem> at line L, column C; <hint>" when the text is not JSON,
/// nests deeper than `maxDepth`, or holds a number beyond the double range. Uses no recursion
/// proportional to the input and O(size of text) memory.
nlohmann::json parseBoundedJson(std::string_view text, std::string_view lead, std::string_view hint,
                                int maxDepth = kMaxJsonDepth);

/// The compact JSON text of `value`, cut after `maxChars` characters with "..." appended;
/// never throws (invalid UTF-8 is replaced), and visits only about `maxChars` elements.
std::string abbreviateJson(const nlohmann::json& value, std::size_t maxChars = kMaxEchoedJson);

}  // namespace curvedslicer
