// Progress reporting and cancellation through one callback.
//
// The callback receives the overall fraction in [0, 1] (never decreasing) and the name of the
// current stage; returning false requests cancellation, which the core turns into a `Cancelled`
// exception at the next check. The callback is only invoked on the calling thread (never from a
// worker thread), so worker loops call `Progress::report` only outside parallel regions.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace curvedslicer {

/// @return false to cancel.
using ProgressCallback = std::function<bool(double fraction, std::string_view stage)>;

/// A view onto a sub-range [begin, end] of the overall progress. Cheap to copy; copies share the
/// monotonic "last reported" state so fractions never go backwards.
class Progress {
 public:
  Progress() = default;
  explicit Progress(ProgressCallback callback);

  /// Reports `fraction` (0..1, of this scope) with the stage name; throws `Cancelled` if the
  /// callback returns false. A no-op without a callback.
  void report(double fraction, std::string_view stage) const;

  /// Throws `Cancelled` if cancellation was requested earlier or the callback asks now
  /// (reports the scope's current position again).
  void check() const;

  /// A child scope covering [begin, end] (fractions of this scope).
  Progress sub(double begin, double end) const;

  bool active() const { return static_cast<bool>(state_); }

 private:
  struct State {
    ProgressCallback callback;
    double last = 0.0;
    std::string lastStage;
  };
  std::shared_ptr<State> state_;
  double begin_ = 0.0;
  double end_ = 1.0;
};

}  // namespace curvedslicer
