// JSON reading that hostile files cannot drive into unbounded recursion or endless messages: the
// nesting depth is checked by a flat scan before the document is built, every library error
// (syntax, number overflow such as 1e999, bad UTF-8) becomes an InvalidInput naming the file, the
// line and the column, and values echoed in messages are cut to a few dozen characters.
// Internal to the readers of plan.json and cell files (cpp/src/plan, cpp/src/robot).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace curvedslicer {

/// Deepest nesting of arrays and objects the readers accept (plan.json needs 5, a cell file 4).
inline constexpr int kMaxJsonDepth = 64;

/// Longest echo of a JSON value in an error message, in characters (before the "...").
inline constexpr std::size_t kMaxEchoedJson = 60;

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
