#include "curvedslicer/core/progress.hpp"

#include <algorithm>
#include <string>

#include "curvedslicer/core/error.hpp"

namespace curvedslicer {

Progress::Progress(ProgressCallback callback)
    : state_(callback ? std::make_shared<State>(State{std::move(callback), 0.0, {}}) : nullptr) {}

void Progress::report(double fraction, std::string_view stage) const {
  if (!state_) return;
  const double f = std::clamp(fraction, 0.0, 1.0);
  const double overall = std::max(state_->last, begin_ + (end_ - begin_) * f);
  state_->last = overall;
  state_->lastStage.assign(stage);
  if (!state_->callback(overall, stage)) {
    throw Cancelled("cancelled by the caller during stage '" + std::string(stage) +
                    "'; no result was produced");
  }
}

void Progress::check() const {
  if (!state_) return;
  if (!state_->callback(state_->last, state_->lastStage)) {
    throw Cancelled("cancelled by the caller during stage '" + state_->lastStage +
                    "'; no result was produced");
  }
}

Progress Progress::sub(double begin, double end) const {
  Progress child = *this;
  const double span = end_ - begin_;
  child.begin_ = begin_ + span * std::clamp(begin, 0.0, 1.0);
  child.end_ = begin_ + span * std::clamp(end, 0.0, 1.0);
  return child;
}

}  // namespace curvedslicer
