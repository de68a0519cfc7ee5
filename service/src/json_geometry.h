#pragma once
// Vectors and poses in the project's JSON conventions (design.md): arrays
// of numbers, {"position": [x,y,z], "orientation": [x,y,z,w]}.

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

namespace hfts::service {

inline nlohmann::json vectorJson(const Eigen::VectorXd& v) {
  return nlohmann::json(std::vector<double>(v.data(), v.data() + v.size()));
}

inline nlohmann::json poseJson(const Eigen::Isometry3d& p) {
  const Eigen::Quaterniond q(p.linear());
  return {{"position", vectorJson(p.translation())}, {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
}

}  // namespace hfts::service
