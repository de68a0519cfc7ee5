#include "bench_options.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "planner/goal_sampler.h"

namespace hfts::bench {
namespace {

// The planner's range of "iterations": decoupledN is checked before any run.
constexpr int kMaxIterations = static_cast<int>(planner::kDecoupledIterationsRange.high);

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

std::optional<int> positiveInteger(const std::string& digits) {
  if (digits.empty() || digits.size() > 7) return std::nullopt;
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  const int value = std::stoi(digits);
  if (value < 1 || value > kMaxIterations) return std::nullopt;
  return value;
}

}  // namespace

namespace {

/// The algorithm part of a name (without ":parameter=value" settings).
Algorithm parseBase(const std::string& text) {
  const auto algorithm = [&text](planner::PlanAlgorithm a, std::optional<int> iterations = {},
                                 planner::PlannerPreset preset = planner::PlannerPreset::kDefault) {
    Algorithm out;
    out.name = text;
    out.algorithm = a;
    out.iterations = iterations;
    out.preset = preset;
    return out;
  };
  if (text == "coupled") return algorithm(planner::PlanAlgorithm::kCoupled);
  if (text == "paper")
    return algorithm(planner::PlanAlgorithm::kCoupled, std::nullopt,
                     planner::PlannerPreset::kPaper);
  if (text == "rrtconnect") return algorithm(planner::PlanAlgorithm::kRrtConnect);
  for (const auto& [prefix, kind] :
       {std::pair{std::string("decoupled"), planner::PlanAlgorithm::kDecoupled},
        std::pair{std::string("rrtconnect"), planner::PlanAlgorithm::kRrtConnect}}) {
    if (text.rfind(prefix, 0) != 0) continue;
    if (const auto n = positiveInteger(text.substr(prefix.size()))) return algorithm(kind, n);
  }
  throw UsageError("unknown algorithm '" + text +
                   "' (valid: coupled, paper, decoupledN and rrtconnect[N] with N = 1.." +
                   std::to_string(kMaxIterations) +
                   " iterations per level, e.g. decoupled20, rrtconnect; any of them with "
                   "planner parameters as :name=value, e.g. coupled:mask_contacts=0, or the "
                   "paper's settings as :preset=paper, e.g. decoupled20:preset=paper)");
}

}  // namespace

Algorithm parseAlgorithm(const std::string& text) {
  std::size_t colon = text.find(':');
  Algorithm a = parseBase(text.substr(0, colon));
  a.name = text;
  while (colon != std::string::npos) {
    const std::size_t next = text.find(':', colon + 1);
    const std::string setting = text.substr(colon + 1, next - colon - 1);
    const std::size_t equals = setting.find('=');
    if (equals == std::string::npos || equals == 0 || equals + 1 == setting.size())
      throw UsageError("algorithm '" + text + "': '" + setting +
                       "' is not a planner parameter setting name=value");
    if (setting.substr(0, equals) == "preset") {
      if (setting.substr(equals + 1) != "paper")
        throw UsageError("algorithm '" + text + "': the only preset is paper, got '" +
                         setting.substr(equals + 1) + "'");
      a.preset = planner::PlannerPreset::kPaper;
    } else if (setting.substr(0, equals) == "lift") {
      const std::string value = setting.substr(equals + 1);
      char* end = nullptr;
      const double height = std::strtod(value.c_str(), &end);
      if (end != value.c_str() + value.size() || !(height >= 0.0 && height <= 1.0))
        throw UsageError("algorithm '" + text + "': lift must be a height in [0, 1] m (0: none), " +
                         "got '" + value + "'");
      if (a.lift) throw UsageError("algorithm '" + text + "' sets 'lift' twice");
      a.lift = height;
    } else if (!a.parameters.emplace(setting.substr(0, equals), setting.substr(equals + 1)).second)
      throw UsageError("algorithm '" + text + "' sets '" + setting.substr(0, equals) + "' twice");
    colon = next;
  }
  return a;
}

std::vector<Algorithm> parseAlgorithms(const std::vector<std::string>& names) {
  if (names.empty()) throw UsageError("--algorithms: give at least one algorithm");
  std::vector<Algorithm> out;
  std::set<std::string> seen;
  for (const std::string& name : names) {
    out.push_back(parseAlgorithm(name));
    if (!seen.insert(name).second)
      throw UsageError("--algorithms lists '" + name + "' more than once");
  }
  return out;
}

std::filesystem::path resolveDefault(const std::string& given, const std::string& fallback) {
  if (!given.empty()) return given;
  std::error_code ec;
  if (std::filesystem::exists(fallback, ec)) return fallback;
  return std::filesystem::path(HFTS_SOURCE_DIR) / fallback;
}

std::vector<std::string> sceneNamesIn(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw std::runtime_error("scene directory '" + dir.string() + "' does not exist");
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() == ".json")
      names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

void requireKnown(const std::vector<std::string>& wanted, const std::vector<std::string>& valid,
                  const std::string& what) {
  std::set<std::string> seen;
  for (const std::string& name : wanted) {
    if (std::find(valid.begin(), valid.end(), name) == valid.end())
      throw UsageError("unknown " + what + " '" + name + "' (valid: " + joined(valid) + ")");
    if (!seen.insert(name).second)
      throw UsageError("the " + what + " '" + name + "' is listed more than once");
  }
}

void checkRunsAndTimeLimit(int runs, double timeLimit) {
  if (runs < 1) throw UsageError("--runs must be at least 1, got " + std::to_string(runs));
  if (!std::isfinite(timeLimit) || timeLimit <= 0.0) {
    std::ostringstream text;
    text << "--time-limit must be a positive number of seconds, got " << timeLimit;
    throw UsageError(text.str());
  }
}

}  // namespace hfts::bench
