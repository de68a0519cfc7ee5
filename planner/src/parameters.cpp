#include "planner/parameters.h"

#include <ompl/util/Console.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <map>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "core/invalid_argument.h"

namespace hfts::planner {
namespace {

/// The shortest decimal text that reads back as exactly `value`; plain
/// digits ("100000", "0.0001") unless an exponent is much shorter.
std::string shortest(double value) {
  char any[64], fixed[400];
  const std::to_chars_result a = std::to_chars(any, any + sizeof any, value);
  const std::to_chars_result f =
      std::to_chars(fixed, fixed + sizeof fixed, value, std::chars_format::fixed);
  if (f.ec == std::errc() && f.ptr - fixed <= a.ptr - any + 2) return std::string(fixed, f.ptr);
  return std::string(any, a.ptr);
}

/// The whole text as a finite number, or nothing.
bool parseNumber(const std::string& text, double& value) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  return errno == 0 && end == text.c_str() + text.size() && std::isfinite(value);
}

std::string field(const std::string& name) {
  return "parameters." + name;
}

std::string outOfRange(const ParameterRange& range, const std::string& value) {
  return "must be in [" + shortest(range.low) + ", " + shortest(range.high) + "], got " + value;
}

/// range.suggestion(), each text made once per process: every planner a
/// plan builds declares a dozen parameters.
const std::string& suggestionOf(const ParameterRange& range) {
  static std::mutex guard;
  static std::map<std::tuple<double, double, double>, std::string> made;
  const std::lock_guard<std::mutex> lock(guard);
  std::string& text = made[{range.low, range.step, range.high}];
  if (text.empty()) text = range.suggestion();
  return text;
}

}  // namespace

std::string ParameterRange::suggestion() const {
  return shortest(low) + ":" + shortest(step) + ":" + shortest(high);
}

ParameterRange ParameterRange::fromSuggestion(const std::string& text) {
  const std::size_t first = text.find(':');
  const std::size_t second = text.find(':', first == std::string::npos ? first : first + 1);
  ParameterRange r;
  if (first == std::string::npos || second == std::string::npos ||
      !parseNumber(text.substr(0, first), r.low) ||
      !parseNumber(text.substr(first + 1, second - first - 1), r.step) ||
      !parseNumber(text.substr(second + 1), r.high))
    throw std::invalid_argument("'" + text + "' is not a range low:step:high");
  return r;
}

template <typename T>
void declareParameter(ompl::base::ParamSet& params, const std::string& name,
                      const ParameterRange& range, std::function<void(T)> set,
                      std::function<T()> get) {
  params.declareParam<T>(
      name,
      [name, range, set = std::move(set)](T value) {
        if (!range.contains(static_cast<double>(value)))
          throw InvalidArgument(field(name),
                                outOfRange(range, shortest(static_cast<double>(value))));
        set(value);
      },
      std::move(get));
  params[name].setRangeSuggestion(suggestionOf(range));
}

template void declareParameter<double>(ompl::base::ParamSet&, const std::string&,
                                       const ParameterRange&, std::function<void(double)>,
                                       std::function<double()>);
template void declareParameter<int>(ompl::base::ParamSet&, const std::string&,
                                    const ParameterRange&, std::function<void(int)>,
                                    std::function<int()>);
template void declareParameter<unsigned>(ompl::base::ParamSet&, const std::string&,
                                         const ParameterRange&, std::function<void(unsigned)>,
                                         std::function<unsigned()>);

void quietOmpl() {
  static const bool once = [] {
    ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
    return true;
  }();
  (void)once;
}

void setParameter(ompl::base::ParamSet& params, const std::string& name, const std::string& value) {
  quietOmpl();  // OMPL logs every value it sets at its debug level
  if (!params.hasParam(name)) throw InvalidArgument(field(name), "unknown planner parameter");
  ompl::base::GenericParam& param = params[name];
  // Checked here, from the declared range, so that a bad value gets its
  // reason (OMPL would only log a warning and return false).
  const ParameterRange range = ParameterRange::fromSuggestion(param.getRangeSuggestion());
  const bool integer = dynamic_cast<ompl::base::SpecificParam<int>*>(&param) != nullptr ||
                       dynamic_cast<ompl::base::SpecificParam<unsigned>*>(&param) != nullptr;
  double number = 0.0;
  if (!parseNumber(value, number) || (integer && number != std::floor(number)))
    throw InvalidArgument(
        field(name),
        std::string(integer ? "must be an integer" : "must be a number") + ", got '" + value + "'");
  if (!range.contains(number)) throw InvalidArgument(field(name), outOfRange(range, value));
  // Integers go through OMPL as "5", not "5.0" or "5e0".
  if (!param.setValue(integer ? std::to_string(static_cast<long long>(number)) : value))
    throw InvalidArgument(field(name), "'" + value + "' was not accepted");
}

}  // namespace hfts::planner
