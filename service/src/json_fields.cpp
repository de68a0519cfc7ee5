#include "json_fields.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>

#include "robot/scene.h"
#include "service/rpc_error.h"

namespace hfts::service {

using nlohmann::json;

JsonFields::JsonFields(const json& object, std::string path)
    : object_(object), path_(std::move(path)) {
  if (!object_.is_object())
    throwInvalidParam(path_.empty() ? "params" : path_, "must be an object");
}

bool JsonFields::has(const char* key) const {
  return object_.contains(key);
}

const json& JsonFields::at(const char* key) const {
  const auto it = object_.find(key);
  if (it == object_.end()) fail(key, "is required");
  return *it;
}

void JsonFields::allowOnly(std::initializer_list<const char*> known) const {
  for (const auto& item : object_.items()) {
    bool ok = false;
    for (const char* k : known) ok = ok || item.key() == k;
    if (!ok) fail(item.key(), "unknown field");
  }
}

std::string JsonFields::path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void JsonFields::fail(const std::string& key, const std::string& problem) const {
  throwInvalidParam(path(key), problem);
}

std::string JsonFields::string(const char* key) const {
  const json& v = at(key);
  if (!v.is_string()) fail(key, "must be a string");
  return v.get<std::string>();
}

bool JsonFields::boolean(const char* key) const {
  const json& v = at(key);
  if (!v.is_boolean()) fail(key, "must be true or false");
  return v.get<bool>();
}

std::string JsonFields::name(const char* key) const {
  std::string value = string(key);
  if (!robot::isSafeName(value))
    fail(key, "'" + value +
                  "' is not a valid name (letters, digits, _ - . only, no path characters, "
                  "at most 128)");
  return value;
}

double JsonFields::finite(const char* key) const {
  const json& v = at(key);
  if (!v.is_number()) fail(key, "must be a number");
  const double value = v.get<double>();
  if (!std::isfinite(value)) fail(key, "must be finite");
  return value;
}

double JsonFields::positive(const char* key) const {
  const double value = finite(key);
  if (!(value > 0)) fail(key, "must be > 0, got " + json(value).dump());
  return value;
}

std::uint64_t JsonFields::unsignedInteger(const char* key) const {
  const json& v = at(key);
  if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<std::int64_t>() >= 0))
    fail(key, "must be an integer >= 0");
  return v.get<std::uint64_t>();
}

int JsonFields::positiveInt(const char* key) const {
  const std::uint64_t value = unsignedInteger(key);
  if (value < 1 || value > static_cast<std::uint64_t>(std::numeric_limits<int>::max()))
    fail(key, "must be an integer >= 1");
  return static_cast<int>(value);
}

Eigen::VectorXd JsonFields::numbers(const char* key, Eigen::Index n) const {
  const json& v = at(key);
  if (!v.is_array() || static_cast<Eigen::Index>(v.size()) != n)
    fail(key, "must be an array of " + std::to_string(n) + " numbers" +
                  (v.is_array() ? ", got " + std::to_string(v.size()) : std::string()));
  Eigen::VectorXd out(n);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string where = std::string(key) + "[" + std::to_string(i) + "]";
    if (!v[i].is_number()) fail(where, "must be a number");
    out(static_cast<Eigen::Index>(i)) = v[i].get<double>();
    if (!std::isfinite(out(static_cast<Eigen::Index>(i)))) fail(where, "must be finite");
  }
  return out;
}

Eigen::Isometry3d JsonFields::pose(const char* key) const {
  const JsonFields p(at(key), path(key));
  p.allowOnly({"position", "orientation"});
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.translation() = p.numbers("position", 3);
  const Eigen::VectorXd q = p.numbers("orientation", 4);  // x, y, z, w (ROS order)
  if (q.norm() < 1e-9) p.fail("orientation", "is a quaternion of zero norm");
  out.linear() = Eigen::Quaterniond(q(3), q(0), q(1), q(2)).normalized().toRotationMatrix();
  return out;
}

}  // namespace hfts::service
