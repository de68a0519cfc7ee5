#include "physics/perturbations.h"

#include <gtest/gtest.h>

#include <set>

namespace hfts::physics {
namespace {

int changedFactors(const Perturbation& p) {
  return (p.friction_scale != 1.0) + (p.mass_scale != 1.0) + (p.gain_scale != 1.0);
}

TEST(Perturbations, TheNominalModelComesFirstAndAloneWithoutPerturbing) {
  const std::vector<Perturbation> one = perturbations(false);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].name, "nominal");
  EXPECT_EQ(changedFactors(one[0]), 0);
}

TEST(Perturbations, EachUncertainQuantityIsChangedAloneToBothSides) {
  const std::vector<Perturbation> all = perturbations(true);
  ASSERT_EQ(all.size(), 7u);
  EXPECT_EQ(all[0].name, "nominal");
  std::set<std::string> names;
  double friction = 1.0, mass = 1.0, gain = 1.0;  // products: both sides of each
  for (std::size_t i = 1; i < all.size(); ++i) {
    names.insert(all[i].name);
    EXPECT_EQ(changedFactors(all[i]), 1) << all[i].name;
    friction *= all[i].friction_scale;
    mass *= all[i].mass_scale;
    gain *= all[i].gain_scale;
  }
  EXPECT_EQ(names.size(), 6u);
  EXPECT_DOUBLE_EQ(friction, 0.75 * 1.25);
  EXPECT_DOUBLE_EQ(mass, 0.75 * 1.25);
  EXPECT_DOUBLE_EQ(gain, 1.0);  // x0.5 and x2
}

}  // namespace
}  // namespace hfts::physics
