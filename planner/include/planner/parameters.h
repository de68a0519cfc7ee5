#pragma once
// Parameters by name: an OMPL ParamSet is the adapter from a name and a
// value as text to a typed field, with one range that is both OMPL's range
// suggestion and the check its setter enforces. The planner's settings
// (plan_settings.h) are declared this way in one table; the multi-tree
// planner declares its own for OMPL (docs/planning.md).

#include <ompl/base/GenericParam.h>

#include <functional>
#include <string>

namespace hfts::planner {

/// The values a parameter takes: low <= value <= high. `step` is only a
/// hint for tools (OMPL's "low:step:high" suggestion); values between
/// steps are accepted.
struct ParameterRange {
  double low = 0.0;
  double step = 0.0;
  double high = 0.0;

  bool contains(double value) const { return value >= low && value <= high; }
  /// OMPL's notation, "low:step:high", each number in its shortest exact form.
  std::string suggestion() const;
  /// The range of a suggestion() string. Throws std::invalid_argument for
  /// any other text.
  static ParameterRange fromSuggestion(const std::string& text);
};

/// Declares `name` in `params` with `range` as its suggestion; the setter
/// throws InvalidArgument ("parameters.<name>") outside the range and
/// otherwise calls `set`.
template <typename T>
void declareParameter(ompl::base::ParamSet& params, const std::string& name,
                      const ParameterRange& range, std::function<void(T)> set,
                      std::function<T()> get);

/// The same for a plain field that lives as long as `params`.
template <typename T>
void declareParameter(ompl::base::ParamSet& params, const std::string& name,
                      const ParameterRange& range, T& field) {
  declareParameter<T>(
      params, name, range, [&field](T value) { field = value; }, [&field] { return field; });
}

/// OMPL's console at warnings and above, once per process (setParameter
/// calls it: OMPL logs every value it sets at its debug level).
void quietOmpl();

/// Sets a declared parameter from text. Throws InvalidArgument with the
/// field "parameters.<name>" for an unknown name, text that is not a number
/// (or not an integer for an integer parameter) or a value outside its
/// range.
void setParameter(ompl::base::ParamSet& params, const std::string& name, const std::string& value);

extern template void declareParameter<double>(ompl::base::ParamSet&, const std::string&,
                                              const ParameterRange&, std::function<void(double)>,
                                              std::function<double()>);
extern template void declareParameter<int>(ompl::base::ParamSet&, const std::string&,
                                           const ParameterRange&, std::function<void(int)>,
                                           std::function<int()>);
extern template void declareParameter<unsigned>(ompl::base::ParamSet&, const std::string&,
                                                const ParameterRange&,
                                                std::function<void(unsigned)>,
                                                std::function<unsigned()>);

}  // namespace hfts::planner
