#include "run_record.h"

#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace hfts::bench {
namespace {

constexpr const char* kHeader =
    "scene,object,algorithm,seed,success,failure,time,gs,vgs,gns,epsilon,path_length,"
    "collision_checks,cpu_time";

/// RFC 4180 quoting; names from file stems may hold commas or quotes.
std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

void writeRow(std::ostream& out, const RunRecord& r) {
  out << csvField(r.scene) << ',' << csvField(r.object) << ',' << csvField(r.algorithm) << ','
      << r.seed << ',' << (r.success ? 1 : 0) << ',' << r.failure << ',' << std::fixed
      << std::setprecision(6) << r.time << ',' << r.gs << ',' << r.vgs << ',' << r.gns << ',';
  // A failed run has no grasp and no path: empty fields, not zeros that
  // would pull averages down.
  if (r.success)
    out << std::setprecision(8) << r.epsilon << ',' << r.path_length;
  else
    out << ',';
  out << ',' << r.collision_checks << ',' << std::setprecision(6) << r.cpu_time << '\n';
}

}  // namespace

RunRecord makeRunRecord(const std::string& scene, const std::string& object,
                        const std::string& algorithm, std::uint64_t seed,
                        const planner::PlanResult& result, double cpuTime) {
  RunRecord r;
  r.scene = scene;
  r.object = object;
  r.algorithm = algorithm;
  r.seed = seed;
  r.success = result.success;
  r.failure = planner::toString(result.failure);
  r.time = result.stats.planning_time;
  r.gs = result.stats.goal_sampling_calls;
  r.vgs = result.stats.valid_goal_samples;
  r.gns = result.stats.hfts_nodes_explored;
  r.epsilon = result.grasp.epsilon;
  r.path_length = result.stats.path_length_smoothed;
  r.collision_checks = result.stats.collision_checks;
  r.cpu_time = cpuTime;
  return r;
}

void writeCsvAtomically(const std::filesystem::path& out, const std::vector<RunRecord>& records) {
  std::filesystem::path tmp = out;
  tmp += ".tmp";
  {
    std::ofstream file(tmp, std::ios::binary | std::ios::trunc);
    if (!file) throw std::runtime_error("cannot write '" + tmp.string() + "'");
    file << kHeader << '\n';
    for (const RunRecord& r : records) writeRow(file, r);
    file.flush();
    if (!file) throw std::runtime_error("error while writing '" + tmp.string() + "'");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, out, ec);
  if (ec)
    throw std::runtime_error("cannot rename '" + tmp.string() + "' to '" + out.string() +
                             "': " + ec.message());
}

}  // namespace hfts::bench
