// libFuzzer target: the plan.json reader (plan_io) on arbitrary bytes. A plan it accepts must be
// written back and read again to the same text (the reader and the writer agree).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "curvedslicer/core/error.hpp"
#include "curvedslicer/plan/plan_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  curvedslicer::Plan plan;
  try {
    plan = curvedslicer::parsePlanJson(text, "fuzz.json");
  } catch (const curvedslicer::Error&) {
    return 0;
  }
  const std::string written = curvedslicer::formatPlanJson(plan);
  if (curvedslicer::formatPlanJson(curvedslicer::parsePlanJson(written, "rewritten")) != written) {
    std::abort();  // an accepted plan must round-trip byte-identically
  }
  return 0;
}
