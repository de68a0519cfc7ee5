#pragma once
// Human-readable output of hfts-client, one function per method result.

#include <nlohmann/json_fwd.hpp>

#include <iosfwd>

namespace hfts::client {

/// Server name and version, robot and joints, objects, scenes, workers and limits.
void printInfo(const nlohmann::json& info, std::ostream& out);
/// One row per object database, then the skipped files.
void printObjects(const nlohmann::json& objects, std::ostream& out);
/// One row per scene.
void printScenes(const nlohmann::json& scenes, std::ostream& out);
/// Outcome, grasp (epsilon, reachability, contacts, hand posture), path
/// (waypoints, length), timing and statistics.
void printPlan(const nlohmann::json& plan, std::ostream& out);
void printQuality(const nlohmann::json& quality, std::ostream& out);
/// A plan's trajectory as CSV: a header time_from_start, the joint names
/// (positions), <joint>_velocity and <joint>_acceleration for each, then
/// one row per point. Throws std::runtime_error when the plan has none.
void writeTrajectoryCsv(const nlohmann::json& plan, std::ostream& out);

}  // namespace hfts::client
