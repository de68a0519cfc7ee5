#include "core/base64.h"

#include <gtest/gtest.h>

#include <random>

#include "core/invalid_argument.h"

namespace hfts::core {
namespace {

TEST(Base64, MatchesTheRfc4648Examples) {
  const std::pair<const char*, const char*> examples[] = {{"", ""},
                                                          {"f", "Zg=="},
                                                          {"fo", "Zm8="},
                                                          {"foo", "Zm9v"},
                                                          {"foob", "Zm9vYg=="},
                                                          {"fooba", "Zm9vYmE="},
                                                          {"foobar", "Zm9vYmFy"}};
  for (const auto& [plain, coded] : examples) {
    EXPECT_EQ(base64Encode(plain), coded);
    EXPECT_EQ(base64Decode(coded), plain);
  }
}

TEST(Base64, RoundTripsAnyBytes) {
  std::mt19937 rng(3);
  for (std::size_t n = 0; n < 300; ++n) {
    std::string bytes(n, '\0');
    for (char& c : bytes) c = static_cast<char>(rng() & 255u);
    EXPECT_EQ(base64Decode(base64Encode(bytes)), bytes) << n;
  }
}

TEST(Base64, MalformedTextIsRefusedByName) {
  for (const char* bad : {"Zg=", "Z===", "Zm9v!A==", "Zg==Zg==", "=Zg="}) {
    try {
      base64Decode(bad, "gltf");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.field(), "gltf") << bad;
    }
  }
}

}  // namespace
}  // namespace hfts::core
