#include "hfts_db/isolated_call.h"

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <thread>
#include <vector>

namespace hfts {
namespace {

using Kind = IsolatedCallError::Kind;

/// The error runIsolated throws for `work`, checked to be one.
IsolatedCallError failureOf(const std::function<std::string()>& work,
                            const IsolationLimits& limits = {}) {
  try {
    runIsolated(work, limits);
  } catch (const IsolatedCallError& e) {
    return e;
  }
  ADD_FAILURE() << "runIsolated returned normally";
  return IsolatedCallError(Kind::kThrew, "");
}

TEST(IsolatedCall, ReturnsTheChildsBytesIntact) {
  EXPECT_EQ(runIsolated([] { return std::string(); }, {}), "");
  // Larger than a pipe's buffer, with every byte value.
  std::string big(8 << 20, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>(i * 131 % 256);
  EXPECT_EQ(runIsolated([&] { return big; }, {}), big);
}

TEST(IsolatedCall, AnExceptionInTheChildKeepsItsMessage) {
  const IsolatedCallError e = failureOf([]() -> std::string { throw std::runtime_error("no"); });
  EXPECT_EQ(e.kind(), Kind::kThrew);
  EXPECT_STREQ(e.what(), "no");
}

TEST(IsolatedCall, AChildThatDiesBecomesAnError) {
  const IsolatedCallError aborted = failureOf([]() -> std::string { std::abort(); });
  EXPECT_EQ(aborted.kind(), Kind::kCrashed);
  EXPECT_NE(std::string(aborted.what()).find("signal " + std::to_string(SIGABRT)),
            std::string::npos)
      << aborted.what();
  const IsolatedCallError exited = failureOf([]() -> std::string { std::_Exit(3); });
  EXPECT_EQ(exited.kind(), Kind::kCrashed);
  EXPECT_NE(std::string(exited.what()).find("exit status 3"), std::string::npos) << exited.what();
}

TEST(IsolatedCall, AChildThatHangsIsKilledAtTheTimeLimit) {
  const auto start = std::chrono::steady_clock::now();
  const IsolatedCallError e = failureOf(
      []() -> std::string {
        for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
      },
      {std::chrono::milliseconds(500)});
  EXPECT_EQ(e.kind(), Kind::kTimedOut);
  EXPECT_NE(std::string(e.what()).find("within 0.5 s"), std::string::npos) << e.what();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
}

TEST(IsolatedCall, TheParentsMemoryIsUntouched) {
  int value = 1;
  runIsolated(
      [&] {
        value = 2;
        return std::string();
      },
      {});
  EXPECT_EQ(value, 1);
}

TEST(IsolatedCall, TheMemoryLimitStopsARunawayChild) {
  const IsolatedCallError e = failureOf(
      [] {
        std::vector<std::string> hog;
        for (int i = 0; i < 64; ++i) hog.emplace_back(std::size_t{64} << 20, 'x');
        return std::string("allocated 4 GiB");
      },
      {std::chrono::seconds(60), std::size_t{256} << 20});
  // std::bad_alloc in the child; under AddressSanitizer its allocator ends
  // the child instead.
  if (e.kind() == Kind::kThrew)
    EXPECT_NE(std::string(e.what()).find("bad_alloc"), std::string::npos) << e.what();
  else
    EXPECT_EQ(e.kind(), Kind::kCrashed) << e.what();
}

}  // namespace
}  // namespace hfts
