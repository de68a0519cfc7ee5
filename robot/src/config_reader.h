#pragma once
// Private to robot/src: reading a robot config's keys with errors that
// name the key (robot_model.cpp).

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "json_numbers.h"
#include "robot/robot_model.h"

namespace hfts::robot {

/// Reads the config's keys; every error is "<source>: <field>: <problem>"
/// with the key's path in the config as the field.
class ConfigReader {
 public:
  ConfigReader(const nlohmann::json& root, std::string what, std::string prefix = {})
      : root_(root), what_(std::move(what)), prefix_(std::move(prefix)) {}

  bool has(const char* key) const { return root_.contains(key); }
  const nlohmann::json& at(const char* key) const {
    if (!root_.contains(key)) failAt(key, "is required");
    return root_.at(key);
  }
  std::string string(const char* key) const {
    const nlohmann::json& v = at(key);
    if (!v.is_string()) failAt(key, "must be a string");
    return v.get<std::string>();
  }
  std::vector<std::string> strings(const char* key) const {
    const nlohmann::json& v = at(key);
    if (!v.is_array()) failAt(key, "must be an array of names");
    std::vector<std::string> out;
    for (const nlohmann::json& item : v) {
      if (!item.is_string()) failAt(key, "must be an array of names");
      out.push_back(item.get<std::string>());
    }
    return out;
  }
  Eigen::VectorXd numbers(const char* key, Eigen::Index expected) const {
    std::string problem;
    std::optional<Eigen::VectorXd> values = finiteNumbers(at(key), expected, problem);
    if (!values) failAt(key, problem);
    return *values;
  }
  double number(const char* key) const {
    const nlohmann::json& v = at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) failAt(key, "must be a finite number");
    return v.get<double>();
  }
  /// A problem of the key `key` (a path below this reader's prefix).
  [[noreturn]] void failAt(const std::string& key, const std::string& problem) const {
    throw ModelError(what_ + ": " + prefix_ + key + ": " + problem);
  }
  /// A problem that is not one key's (the URDF's structure).
  [[noreturn]] void fail(const std::string& problem) const {
    throw ModelError(what_ + ": " + problem);
  }

 private:
  const nlohmann::json& root_;
  std::string what_;
  std::string prefix_;  // the path of root_ in the config, e.g. "fingertips[1]."
};

}  // namespace hfts::robot
