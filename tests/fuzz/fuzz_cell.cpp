// libFuzzer target: the cell reader (robot/cell) on arbitrary bytes. A cell it accepts must be
// written and read back without error.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/robot/cell.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  curvedslicer::Cell cell;
  try {
    cell = curvedslicer::parseCell(text, "fuzz.json");
  } catch (const curvedslicer::Error&) {
    return 0;
  }
  (void)curvedslicer::parseCell(curvedslicer::writeCellJson(cell), "rewritten");
  return 0;
}
