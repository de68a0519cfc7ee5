#pragma once
// Checked access to the members of a JSON object: every error is an
// RpcError(kInvalidParams) whose message starts with the field's path.

#include <Eigen/Geometry>
#include <nlohmann/json_fwd.hpp>

#include <cstdint>
#include <initializer_list>
#include <string>

namespace hfts::service {

/// The members of one JSON object at `path` ("" for the params object
/// itself, "object_pose" for a nested one). Keeps a reference: the object
/// must outlive this.
class JsonFields {
 public:
  /// Throws unless `object` is a JSON object.
  JsonFields(const nlohmann::json& object, std::string path);

  bool has(const char* key) const;
  /// The member; throws when it is missing.
  const nlohmann::json& at(const char* key) const;
  /// Throws for a member whose name is not in `known`.
  void allowOnly(std::initializer_list<const char*> known) const;
  /// The path of a member ("object_pose.position").
  std::string path(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

  std::string string(const char* key) const;
  bool boolean(const char* key) const;
  /// A string that is safe as a file stem (planner::isSafeName).
  std::string name(const char* key) const;
  double finite(const char* key) const;
  double positive(const char* key) const;
  std::uint64_t unsignedInteger(const char* key) const;
  int positiveInt(const char* key) const;
  /// An array of exactly `n` finite numbers.
  Eigen::VectorXd numbers(const char* key, Eigen::Index n) const;
  /// {"position": [x,y,z], "orientation": [x,y,z,w]} with a quaternion of
  /// non-zero norm (normalised).
  Eigen::Isometry3d pose(const char* key) const;

 private:
  const nlohmann::json& object_;
  std::string path_;
};

}  // namespace hfts::service
