#pragma once
// The experiments hfts-bench can run by name (--experiment): which objects
// are planned for in which scene, with which algorithms, how many runs and
// which time limit. docs/benchmarks.md describes them and why.

#include <string>
#include <vector>

namespace hfts::bench {

/// One scene and the objects planned for in it, each at the scene's
/// target pose.
struct SceneObjects {
  std::string scene;
  std::vector<std::string> objects;
};

struct ExperimentDesign {
  std::string name;  ///< "paper" or "paper-quick"
  std::vector<SceneObjects> cases;
  std::vector<std::string> algorithms;
  int runs = 0;  ///< per scene, object and algorithm, seeds 1..runs
  double time_limit = 0.0;
};

/// The design of `name` ("paper"); `quick` gives its small variant for CI
/// (two scenes with one object each, every algorithm, 2 runs of at most
/// 2 s). Throws UsageError for an unknown name.
ExperimentDesign experimentDesign(const std::string& name, bool quick);

}  // namespace hfts::bench
