#pragma once
// Reading a JSON array of numbers, shared by the robot config and scene
// readers (private to robot/src).

#include <nlohmann/json.hpp>

#include <Eigen/Core>

#include <cmath>
#include <optional>
#include <string>

namespace hfts::robot {

/// The values of `v` when it is an array of `n` finite numbers (any count
/// for n < 0); otherwise nothing, and `problem` says what is wrong.
inline std::optional<Eigen::VectorXd> finiteNumbers(const nlohmann::json& v, Eigen::Index n,
                                                    std::string& problem) {
  if (!v.is_array() || (n >= 0 && static_cast<Eigen::Index>(v.size()) != n)) {
    problem = n >= 0 ? "must be an array of " + std::to_string(n) + " numbers"
                     : "must be an array of numbers";
    return std::nullopt;
  }
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>())) {
      problem = "must hold finite numbers";
      return std::nullopt;
    }
    out(static_cast<Eigen::Index>(i)) = v[i].get<double>();
  }
  return out;
}

}  // namespace hfts::robot
