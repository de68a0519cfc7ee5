#pragma once
// The experiments hfts-bench can run by name (--experiment): which objects
// are planned for in which scene, with which algorithms, how many runs and
// which time limit. docs/benchmarks.md describes them and why.

#include <string>
#include <vector>

namespace hfts::bench {

/// One scene and the objects planned for in it (empty: every object in
/// the databases).
struct SceneObjects {
  std::string scene;
  std::vector<std::string> objects;
};

struct ExperimentDesign {
  std::string name;  ///< "paper", "zoo" or their "-quick" variants
  std::vector<SceneObjects> cases;
  /// Where each object stands: "target" (the scene's target pose), names
  /// of placements, or "all" (as --placements).
  std::vector<std::string> placements{"target"};
  std::vector<std::string> algorithms;
  int runs = 0;  ///< per scene, object and algorithm, seeds 1..runs
  double time_limit = 0.0;
};

/// The design of `name`: "paper" (the paper's Sec. IV on the bundled
/// scenes) or "zoo" (every object at every placement of every scene,
/// coupled against decoupled, 10 s). `quick` gives a small variant for CI.
/// Throws UsageError for an unknown name.
ExperimentDesign experimentDesign(const std::string& name, bool quick);

}  // namespace hfts::bench
