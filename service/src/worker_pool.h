#pragma once
// The threads that run plans: a fixed pool fed by a bounded queue.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace hfts::service {

/// Raised to stop a job (planGrasp polls it).
using CancelFlag = std::shared_ptr<std::atomic<bool>>;

/// `threads` workers take jobs in order from a queue of at most
/// `queueCapacity` waiting jobs. Every job carries a cancel flag, so that
/// cancelAll() can stop the queued and running ones (graceful shutdown).
/// Thread-safe.
class WorkerPool {
 public:
  /// Throws std::invalid_argument unless threads >= 1.
  WorkerPool(int threads, std::size_t queueCapacity);
  /// Runs the jobs still queued, then joins the threads.
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Queues `job`; false (and nothing queued) when the queue is full. A
  /// job must not throw.
  bool trySubmit(CancelFlag cancel, std::function<void()> job);
  /// Raises the flag of every queued and running job.
  void cancelAll();

  int threads() const { return static_cast<int>(threads_.size()); }
  std::size_t capacity() const { return capacity_; }
  std::size_t queued() const;
  std::size_t running() const;
  /// No job queued or running.
  bool idle() const;

 private:
  struct Job {
    CancelFlag cancel;
    std::function<void()> run;
  };
  void work();

  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> queue_;
  std::vector<CancelFlag> running_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace hfts::service
