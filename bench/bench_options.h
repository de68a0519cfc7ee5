#pragma once
// hfts-bench's command-line vocabulary: algorithm names, default paths and
// the checks that turn a bad argument into a usage error naming it.

#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "planner/grasp_motion_planner.h"

namespace hfts::bench {

/// A bad command-line argument; hfts-bench exits with status 2 for it.
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// One benchmarked planner variant, named as on the command line.
struct Algorithm {
  std::string name;  ///< as given: "coupled", "decoupledN", "coupled:mask_contacts=0", ...
  planner::PlanAlgorithm algorithm = planner::PlanAlgorithm::kCoupled;
  std::optional<int> iterations;  ///< decoupled only: N iterations per level
  /// Planner parameters of every run (the ":name=value" settings).
  std::map<std::string, std::string> parameters;
  /// "paper" (or a ":preset=paper" setting): the paper's settings under
  /// the parameters (planner::PlannerPreset).
  planner::PlannerPreset preset = planner::PlannerPreset::kDefault;
  /// A ":lift=H" setting: the lift's height (m; 0: no lift). Unset: the
  /// paper's planner does not lift, the others lift by the default height.
  std::optional<double> lift;
};

/// Parses "coupled", "paper" (coupled with the paper's settings),
/// "decoupledN" or "rrtconnect[N]" (N >= 1), each
/// optionally followed by planner parameter settings ":name=value", e.g.
/// "coupled:mask_contacts=0:other_postures=1" (names and values are
/// checked by the planner). Throws UsageError.
Algorithm parseAlgorithm(const std::string& text);

/// Parses every name; duplicates are a UsageError (they would count twice).
std::vector<Algorithm> parseAlgorithms(const std::vector<std::string>& names);

/// `fallback` relative to the current directory if it exists there, else
/// relative to the source tree (so the program runs from any directory);
/// `given` unchanged when not empty.
std::filesystem::path resolveDefault(const std::string& given, const std::string& fallback);

/// The stems of the *.json files in `dir`, sorted. Throws
/// std::runtime_error when `dir` is not a directory.
std::vector<std::string> sceneNamesIn(const std::filesystem::path& dir);

/// Throws UsageError "unknown <what> 'x' (valid: a, b)" for the first entry
/// of `wanted` that is not in `valid`, or for a repeated entry.
void requireKnown(const std::vector<std::string>& wanted, const std::vector<std::string>& valid,
                  const std::string& what);

/// Throws UsageError unless runs >= 1 and the time limit is finite and > 0.
void checkRunsAndTimeLimit(int runs, double timeLimit);

}  // namespace hfts::bench
