#include <gtest/gtest.h>

#include <random>
#include <set>

#include "preprocess/kmeans.h"

namespace hfts::preprocess {
namespace {

Features blobs(int perBlob, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  const double centres[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  Features x(3 * perBlob, 2);
  for (int b = 0; b < 3; ++b)
    for (int i = 0; i < perBlob; ++i)
      x.row(b * perBlob + i) << centres[b][0] + noise(rng), centres[b][1] + noise(rng);
  return x;
}

TEST(KMeans, SeparatesWellSeparatedBlobs) {
  const Features x = blobs(50, 7);
  const auto label = kmeansPlusPlus(x, 3, 50, 1);
  ASSERT_EQ(label.size(), 150u);
  for (int b = 0; b < 3; ++b)
    for (int i = 1; i < 50; ++i) EXPECT_EQ(label[b * 50 + i], label[b * 50]);
  EXPECT_EQ(std::set<std::uint32_t>(label.begin(), label.end()).size(), 3u);
  EXPECT_EQ(label[0], 0u);  // numbered by first appearance
}

TEST(KMeans, NeverReturnsEmptyClusters) {
  // All points identical: D^2 seeding has nothing to go on.
  const Features same = Features::Ones(10, 6);
  const auto label = kmeansPlusPlus(same, 4, 20, 3);
  std::vector<int> size(4, 0);
  for (auto l : label) ++size.at(l);
  for (int s : size) EXPECT_GT(s, 0);
}

TEST(KMeans, FewerPointsThanClustersGivesOneClusterPerPoint) {
  const Features x = Features::Random(3, 6);
  const auto label = kmeansPlusPlus(x, 20, 10, 1);
  EXPECT_EQ(std::set<std::uint32_t>(label.begin(), label.end()).size(), 3u);
}

TEST(KMeans, IsDeterministicPerSeed) {
  const Features x = Features::Random(500, 6);
  EXPECT_EQ(kmeansPlusPlus(x, 8, 30, 5), kmeansPlusPlus(x, 8, 30, 5));
  EXPECT_THROW(kmeansPlusPlus(x, 0, 30, 5), std::invalid_argument);
  EXPECT_TRUE(kmeansPlusPlus(Features(0, 6), 3, 10, 1).empty());
}

}  // namespace
}  // namespace hfts::preprocess
