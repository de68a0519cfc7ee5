#include "bench_report.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace hfts::bench {
namespace {

constexpr std::size_t kBarWidth = 24;

std::string clock(double seconds) {
  const long s = static_cast<long>(seconds);
  std::ostringstream text;
  text << std::setfill('0');
  if (s >= 3600) text << s / 3600 << ":";
  text << std::setw(2) << s / 60 % 60 << ":" << std::setw(2) << s % 60;
  return text.str();
}

struct AlgorithmSummary {
  std::size_t runs = 0;
  std::size_t successes = 0;  ///< planned and held
  std::size_t planned = 0;
  double mean_time = 0.0;
  double median_time = 0.0;
  double mean_gs = 0.0;
  double vgs_per_gs = 0.0;  ///< negative when no goal was ever sampled
  double mean_gns = 0.0;
};

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

AlgorithmSummary summarize(const std::vector<RunRecord>& records, const std::string& algorithm) {
  AlgorithmSummary s;
  std::vector<double> times;
  double gs = 0.0, vgs = 0.0, gns = 0.0;
  for (const RunRecord& r : records) {
    if (r.algorithm != algorithm) continue;
    times.push_back(r.stats.planning_time);
    s.successes += r.success ? 1 : 0;
    s.planned += r.planned ? 1 : 0;
    gs += static_cast<double>(r.stats.goal_sampling_calls);
    vgs += static_cast<double>(r.stats.valid_goal_samples);
    gns += static_cast<double>(r.stats.hfts_nodes_explored);
  }
  s.runs = times.size();
  if (s.runs == 0) return s;
  const double n = static_cast<double>(s.runs);
  for (double t : times) s.mean_time += t / n;
  s.median_time = median(times);
  s.mean_gs = gs / n;
  s.vgs_per_gs = gs > 0.0 ? vgs / gs : -1.0;
  s.mean_gns = gns / n;
  return s;
}

void printSummaryRow(std::ostream& out, const std::string& name, const AlgorithmSummary& s,
                     int width) {
  const auto percent = [&](std::size_t k) {
    return s.runs == 0 ? 0.0 : 100.0 * static_cast<double>(k) / static_cast<double>(s.runs);
  };
  std::ostringstream ratio;
  if (s.vgs_per_gs < 0.0)
    ratio << "-";
  else
    ratio << std::fixed << std::setprecision(3) << s.vgs_per_gs;
  out << std::left << std::setw(width) << name << std::right << std::setw(6) << s.runs << std::fixed
      << std::setprecision(1) << std::setw(9) << percent(s.successes) << "%" << std::setw(9)
      << percent(s.planned) << "%" << std::setprecision(3) << std::setw(12) << s.mean_time
      << std::setw(14) << s.median_time << std::setprecision(1) << std::setw(10) << s.mean_gs
      << std::setw(9) << ratio.str() << std::setw(11) << s.mean_gns << "\n";
}

}  // namespace

std::string describeRun(const RunRecord& r) {
  std::ostringstream text;
  text << r.scene << " " << r.object << " " << r.algorithm << " seed " << r.seed << ": "
       << (r.success ? "success" : "failure " + r.failure) << " " << std::fixed
       << std::setprecision(2) << r.stats.planning_time << " s";
  if (r.held) text << " (held in " << std::setprecision(2) << r.held_fraction << " of the trials)";
  return text.str();
}

Progress::Progress(std::ostream& out, bool terminal, std::size_t total)
    : out_(&out), terminal_(terminal), total_(total), began_(std::chrono::steady_clock::now()) {
  if (terminal_) drawBar();  // the first run may take a minute: show that it started
}

Progress::~Progress() {
  if (terminal_ && finished_ != total_) *out_ << "\n";
}

void Progress::done(const RunRecord& record) {
  ++finished_;
  succeeded_ += record.success ? 1 : 0;
  if (terminal_) {
    drawBar();
    return;
  }
  *out_ << "[" << finished_ << "/" << total_ << "] " << describeRun(record) << std::endl;
}

void Progress::drawBar() {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began_).count();
  const std::size_t filled = kBarWidth * finished_ / std::max<std::size_t>(total_, 1);
  // Short enough for an 80-column terminal, where a wrapped line could not
  // be redrawn with \r; \033[K clears what a longer previous line left.
  *out_ << "\r[" << std::string(filled, '#') << std::string(kBarWidth - filled, ' ') << "] "
        << finished_ << "/" << total_ << "  elapsed " << clock(elapsed) << "  success "
        << succeeded_ << "/" << finished_ << "\033[K" << std::flush;
  if (finished_ == total_) *out_ << "\n";
}

void printSummary(std::ostream& out, const std::vector<RunRecord>& records,
                  const std::vector<std::string>& algorithms) {
  std::size_t width = 9;
  for (const std::string& a : algorithms) width = std::max(width, a.size());
  const int w = static_cast<int>(width) + 2;
  out << std::left << std::setw(w) << "algorithm" << std::right << std::setw(6) << "runs"
      << std::setw(10) << "success" << std::setw(10) << "planned" << std::setw(12) << "mean t (s)"
      << std::setw(14) << "median t (s)" << std::setw(10) << "mean GS" << std::setw(9) << "VGS/GS"
      << std::setw(11) << "mean GNS"
      << "\n";
  for (const std::string& a : algorithms) printSummaryRow(out, a, summarize(records, a), w);
}

}  // namespace hfts::bench
