#include "worker_pool.h"

#include <algorithm>
#include <stdexcept>

namespace hfts::service {

WorkerPool::WorkerPool(int threads, std::size_t queueCapacity) : capacity_(queueCapacity) {
  if (threads < 1) throw std::invalid_argument("workers: at least 1 thread expected");
  for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { work(); });
}

WorkerPool::~WorkerPool() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : threads_) t.join();
}

bool WorkerPool::trySubmit(CancelFlag cancel, std::function<void()> job, std::string client) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (queue_.size() >= capacity_) return false;
    Client& c = clients_[client];
    if (c.queued == 0 && c.running == 0) c.served = ++events_;  // new: counts from now
    ++c.queued;
    queue_.push_back({std::move(cancel), std::move(job), std::move(client)});
  }
  wake_.notify_one();
  return true;
}

void WorkerPool::cancelAll() {
  const std::lock_guard<std::mutex> lock(mutex_);
  for (const Job& job : queue_) job.cancel->store(true);
  for (const CancelFlag& flag : running_) flag->store(true);
}

std::size_t WorkerPool::queued() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return queue_.size();
}

std::size_t WorkerPool::running() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return running_.size();
}

bool WorkerPool::idle() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return queue_.empty() && running_.empty();
}

std::deque<WorkerPool::Job>::iterator WorkerPool::next() {
  auto best = queue_.begin();
  const auto rank = [this](const Job& job) {
    const Client& c = clients_.at(job.client);
    return std::make_pair(c.running, c.served);
  };
  for (auto job = queue_.begin() + 1; job != queue_.end(); ++job)
    if (rank(*job) < rank(*best)) best = job;
  return best;
}

void WorkerPool::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, and nothing left to run
    const auto chosen = next();
    Job job = std::move(*chosen);
    queue_.erase(chosen);
    Client& client = clients_.at(job.client);
    --client.queued;
    ++client.running;
    client.served = ++events_;
    running_.push_back(job.cancel);
    lock.unlock();
    job.run();
    job.run = nullptr;  // release what the job holds before it counts as done
    lock.lock();
    running_.erase(std::find(running_.begin(), running_.end(), job.cancel));
    const auto done = clients_.find(job.client);
    if (--done->second.running == 0 && done->second.queued == 0) clients_.erase(done);
  }
}

}  // namespace hfts::service
