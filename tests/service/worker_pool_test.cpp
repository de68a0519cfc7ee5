#include "worker_pool.h"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <mutex>
#include <string>
#include <vector>

namespace hfts::service {
namespace {

CancelFlag flag() {
  return std::make_shared<std::atomic<bool>>(false);
}

/// A job that waits until it is cancelled (or 10 s pass).
std::function<void()> waitForCancel(const CancelFlag& f, std::promise<void>* started = nullptr) {
  return [f, started] {
    if (started) started->set_value();
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!f->load() && std::chrono::steady_clock::now() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  };
}

TEST(WorkerPool, RunsEveryJob) {
  std::atomic<int> done{0};
  {
    WorkerPool pool(2, 100);
    for (int i = 0; i < 50; ++i) EXPECT_TRUE(pool.trySubmit(flag(), [&done] { ++done; }));
  }  // the destructor runs what is still queued
  EXPECT_EQ(done.load(), 50);
}

/// The order in which the jobs it makes ran.
class RunOrder {
 public:
  std::function<void()> record(std::string name) {
    return [this, name] {
      const std::lock_guard<std::mutex> lock(mutex_);
      names_.push_back(name);
    };
  }
  std::vector<std::string> names() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return names_;
  }

 private:
  std::mutex mutex_;
  std::vector<std::string> names_;
};

TEST(WorkerPool, AClientWaitingBehindAnothersJobsGoesNext) {
  WorkerPool pool(1, 10);
  const CancelFlag blocker = flag();
  std::promise<void> started;
  ASSERT_TRUE(pool.trySubmit(blocker, waitForCancel(blocker, &started), "flood"));
  started.get_future().wait();
  RunOrder run;
  for (const char* name : {"flood 1", "flood 2", "flood 3"})
    ASSERT_TRUE(pool.trySubmit(flag(), run.record(name), "flood"));
  ASSERT_TRUE(pool.trySubmit(flag(), run.record("other 1"), "other"));
  ASSERT_TRUE(pool.trySubmit(flag(), run.record("other 2"), "other"));
  blocker->store(true);
  while (!pool.idle()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  // With no job running, the two take turns: "flood" was served (its
  // blocker started) before "other" arrived, so it goes first; each
  // client's jobs in the order they came.
  EXPECT_EQ(run.names(),
            (std::vector<std::string>{"flood 1", "other 1", "flood 2", "other 2", "flood 3"}));
}

TEST(WorkerPool, ANewcomerNeverGoesBeforeAClientServedBeforeItCame) {
  // One worker. "c" has two jobs queued; while its first runs, newcomers
  // arrive. When the worker comes free, "c" (served before they came)
  // goes before every one of them: a stream of newcomers cannot keep a
  // waiting client's job back for ever.
  WorkerPool pool(1, 20);
  RunOrder run;
  const CancelFlag first = flag();
  std::promise<void> started;
  ASSERT_TRUE(pool.trySubmit(first, waitForCancel(first, &started), "c"));
  ASSERT_TRUE(pool.trySubmit(flag(), run.record("c 2"), "c"));
  started.get_future().wait();
  for (int i = 0; i < 3; ++i) {
    const std::string name = "new " + std::to_string(i);
    ASSERT_TRUE(pool.trySubmit(flag(), run.record(name), name));
  }
  first->store(true);
  while (!pool.idle()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_EQ(run.names(), (std::vector<std::string>{"c 2", "new 0", "new 1", "new 2"}));
}

TEST(WorkerPool, RefusesJobsBeyondTheQueueCapacity) {
  WorkerPool pool(1, 2);
  const CancelFlag running = flag(), a = flag(), b = flag();
  std::promise<void> started;
  ASSERT_TRUE(pool.trySubmit(running, waitForCancel(running, &started)));
  started.get_future().wait();
  EXPECT_TRUE(pool.trySubmit(a, waitForCancel(a)));
  EXPECT_TRUE(pool.trySubmit(b, waitForCancel(b)));
  EXPECT_FALSE(pool.trySubmit(flag(), [] {}));
  EXPECT_EQ(pool.running(), 1u);
  EXPECT_EQ(pool.queued(), 2u);
  EXPECT_FALSE(pool.idle());
  pool.cancelAll();
  EXPECT_TRUE(running->load() && a->load() && b->load());
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!pool.idle() && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(pool.idle());
}

TEST(WorkerPool, RunsJobsConcurrentlyOnItsThreads) {
  WorkerPool pool(3, 10);
  std::promise<void> p1, p2, p3;
  const CancelFlag f1 = flag(), f2 = flag(), f3 = flag();
  pool.trySubmit(f1, waitForCancel(f1, &p1));
  pool.trySubmit(f2, waitForCancel(f2, &p2));
  pool.trySubmit(f3, waitForCancel(f3, &p3));
  for (std::promise<void>* p : {&p1, &p2, &p3})
    EXPECT_EQ(p->get_future().wait_for(std::chrono::seconds(5)), std::future_status::ready);
  EXPECT_EQ(pool.running(), 3u);
  pool.cancelAll();
}

TEST(WorkerPool, NeedsAThread) {
  EXPECT_THROW(WorkerPool(0, 1), std::invalid_argument);
  EXPECT_EQ(WorkerPool(4, 1).threads(), 4);
}

}  // namespace
}  // namespace hfts::service
