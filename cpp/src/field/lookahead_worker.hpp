// A helper thread that computes pure functions of queued tasks ahead of the thread that needs
// their results (the shadow phase of the any-angle field: line-of-sight tests of cells queued in
// Dijkstra order, computed while the cells wait in the queue).
//
// One producer (the owning thread) submits tasks into a ring; the worker computes them in order;
// the producer later asks for the result of a ticket and gets it if the worker has finished it
// and its slot has not been reused, else nothing (it then computes the task itself). Results are
// therefore the same whatever the timing, provided `work` is a pure function of the task.
// Cost: the worker spins (yielding) while the ring is empty; stop() or the destructor joins it.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>
#include <utility>
#include <vector>

namespace curvedslicer::detail {

template <class Task, class Result, class Work>
class LookaheadWorker {
 public:
  /// Ticket of a task that was not submitted (the ring was full).
  static constexpr std::uint32_t kNoTicket = UINT32_MAX;

  /// @param capacityLog2  the ring holds 2^capacityLog2 tasks
  /// @param work          work(const Task&, Result&, ticket), pure; runs on the worker thread
  ///                      only (it may leave a result invalid for a task it knows is not needed)
  LookaheadWorker(int capacityLog2, Work work)
      : mask_((std::uint64_t{1} << capacityLog2) - 1),
        tasks_(mask_ + 1),
        results_(mask_ + 1),
        work_(std::move(work)),
        thread_([this] { serve(); }) {}

  LookaheadWorker(const LookaheadWorker&) = delete;
  LookaheadWorker& operator=(const LookaheadWorker&) = delete;
  ~LookaheadWorker() { stop(); }

  /// Owner thread: the ticket the next submit returns unless the ring is full.
  std::uint32_t nextTicket() const {
    return static_cast<std::uint32_t>(produced_.load(std::memory_order_relaxed));
  }

  /// Owner thread: queues a task; returns its ticket (the low 32 bits of its sequence number),
  /// or kNoTicket when the worker is a whole ring behind.
  std::uint32_t submit(const Task& task) {
    if (produced_ - done_.load(std::memory_order_acquire) > mask_) return kNoTicket;
    tasks_[produced_ & mask_] = task;
    const auto ticket = static_cast<std::uint32_t>(produced_);
    produced_.fetch_add(1, std::memory_order_release);
    return ticket == kNoTicket ? kNoTicket : ticket;
  }

  /// Owner thread: the result of `ticket` if the worker has computed it and its slot still holds
  /// it, else nullptr. The pointer is valid until the next submit.
  const Result* find(std::uint32_t ticket) const {
    if (ticket == kNoTicket) return nullptr;
    const std::uint64_t produced = produced_.load(std::memory_order_relaxed);
    // The full sequence number: the newest one with these low 32 bits.
    const std::uint64_t seq = produced - static_cast<std::uint32_t>(produced - 1 - ticket) - 1;
    if (produced - seq > mask_ + 1) return nullptr;  // its slot holds a newer task
    if (seq >= done_.load(std::memory_order_acquire)) return nullptr;  // not computed yet
    return &results_[seq & mask_];
  }

  /// Owner thread: ends the worker (idempotent).
  void stop() {
    if (!thread_.joinable()) return;
    stop_.store(true, std::memory_order_release);
    thread_.join();
  }

 private:
  void serve() {
    std::uint64_t next = 0;
    while (true) {
      if (next < produced_.load(std::memory_order_acquire)) {
        work_(tasks_[next & mask_], results_[next & mask_], static_cast<std::uint32_t>(next));
        done_.store(++next, std::memory_order_release);
      } else if (stop_.load(std::memory_order_acquire)) {
        return;
      } else {
        std::this_thread::yield();
      }
    }
  }

  const std::uint64_t mask_;
  std::vector<Task> tasks_;
  std::vector<Result> results_;
  Work work_;
  std::atomic<std::uint64_t> produced_{0};  // written by the owner only
  std::atomic<std::uint64_t> done_{0};      // written by the worker only
  std::atomic<bool> stop_{false};
  std::thread thread_;  // last: started once the rest is set up
};

}  // namespace curvedslicer::detail
