#include "terminal_progress.hpp"

#include <algorithm>
#include <cmath>

#include <unistd.h>

namespace curvedslicer::cli {

namespace {

volatile std::sig_atomic_t gInterruptSignal = 0;

extern "C" void onInterrupt(int signal) {
  gInterruptSignal = signal;
}

}  // namespace

void installInterruptHandlers() {
  struct sigaction action {};
  action.sa_handler = onInterrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;  // a second signal terminates at once
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // the terminal closing (SSH dropped, window closed) cancels as Ctrl+C does
  sigaction(SIGHUP, &action, nullptr);
}

int interruptSignal() {
  return static_cast<int>(gInterruptSignal);
}

TerminalProgress::TerminalProgress(bool enabled, std::FILE* out)
    : enabled_(enabled), tty_(::isatty(::fileno(out)) == 1), out_(out) {}

bool TerminalProgress::update(double fraction, std::string_view stage) {
  if (enabled_) {
    const int percent = static_cast<int>(std::floor(std::clamp(fraction, 0.0, 1.0) * 100.0));
    const auto now = Clock::now();
    const bool newStage = stage != stage_;
    const auto interval = tty_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(2000);
    const bool due = now - last_ >= interval || (tty_ && percent == 100);
    if (newStage || (percent != percent_ && due)) {
      stage_.assign(stage);
      percent_ = percent;
      last_ = now;
      print(percent, stage);
    }
  }
  return interruptSignal() == 0;
}

void TerminalProgress::print(int percent, std::string_view stage) {
  char head[32];
  std::snprintf(head, sizeof head, "[%3d%%] ", percent);
  std::string line = "curvedslicer: " + std::string(head) + std::string(stage);
  if (tty_) {
    const std::size_t length = line.size();
    if (length < lineLength_) line.append(lineLength_ - length, ' ');
    lineLength_ = length;
    std::fprintf(out_, "\r%s", line.c_str());
  } else {
    std::fprintf(out_, "%s\n", line.c_str());
  }
  std::fflush(out_);
}

void TerminalProgress::finishLine() {
  if (tty_ && lineLength_ > 0) {
    std::fputc('\n', out_);
    std::fflush(out_);
    lineLength_ = 0;
  }
}

}  // namespace curvedslicer::cli
