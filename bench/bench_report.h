#pragma once
// What hfts-bench tells its user: progress while it runs (stderr) and the
// per-algorithm summary at the end (stdout).

#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "run_record.h"

namespace hfts::bench {

/// Reports each finished run: on a terminal a bar redrawn in place (runs
/// done / total, elapsed time, successes so far), elsewhere one line per
/// run, e.g. "[3/24] table mug coupled seed 3: success 0.82 s".
class Progress {
 public:
  Progress(std::ostream& out, bool terminal, std::size_t total);
  /// Ends an unfinished bar's line, so an error message starts on its own.
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void done(const RunRecord& record);

 private:
  void drawBar();

  std::ostream* out_;
  bool terminal_;
  std::size_t total_;
  std::size_t finished_ = 0;
  std::size_t succeeded_ = 0;
  std::chrono::steady_clock::time_point began_;
};

/// "table mug coupled seed 3: success 0.82 s (held in 1.00 of the trials)"
/// (or "failure time_limit", "failure not_held").
std::string describeRun(const RunRecord& record);

/// One row per algorithm, in `algorithms` order: runs, success rate
/// (planned and held), planned rate, mean and median time over all runs
/// (failures count at their time), mean GS, VGS/GS, mean GNS.
void printSummary(std::ostream& out, const std::vector<RunRecord>& records,
                  const std::vector<std::string>& algorithms);

}  // namespace hfts::bench
