#pragma once
// The threads that run plans: a fixed pool fed by a bounded queue.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace hfts::service {

/// Raised to stop a job (planGrasp polls it).
using CancelFlag = std::shared_ptr<std::atomic<bool>>;

/// `threads` workers take jobs from a queue of at most `queueCapacity`
/// waiting jobs. Every job carries a cancel flag, so that cancelAll() can
/// stop the queued and running ones (graceful shutdown), and the client it
/// is for: a free worker takes the first queued job of the client with the
/// fewest jobs running, of those the client served longest ago (a client
/// not served yet counts from the arrival of its first queued job). So
/// clients with the same number of jobs running take turns, a client whose
/// one job waits behind another's many goes next, and no job waits for
/// ever: a newcomer never goes before a client that waited longer.
/// Thread-safe.
class WorkerPool {
 public:
  /// Throws std::invalid_argument unless threads >= 1.
  WorkerPool(int threads, std::size_t queueCapacity);
  /// Runs the jobs still queued, then joins the threads.
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Queues `job` for `client`; false (and nothing queued) when the queue
  /// is full. A job must not throw.
  bool trySubmit(CancelFlag cancel, std::function<void()> job, std::string client = {});
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
    std::string client;
  };
  /// What the pool knows of a client with jobs queued or running.
  struct Client {
    std::size_t queued = 0, running = 0;
    std::uint64_t served = 0;  // when its last job started, or its first arrived
  };
  void work();
  /// The queued job a free worker takes next (queue_ not empty).
  std::deque<Job>::iterator next();

  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> queue_;
  std::vector<CancelFlag> running_;
  std::map<std::string, Client> clients_;
  std::uint64_t events_ = 0;  // the clock of Client::served: arrivals and starts
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace hfts::service
