#include "experiment_design.h"

#include "bench_options.h"

namespace hfts::bench {
namespace {

const std::vector<std::string> kAllAlgorithms = {"coupled", "decoupled20", "decoupled60",
                                                 "decoupled100", "rrtconnect"};

}  // namespace

ExperimentDesign experimentDesign(const std::string& name, bool quick) {
  if (name != "paper") throw UsageError("unknown experiment '" + name + "' (valid: paper)");
  if (quick)
    return {"paper-quick", {{"table", {"mug"}}, {"bin", {"blob"}}}, kAllAlgorithms, 2, 2.0};
  // Sec. IV: every algorithm on every environment with several objects.
  // Two objects per bundled scene (its own target and one more that
  // stands at the target pose); 300 runs of at most 8 s keep the worst
  // case at 40 minutes on one core.
  return {"paper",
          {{"table", {"mug", "box"}}, {"shelf", {"bottle", "mug"}}, {"bin", {"blob", "cylinder"}}},
          kAllAlgorithms,
          10,
          8.0};
}

}  // namespace hfts::bench
