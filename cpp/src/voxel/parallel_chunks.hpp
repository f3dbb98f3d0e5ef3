// Internal helpers of the voxel stage: OpenMP loops that report progress between chunks.
//
// The progress callback may only run on the calling thread, so a loop over `count` items is split
// into chunks (fewer for small jobs, so tiny grids do not pay for many parallel regions); each
// chunk is one OpenMP parallel loop (dynamic schedule), and progress is reported (which may throw
// Cancelled) between chunks. Exceptions thrown by the body inside the parallel region are captured
// and the first one is rethrown after the region.
#pragma once

#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <mutex>
#include <string_view>

#include "curvedslicer/core/progress.hpp"

namespace curvedslicer::voxel_internal {

/// Collects the first exception thrown inside an OpenMP region, to rethrow after it.
class ParallelErrors {
 public:
  template <class F>
  void run(F&& body) noexcept {
    try {
      body();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }
  void rethrowIfAny() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex mutex_;
  std::exception_ptr error_;
};

/// Number of chunks for a job touching `cells` grid cells: one per ~4 M cells, 1 to 32.
inline int chunksForCells(double cells) {
  return static_cast<int>(std::clamp(cells / 4194304.0, 1.0, 32.0));
}

/// Runs body(item, thread) for items [0, count) in parallel, in `chunks` chunks; `thread` is in
/// [0, omp_get_max_threads()). Reports progress (fraction of items done) between chunks.
template <class Body>
void runChunked(int count, int chunks, const Progress& progress, std::string_view stage,
                Body&& body) {
  chunks = std::max(1, std::min(count, chunks));
  ParallelErrors errors;
  for (int c = 0; c < chunks; ++c) {
    const int begin = static_cast<int>(static_cast<std::int64_t>(count) * c / chunks);
    const int end = static_cast<int>(static_cast<std::int64_t>(count) * (c + 1) / chunks);
#pragma omp parallel for schedule(dynamic, 1)
    for (int item = begin; item < end; ++item) {
      errors.run([&] { body(item, omp_get_thread_num()); });
    }
    errors.rethrowIfAny();
    progress.report(static_cast<double>(c + 1) / chunks, stage);
  }
}

}  // namespace curvedslicer::voxel_internal
