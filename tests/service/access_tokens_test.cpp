#include "service/access_tokens.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "test_meshes.h"

namespace hfts::service {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

constexpr const char* kFile =
    "# the lab's tokens\n"
    "plan  plan-token-0123456789abcdef  alice\n"
    "\n"
    "admin admin-token-0123456789abcdef\r\n";

TEST(AccessTokens, EachRoleCallsItsMethods) {
  for (const char* method :
       {"server.info", "objects.list", "scenes.list", "plan", "grasp.quality", "cancel"})
    EXPECT_EQ(requiredRole(method), Role::kPlan) << method;
  EXPECT_EQ(requiredRole("reload"), Role::kAdmin);
  EXPECT_EQ(requiredRole("shutdown"), Role::kAdmin);
  EXPECT_EQ(requiredRole("auth"), std::nullopt);
  EXPECT_TRUE(allows(Role::kAdmin, Role::kAdmin));
  EXPECT_TRUE(allows(Role::kAdmin, Role::kPlan));
  EXPECT_TRUE(allows(Role::kPlan, Role::kPlan));
  EXPECT_FALSE(allows(Role::kPlan, Role::kAdmin));
}

TEST(AccessTokens, AFileGivesEachTokenItsRoleAndName) {
  const TokenTable table = TokenTable::parse(kFile, "tokens");
  ASSERT_EQ(table.size(), 2u);
  const TokenEntry* plan = table.find("plan-token-0123456789abcdef");
  ASSERT_NE(plan, nullptr);
  EXPECT_EQ(plan->role, Role::kPlan);
  EXPECT_EQ(plan->name, "alice");
  const TokenEntry* admin = table.find("admin-token-0123456789abcdef");
  ASSERT_NE(admin, nullptr);
  EXPECT_EQ(admin->role, Role::kAdmin);
  EXPECT_EQ(admin->name, "line 4");
  EXPECT_EQ(table.find("admin-token-0123456789abcde"), nullptr);  // one character short
  EXPECT_EQ(table.find(""), nullptr);
  EXPECT_EQ(table.find(digestOf("plan-token-0123456789abcdef")), plan);
}

TEST(AccessTokens, ABadLineIsNamed) {
  const auto fails = [](const std::string& text, const std::string& says) {
    try {
      TokenTable::parse(text, "tokens.txt");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  fails("root plan-token-0123456789abcdef\n", "line 1: the role must be plan or admin");
  fails("plan\n", "a token is missing");
  fails("# only a comment\nplan short\n", "line 2: a token must have 16 to 1024 characters");
  fails("plan plan-token-0123456789abcdef a b\n", "more than ROLE TOKEN [NAME]");
  fails("plan plan-token-\x01-0123456789abcdef\n", "printable ASCII");
  fails("plan plan-token-0123456789abcdef\nadmin plan-token-0123456789abcdef\n",
        "line 2: this token is already on an earlier line");
  fails("# nothing\n\n", "holds no token");
}

TEST(AccessTokens, AFileEveryUserMayReadIsRefused) {
  const test::TempDir dir;
  const fs::path file = dir / "tokens.txt";
  test::writeText(file, kFile);
  ASSERT_EQ(::chmod(file.c_str(), 0644), 0);
  try {
    TokenTable::load(file);
    ADD_FAILURE() << "a world-readable token file was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("mode 0644): chmod 600"), std::string::npos) << e.what();
  }
  ASSERT_EQ(::chmod(file.c_str(), 0600), 0);
  EXPECT_EQ(TokenTable::load(file).size(), 2u);
  EXPECT_THROW(TokenTable::load(file.string() + ".missing"), std::runtime_error);
}

TEST(AccessTokens, RepeatedFailuresFromOneAddressAreThrottled) {
  AuthThrottle throttle(3, seconds(60), seconds(30));
  const auto t0 = AuthThrottle::Clock::now();
  throttle.failed("10.0.0.1", t0);
  throttle.failed("10.0.0.1", t0 + seconds(1));
  EXPECT_EQ(throttle.blockedFor("10.0.0.1", t0 + seconds(2)).count(), 0);
  throttle.failed("10.0.0.1", t0 + seconds(2));
  EXPECT_EQ(throttle.blockedFor("10.0.0.1", t0 + seconds(2)), seconds(30));
  EXPECT_EQ(throttle.blockedFor("10.0.0.2", t0 + seconds(2)).count(), 0);  // another peer
  EXPECT_EQ(throttle.blockedFor("10.0.0.1", t0 + seconds(33)).count(), 0);
  // Failures further apart than the window never add up to a block.
  AuthThrottle slow(3, seconds(60), seconds(30));
  for (int i = 0; i < 10; ++i) slow.failed("10.0.0.3", t0 + seconds(61 * i));
  EXPECT_EQ(slow.blockedFor("10.0.0.3", t0 + seconds(61 * 9)).count(), 0);
}

TEST(AccessTokens, TheThrottleForgetsTheOldestAddressWhenFull) {
  AuthThrottle throttle(1, seconds(60), seconds(60));
  const auto t0 = AuthThrottle::Clock::now();
  for (std::size_t i = 0; i < AuthThrottle::kMaxAddresses; ++i)
    throttle.failed("a" + std::to_string(i), t0 + std::chrono::milliseconds(i));
  EXPECT_GT(throttle.blockedFor("a0", t0).count(), 0);
  throttle.failed("newcomer", t0 + seconds(5));
  EXPECT_EQ(throttle.blockedFor("a0", t0).count(), 0);  // forgotten
  EXPECT_GT(throttle.blockedFor("a1", t0).count(), 0);
  EXPECT_GT(throttle.blockedFor("newcomer", t0 + seconds(5)).count(), 0);
}

}  // namespace
}  // namespace hfts::service
