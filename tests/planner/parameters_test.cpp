#include "planner/parameters.h"

#include <gtest/gtest.h>

#include "core/invalid_argument.h"

namespace hfts::planner {
namespace {

TEST(ParameterRange, SuggestionIsOmplsNotationAndReadsBackExactly) {
  const ParameterRange r{1e-12, 0.05, 0.1 + 0.2};
  EXPECT_EQ((ParameterRange{0, 1, 64}.suggestion()), "0:1:64");
  EXPECT_EQ((ParameterRange{0.001, 0.05, 10}.suggestion()), "0.001:0.05:10");
  const ParameterRange back = ParameterRange::fromSuggestion(r.suggestion());
  EXPECT_EQ(back.low, r.low);
  EXPECT_EQ(back.step, r.step);
  EXPECT_EQ(back.high, r.high);  // 0.30000000000000004, not 0.3
  EXPECT_THROW(ParameterRange::fromSuggestion("0.:1."), std::invalid_argument);
  EXPECT_THROW(ParameterRange::fromSuggestion("a:b:c"), std::invalid_argument);
}

/// A set like a planner's: one double and one integer parameter.
struct Owner {
  double ratio = 0.5;
  int count = 4;
  ompl::base::ParamSet params;
  Owner() {
    declareParameter(params, "ratio", {0.0, 0.1, 1.0}, ratio);
    declareParameter(params, "count", {1, 1, 10}, count);
  }
};

std::string rejection(Owner& owner, const std::string& name, const std::string& value) {
  try {
    setParameter(owner.params, name, value);
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.field(), "parameters." + name);
    return e.problem();
  }
  return "";
}

TEST(SetParameter, AcceptsValuesInTheDeclaredRange) {
  Owner o;
  EXPECT_EQ(o.params["ratio"].getRangeSuggestion(), "0:0.1:1");
  setParameter(o.params, "ratio", "0.25");
  setParameter(o.params, "count", "10");
  EXPECT_EQ(o.ratio, 0.25);
  EXPECT_EQ(o.count, 10);
  setParameter(o.params, "ratio", "1");  // both ends belong to the range
  setParameter(o.params, "ratio", "0");
  EXPECT_EQ(o.ratio, 0.0);
}

TEST(SetParameter, RejectsWithTheFieldAndTheReason) {
  Owner o;
  EXPECT_EQ(rejection(o, "ratio", "1.5"), "must be in [0, 1], got 1.5");
  EXPECT_EQ(rejection(o, "count", "0"), "must be in [1, 10], got 0");
  EXPECT_EQ(rejection(o, "count", "3.5"), "must be an integer, got '3.5'");
  EXPECT_EQ(rejection(o, "ratio", "half"), "must be a number, got 'half'");
  EXPECT_EQ(rejection(o, "ratio", "0.5x"), "must be a number, got '0.5x'");
  EXPECT_EQ(rejection(o, "ratio", "nan"), "must be a number, got 'nan'");
  EXPECT_EQ(rejection(o, "ratio", ""), "must be a number, got ''");
  EXPECT_EQ(rejection(o, "size", "1"), "unknown planner parameter");
  EXPECT_EQ(o.ratio, 0.5);  // nothing was set
  EXPECT_EQ(o.count, 4);
}

TEST(SetParameter, TheDeclaredSetterEnforcesTheRangeForOmplUsersToo) {
  Owner o;
  // OMPL's own setParam goes through the setter, which checks the same
  // range (OMPL reports the failure as false).
  EXPECT_FALSE(o.params.setParam("count", "11"));
  EXPECT_EQ(o.count, 4);
  EXPECT_TRUE(o.params.setParam("count", "7"));
  EXPECT_EQ(o.count, 7);
}

}  // namespace
}  // namespace hfts::planner
