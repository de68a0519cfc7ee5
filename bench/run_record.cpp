#include "run_record.h"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"

namespace hfts::bench {
namespace {

constexpr const char* kHeader =
    "scene,object,algorithm,seed,success,failure,time,gs,vgs,gns,epsilon,path_length,"
    "collision_checks,cpu_time,placement,rejected_unstable,rejected_no_arm_ik,"
    "rejected_out_of_hand_reach,rejected_colliding,rejected_closing_blocked,fingertip_error,"
    "planned_epsilon,penetration,rejected_no_pad_contact,rejected_weak_at_contacts,planned,held,"
    "held_fraction,physics_failure,lift,dropped_goals,physics_checks,physics_time,"
    "rejected_paths,final_check_time,certificate_queries,clearance";

/// RFC 4180 quoting; names from file stems may hold commas or quotes.
std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

/// One line of an RFC 4180 file (without its line break) split into its
/// fields; quoted fields may hold commas and doubled quotes, not line
/// breaks. Returns what is wrong, empty when nothing is.
std::string splitCsvLine(const std::string& line, std::vector<std::string>& fields) {
  fields.assign(1, std::string());
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == ',') {
      fields.emplace_back();
    } else if (line[i] == '"' && fields.back().empty()) {
      for (++i;; ++i) {
        if (i >= line.size()) return "a quote is not closed";
        if (line[i] != '"') {
          fields.back() += line[i];
        } else if (i + 1 < line.size() && line[i + 1] == '"') {
          fields.back() += '"';
          ++i;
        } else {
          break;
        }
      }
      if (i + 1 < line.size() && line[i + 1] != ',')
        return "text follows a closing quote in field " + std::to_string(fields.size());
    } else {
      fields.back() += line[i];
    }
  }
  return {};
}

/// The next line of `in` without its line break (LF or CRLF); false at the end.
bool nextLine(std::istream& in, std::string& line) {
  if (!std::getline(in, line)) return false;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

void writeRow(std::ostream& out, const RunRecord& r) {
  const planner::PlanStatistics& s = r.stats;
  out << csvField(r.scene) << ',' << csvField(r.object) << ',' << csvField(r.algorithm) << ','
      << r.seed << ',' << (r.success ? 1 : 0) << ',' << r.failure << ',' << std::fixed
      << std::setprecision(6) << s.planning_time << ',' << s.goal_sampling_calls << ','
      << s.valid_goal_samples << ',' << s.hfts_nodes_explored << ',';
  // A run without a plan has no grasp and no path: empty fields, not
  // zeros that would pull averages down.
  if (r.planned)
    out << std::setprecision(8) << r.epsilon << ',' << s.path_length_smoothed;
  else
    out << ',';
  out << ',' << s.collision_checks << ',' << std::setprecision(6) << r.cpu_time << ','
      << csvField(r.placement);
  const planner::GraspRejections& rejected = s.rejected;
  for (const std::uint64_t count :
       {rejected.unstable, rejected.no_arm_ik, rejected.out_of_hand_reach, rejected.colliding,
        rejected.closing_blocked})
    out << ',' << count;
  out << ',';
  if (r.planned)
    out << std::setprecision(8) << r.fingertip_error << ',' << r.planned_epsilon << ','
        << r.penetration;
  else
    out << ",,";
  out << ',' << rejected.no_pad_contact << ',' << rejected.weak_at_contacts << ','
      << (r.planned ? 1 : 0) << ',';
  if (r.held)
    out << (*r.held ? 1 : 0) << ',' << std::setprecision(4) << r.held_fraction << ','
        << csvField(r.physics_failure) << ',' << csvField(r.lift);
  else
    out << ",,,";
  out << ',' << s.dropped_goals << ',' << s.physics_checks << ',' << std::setprecision(6)
      << s.physics_time << ',' << s.rejected_paths << ',' << s.final_check_time << ','
      << s.certificate_queries << ',';
  if (r.clearance) out << std::setprecision(8) << *r.clearance;
  out << '\n';
}

}  // namespace

