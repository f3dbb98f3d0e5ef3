#include "command_errors.hpp"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>

#include "curvedslicer/core/error.hpp"
#include "layers_command.hpp"

namespace curvedslicer::cli {

void printWarnings(const std::vector<std::string>& warnings) {
  for (const std::string& warning : warnings) {
    std::fprintf(stderr, "curvedslicer: warning: %s\n", warning.c_str());
  }
}

int reportFailure(TerminalProgress& display, int code, const std::string& message) {
  display.finishLine();
  std::fprintf(stderr, "curvedslicer: error: %s\n", message.c_str());
  return code;
}

int failWithCurrentException(TerminalProgress& display, const std::string& output,
                             const std::string& outOfMemoryMessage) {
  try {
    throw;
  } catch (const Cancelled& e) {
    if (interruptSignal() != 0) {
      display.finishLine();
      std::fprintf(stderr, "curvedslicer: interrupted; nothing was written to '%s'\n",
                   output.c_str());
      return kExitInterruptedBase + interruptSignal();
    }
    return reportFailure(display, kExitOther, e.what());
  } catch (const InvalidInput& e) {
    return reportFailure(display, kExitInvalidInput, e.what());
  } catch (const IoError& e) {
    return reportFailure(display, kExitIo, e.what());
  } catch (const ResourceLimit& e) {
    return reportFailure(display, kExitResourceLimit, e.what());
  } catch (const NumericalFailure& e) {
    return reportFailure(display, kExitNumericalFailure, e.what());
  } catch (const std::filesystem::filesystem_error& e) {
    return reportFailure(display, kExitIo, e.what());
  } catch (const std::bad_alloc&) {
    return reportFailure(display, kExitResourceLimit, outOfMemoryMessage);
  } catch (const std::exception& e) {
    return reportFailure(display, kExitOther, e.what());
  } catch (...) {
    return reportFailure(display, kExitOther, "unknown error; please report");
  }
}

}  // namespace curvedslicer::cli
