#include "grasp/grasp_quality_json.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <set>

#include "core/invalid_argument.h"

namespace hfts::grasp {
namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& field, const std::string& problem) {
  throw InvalidArgument(field, problem);
}

Eigen::Vector3d vector3(const json& v, const std::string& name) {
  if (!v.is_array() || v.size() != 3) fail(name, "must be an array of 3 numbers");
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) {
    if (!v[static_cast<std::size_t>(i)].is_number()) fail(name, "must hold numbers");
    out(i) = v[static_cast<std::size_t>(i)].get<double>();
  }
  if (!out.allFinite()) fail(name, "must be finite");
  return out;
}

double number(const json& root, const char* key, double fallback) {
  if (!root.contains(key)) return fallback;
  const json& v = root.at(key);
  if (!v.is_number() || !std::isfinite(v.get<double>())) fail(key, "must be a finite number");
  return v.get<double>();
}

}  // namespace

GraspQualityRequest graspQualityRequestFromJson(const std::string& text) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    fail("request", std::string("not valid JSON: ") + e.what());
  }
  if (!root.is_object()) fail("request", "must be a JSON object");
  static const std::set<std::string> known = {"contacts",          "normals",  "center",
                                              "torque_scale",      "friction", "cone_edges",
                                              "torsional_friction"};
  for (const auto& item : root.items())
    if (!known.count(item.key())) fail(item.key(), "unknown field");
  if (!root.contains("contacts") || !root["contacts"].is_array() || root["contacts"].empty())
    fail("contacts", "must be a non-empty array");
  const json& contacts = root["contacts"];
  if (contacts.size() > 64) fail("contacts", "holds more than 64 contacts");
  GraspQualityRequest r;
  r.positions.resize(3, static_cast<Eigen::Index>(contacts.size()));
  r.normals.resize(3, r.positions.cols());
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const std::string where = "contacts[" + std::to_string(i) + "]";
    if (!contacts[i].is_object() || !contacts[i].contains("position") ||
        !contacts[i].contains("normal"))
      fail(where, "must have 'position' and 'normal'");
    r.positions.col(static_cast<Eigen::Index>(i)) =
        vector3(contacts[i]["position"], where + ".position");
    const Eigen::Vector3d n = vector3(contacts[i]["normal"], where + ".normal");
    if (std::abs(n.norm() - 1.0) > 1e-6) fail(where + ".normal", "must be a unit vector");
    r.normals.col(static_cast<Eigen::Index>(i)) = n;
  }
  if (root.contains("normals")) {
    const json& d = root["normals"];
    if (d == "inward")
      r.direction = NormalDirection::kInward;
    else if (d == "outward")
      r.direction = NormalDirection::kOutward;
    else
      fail("normals", "must be \"inward\" or \"outward\"");
  }
  if (root.contains("center")) r.center = vector3(root["center"], "center");
  r.torque_scale = number(root, "torque_scale", r.torque_scale);
  r.friction = number(root, "friction", r.friction);
  r.torsional_friction = number(root, "torsional_friction", r.torsional_friction);
  const double edges = number(root, "cone_edges", r.cone_edges);
  if (edges != std::floor(edges) || edges < 3 || edges > 64)
    fail("cone_edges", "must be an integer in 3..64");
  r.cone_edges = static_cast<int>(edges);
  const bool soft = r.torsional_friction > 0;
  const std::size_t perContact = static_cast<std::size_t>(r.cone_edges) + (soft ? 2 : 0);
  if (contacts.size() * perContact > kMaxQualityWrenches)
    fail("cone_edges", std::string("contacts x cone_edges") +
                           (soft ? " (+ 2 torsions per soft contact)" : "") + " must be at most " +
                           std::to_string(kMaxQualityWrenches) + ", got " +
                           std::to_string(contacts.size()) + " x " + std::to_string(perContact));
  if (!(r.torque_scale > 0)) fail("torque_scale", "must be > 0");
  if (!(r.friction > 0)) fail("friction", "must be > 0");
  if (!(r.torsional_friction >= 0)) fail("torsional_friction", "must be >= 0");
  return r;
}

std::string graspQualityResultToJson(const GraspQualityResult& result) {
  return json{{"epsilon", result.epsilon}}.dump();
}

}  // namespace hfts::grasp
