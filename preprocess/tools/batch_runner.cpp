#include "batch_runner.h"

#include <assimp/Importer.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <iomanip>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "preprocess/database_builder.h"

namespace hfts::preprocess {
namespace {

class ProgressBar {
 public:
  ProgressBar(std::ostream& out, bool terminal, bool show, std::size_t total)
      : out_(&out), terminal_(terminal && show), show_(show), total_(total) {}

  void done(const BatchOutcome& outcome) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++finished_;
    for (const std::string& w : outcome.warnings) line("warning: " + w);
    if (!outcome.ok) line("error: " + outcome.error);
    if (!show_) return;
    const std::string status = outcome.name + (outcome.ok ? " ok" : " FAILED");
    if (!terminal_) {
      *out_ << "[" << finished_ << "/" << total_ << "] " << status << std::endl;
      return;
    }
    constexpr std::size_t kWidth = 30;
    const std::size_t filled = kWidth * finished_ / std::max<std::size_t>(total_, 1);
    *out_ << "\r[" << std::string(filled, '#') << std::string(kWidth - filled, ' ') << "] "
          << finished_ << "/" << total_ << " " << std::left << std::setw(24) << status
          << std::flush;
    if (finished_ == total_) *out_ << "\n";
  }

 private:
  void line(const std::string& text) {
    if (terminal_) *out_ << "\r\033[K";
    *out_ << text << "\n";
  }
  std::ostream* out_;
  bool terminal_;
  bool show_;
  std::size_t total_;
  std::size_t finished_ = 0;
  std::mutex mutex_;
};

BatchOutcome buildOne(const std::filesystem::path& mesh, const std::filesystem::path& outDir,
                      const db::BuildParameters& params, double density) {
  BatchOutcome outcome;
  outcome.mesh = mesh;
  outcome.name = mesh.stem().string();
  const auto start = std::chrono::steady_clock::now();
  try {
    const BuildResult result = buildObjectDatabaseFromFile(mesh, params, density);
    db::saveObjectDatabase(result.database, outDir / (outcome.name + ".h5"));
    describeBuild(result, outcome);
  } catch (const std::exception& e) {
    outcome.error = e.what();
  }
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return outcome;
}

}  // namespace

void describeBuild(const BuildResult& result, BatchOutcome& outcome) {
  outcome.warnings = result.warnings;
  outcome.samples = result.database.num_samples;
  outcome.contacts = result.database.numContacts();
  for (const auto& level : result.database.levels) outcome.nodes_per_level.push_back(level.size());
  outcome.convex_parts = result.database.geometry.convex_parts.size();
  outcome.convex_parts_seconds = result.times.convex_parts;
  outcome.ok = true;
}

std::vector<std::filesystem::path> collectMeshes(const std::filesystem::path& input) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(input, ec)) return {input};
  if (!std::filesystem::is_directory(input, ec))
    throw std::runtime_error("'" + input.string() + "' is neither a mesh file nor a directory");
  Assimp::Importer importer;
  std::vector<std::filesystem::path> meshes;
  for (const auto& entry : std::filesystem::directory_iterator(input)) {
    if (!entry.is_regular_file()) continue;
    const std::string ext = entry.path().extension().string();
    if (!ext.empty() && ext != ".json" && importer.IsExtensionSupported(ext))
      meshes.push_back(entry.path());
  }
  if (meshes.empty())
    throw std::runtime_error("directory '" + input.string() + "' holds no mesh file");
  std::sort(meshes.begin(), meshes.end());
  return meshes;
}

std::vector<BatchOutcome> runBatch(const std::vector<std::filesystem::path>& meshes,
                                   const std::filesystem::path& outDir,
                                   const db::BuildParameters& params, double density, unsigned jobs,
                                   std::ostream& log, bool logIsTerminal, bool showProgress) {
  std::vector<BatchOutcome> outcomes(meshes.size());
  // Two meshes with one stem would write one database: the later ones fail.
  std::map<std::string, std::size_t> firstWithStem;
  std::vector<bool> duplicate(meshes.size(), false);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const auto [it, inserted] = firstWithStem.emplace(meshes[i].stem().string(), i);
    duplicate[i] = !inserted;
  }
  ProgressBar bar(log, logIsTerminal, showProgress, meshes.size());
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next++; i < meshes.size(); i = next++) {
      if (duplicate[i]) {
        outcomes[i].mesh = meshes[i];
        outcomes[i].name = meshes[i].stem().string();
        outcomes[i].error = "mesh '" + meshes[i].string() + "': another mesh has the stem '" +
                            outcomes[i].name + "' and already writes " + outcomes[i].name + ".h5";
      } else {
        outcomes[i] = buildOne(meshes[i], outDir, params, density);
      }
      bar.done(outcomes[i]);
    }
  };
  const unsigned threads =
      std::max(1u, std::min<unsigned>(jobs, static_cast<unsigned>(meshes.size())));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  return outcomes;
}

void printSummaryTable(std::ostream& out, const std::vector<BatchOutcome>& outcomes) {
  std::size_t width = 6;
  for (const BatchOutcome& o : outcomes) width = std::max(width, o.name.size());
  out << std::left << std::setw(static_cast<int>(width) + 2) << "object" << std::right
      << std::setw(10) << "contacts" << std::setw(10) << "samples"
      << "  " << std::left << std::setw(18) << "nodes per level" << std::right << std::setw(6)
      << "parts" << std::setw(11) << "parts (s)" << std::setw(10) << "time (s)"
      << "  status\n";
  for (const BatchOutcome& o : outcomes) {
    std::ostringstream nodes;
    for (std::size_t l = 0; l < o.nodes_per_level.size(); ++l)
      nodes << (l ? "/" : "") << o.nodes_per_level[l];
    const auto ifOk = [&](const std::string& text) { return o.ok ? text : std::string("-"); };
    out << std::left << std::setw(static_cast<int>(width) + 2) << o.name << std::right
        << std::setw(10) << ifOk(std::to_string(o.contacts)) << std::setw(10)
        << ifOk(std::to_string(o.samples)) << "  " << std::left << std::setw(18)
        << ifOk(nodes.str()) << std::right << std::setw(6) << ifOk(std::to_string(o.convex_parts))
        << std::fixed << std::setprecision(2) << std::setw(11) << o.convex_parts_seconds
        << std::setw(10) << o.seconds << "  " << (o.ok ? "ok" : "FAILED") << "\n";
  }
  const auto failed =
      std::count_if(outcomes.begin(), outcomes.end(), [](const BatchOutcome& o) { return !o.ok; });
  out << outcomes.size() - static_cast<std::size_t>(failed) << " built, " << failed << " failed\n";
}

}  // namespace hfts::preprocess
