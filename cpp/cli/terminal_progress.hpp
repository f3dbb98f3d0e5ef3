// Progress display of the command line on stderr, and SIGINT/SIGTERM/SIGHUP handling.
//
// On a terminal one line is redrawn with carriage returns (at most ten times a second); otherwise
// a plain line is printed when the stage changes and at most every two seconds within a stage.
// An interrupt signal makes the progress callback return false, so the core stops at its next
// progress check with `Cancelled` and no output is written; a second signal kills the process.
#pragma once

#include <chrono>
#include <csignal>
#include <cstdio>
#include <string>
#include <string_view>

namespace curvedslicer::cli {

/// Installs the SIGINT, SIGTERM and SIGHUP handlers (one-shot: the second signal has its default
/// effect).
void installInterruptHandlers();

/// The signal received so far (0 if none).
int interruptSignal();

class TerminalProgress {
 public:
  /// @param enabled  false: print nothing (--quiet); interrupts still cancel
  explicit TerminalProgress(bool enabled, std::FILE* out = stderr);

  /// The progress callback: prints when due; returns false once an interrupt arrived.
  bool update(double fraction, std::string_view stage);

  /// Ends a carriage-return line with a newline (call before printing anything else).
  void finishLine();

 private:
  using Clock = std::chrono::steady_clock;
  void print(int percent, std::string_view stage);

  bool enabled_;
  bool tty_;
  std::FILE* out_;
  std::string stage_;
  int percent_ = -1;
  Clock::time_point last_{};
  std::size_t lineLength_ = 0;  ///< characters of the current carriage-return line
};

}  // namespace curvedslicer::cli