RunRecord makeRunRecord(const CaseName& c, const std::string& algorithm, std::uint64_t seed,
                        const planner::PlanResult& result, double cpuTime) {
  RunRecord r;
  r.scene = c.scene;
  r.object = c.object;
  r.placement = c.placement;
  r.algorithm = algorithm;
  r.seed = seed;
  r.planned = result.success;
  r.success = result.success && (!result.validation || result.validation->holds());
  r.failure = r.planned && !r.success ? "not_held" : planner::toString(result.failure);
  if (result.validation && result.validation->physics) {
    const physics::GraspVerdict& v = *result.validation->physics;
    r.held = v.held && result.validation->check.valid();
    r.held_fraction = v.held_fraction;
    // The plan's lift when it has one (the simulation followed it).
    r.lift = result.lift ? result.lift->direction : v.lift_direction;
    r.physics_failure = result.validation->check.problem;
    for (const physics::TrialResult& t : v.trials)
      if (r.physics_failure.empty() && !t.held) r.physics_failure = t.name + ": " + t.failure;
  }
  r.cpu_time = cpuTime;
  r.epsilon = result.grasp.epsilon;
  r.fingertip_error = result.grasp.fingertip_error;
  r.planned_epsilon = result.grasp.planned_epsilon;
  r.penetration = result.grasp.penetration;
  r.clearance = result.clearance;
  r.stats = result.stats;
  return r;
}

void writeCsvAtomically(const std::filesystem::path& out, const std::vector<RunRecord>& records) {
  std::ostringstream text;
  text << kHeader << '\n';
  for (const RunRecord& r : records) writeRow(text, r);
  core::writeFileAtomically(out, text.str());
}

void writeHoldabilityCsv(const std::filesystem::path& out,
                         const std::vector<HoldabilityRecord>& records) {
  std::ostringstream text;
  text << "scene,object,placement,holdable,climbs,leaves,stable,reached,hand_clear,epsilon,seconds,"
          "reason\n";
  for (const HoldabilityRecord& r : records) {
    const Holdability& g = r.answer;
    text << csvField(r.name.scene) << ',' << csvField(r.name.object) << ','
         << csvField(r.name.placement) << ',' << (g.holdable ? 1 : 0) << ',' << g.climbs << ','
         << g.leaves << ',' << g.stable << ',' << g.reached << ',' << g.hand_clear << ','
         << std::fixed << std::setprecision(8) << g.epsilon << ',' << std::setprecision(4)
         << r.seconds << ',' << csvField(g.reason) << '\n';
  }
  core::writeFileAtomically(out, text.str());
}

HoldabilityFile::HoldabilityFile(const std::filesystem::path& path) : path_(path) {
  const std::string name = "holdability file '" + path.string() + "'";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(name + ": cannot be read");
  std::string line;
  std::vector<std::string> fields;
  if (!nextLine(in, line)) throw std::runtime_error(name + ": is empty");
  if (const std::string wrong = splitCsvLine(line, fields); !wrong.empty())
    throw std::runtime_error(name + " line 1: " + wrong);
  const auto column = [&](const std::string& wanted) {
    const auto at = std::find(fields.begin(), fields.end(), wanted);
    if (at == fields.end())
      throw std::runtime_error(name + ": no '" + wanted +
                               "' column (hfts-bench --holdability writes the file)");
    return static_cast<std::size_t>(at - fields.begin());
  };
  const std::size_t scene = column("scene"), object = column("object"),
                    placement = column("placement"), holdable = column("holdable");
  const std::size_t needed = std::max({scene, object, placement, holdable}) + 1;
  for (int number = 2; nextLine(in, line); ++number) {
    if (line.empty()) continue;
    const std::string where = name + " line " + std::to_string(number);
    if (const std::string wrong = splitCsvLine(line, fields); !wrong.empty())
      throw std::runtime_error(where + ": " + wrong);
    if (fields.size() < needed)
      throw std::runtime_error(where + ": " + std::to_string(fields.size()) +
                               " fields, the columns need at least " + std::to_string(needed));
    if (fields[holdable] != "0" && fields[holdable] != "1")
      throw std::runtime_error(where + ": holdable is '" + fields[holdable] + "', not 0 or 1");
    if (!answers_
             .emplace(std::make_tuple(fields[scene], fields[object], fields[placement]),
                      fields[holdable] == "1")
             .second)
      throw std::runtime_error(where + ": " + fields[scene] + "/" + fields[object] + " at " +
                               fields[placement] + " is answered twice");
  }
}

bool HoldabilityFile::holdable(const CaseName& c) const {
  const auto at = answers_.find(std::make_tuple(c.scene, c.object, c.placement));
  if (at == answers_.end())
    throw std::runtime_error("holdability file '" + path_.string() + "' has no answer for " +
                             c.scene + "/" + c.object + " at " + c.placement);
  return at->second;
}

}  // namespace hfts::bench
