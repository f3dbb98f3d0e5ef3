// The text layer every robot-program writer shares: locale-independent number formatting, a line
// buffer with a fixed line ending that counts its lines, splitting a long sequence into jobs at a
// line limit, and program/job names that respect a controller's character set and length limit.
//
// Method: numbers go through std::to_chars (shortest round trip or fixed decimals, correctly
// rounded, never locale dependent, never "-0.000"); lines are appended to one std::string.
// Preconditions: none beyond the per-function ones. Cost: linear in the text written.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "curvedslicer/robot/cell.hpp"  // LineEnding

namespace curvedslicer {

/// "\n" or "\r\n" (Yaskawa controllers need CRLF; the others accept LF).
std::string_view lineEndingText(LineEnding ending);

/// `value` with exactly `decimals` digits after the point (0 ≤ decimals ≤ 17), rounded to
/// nearest; a result that rounds to zero has no minus sign ("0.000", never "-0.000").
/// @throws InvalidInput if `value` is not finite (a program must never contain "nan" or "inf").
std::string formatFixed(double value, int decimals);

/// Appends formatFixed(value, decimals) to `out` without a temporary string.
void appendFixed(std::string& out, double value, int decimals);

/// Appends the decimal digits of `value` to `out`.
void appendInt(std::string& out, std::int64_t value);

/// A program being written: lines are appended with the chosen ending; the ending is also used
/// after the last line.
class ProgramText {
 public:
  explicit ProgramText(LineEnding ending = LineEnding::Lf) : ending_(lineEndingText(ending)) {}

  /// Appends one line (`text` must not contain a line break).
  void line(std::string_view text);

  /// The line being built: append to it, then call endLine(). Avoids temporaries in hot loops.
  std::string& buffer() { return text_; }
  void endLine();

  std::size_t lineCount() const { return lines_; }
  const std::string& str() const { return text_; }
  /// Moves the text out; the object is then empty.
  std::string take();

 private:
  std::string_view ending_;
  std::string text_;
  std::size_t lines_ = 0;
};

/// Half-open index range [begin, end).
struct IndexRange {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::size_t size() const { return end - begin; }
};

/// Splits the items 0 … costs.size()−1 (in order) into consecutive chunks whose summed cost stays
/// ≤ `limit`, preferring to cut where `breakAllowed[i]` is true (a cut before item i). A chunk ends
/// at the last preferred cut that fits; only where a run between preferred cuts alone exceeds the
/// limit is it cut elsewhere (as late as possible).
/// @param costs         cost of each item (e.g. program lines), each ≥ 0
/// @param breakAllowed  same size as costs; breakAllowed[0] is ignored
/// @param limit         maximal cost of a chunk
/// @throws InvalidInput if one item alone exceeds `limit` or the sizes differ.
std::vector<IndexRange> splitAtLimit(const std::vector<std::size_t>& costs,
                                     const std::vector<bool>& breakAllowed, std::size_t limit);

/// A controller program name: characters other than A–Z, a–z, 0–9 and '_' become '_', the first
/// character is a letter (an 'P' is prepended otherwise), optionally upper-cased, and the result
/// is at most `maxLength` characters (cut from the end).
/// @throws InvalidInput if maxLength < 1.
std::string makeProgramName(std::string_view base, std::size_t maxLength, bool upperCase);

/// The name of sub-job `index` (1-based) of `count` jobs made from `base`: base + a zero-padded
/// number as wide as `count`; `base` is shortened so the whole name fits into `maxLength`.
/// @throws InvalidInput if the number alone does not fit.
std::string makeSubJobName(std::string_view base, std::size_t index, std::size_t count,
                           std::size_t maxLength);

}  // namespace curvedslicer
