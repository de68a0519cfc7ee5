#pragma once
// Runs bench/plot_results.py, which turns a results CSV into the figures
// and the summary of docs/experiments/2026-11-21-paper-experiment.md.

#include <filesystem>
#include <string>
#include <vector>

namespace hfts::bench {

/// Runs `python script args...` with this program's stdout and stderr and
/// waits for it. Returns its exit status; 127 when it could not be started,
/// 128 + n when signal n ended it.
int runPython(const std::string& python, const std::filesystem::path& script,
              const std::vector<std::string>& args);

}  // namespace hfts::bench
