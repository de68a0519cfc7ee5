// Loading a robot from URDF (urdfdom) and its config file (JSON).
#include "robot/robot_model.h"

#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

#include "config_reader.h"

namespace hfts::robot {
namespace {

using nlohmann::json;

std::string readFile(const std::filesystem::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(what + ": cannot read '" + path.string() + "'");
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

Eigen::Isometry3d toIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() << pose.position.x, pose.position.y, pose.position.z;
  t.linear() =
      Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
          .normalized()
          .toRotationMatrix();
  return t;
}

CollisionShape toShape(const urdf::Collision& collision, const std::string& where) {
  CollisionShape shape;
  shape.origin = toIsometry(collision.origin);
  const urdf::GeometrySharedPtr& g = collision.geometry;
  if (!g) throw ModelError(where + ": collision without geometry");
  switch (g->type) {
    case urdf::Geometry::BOX: {
      const auto& box = dynamic_cast<const urdf::Box&>(*g);
      shape.type = CollisionShape::Type::kBox;
      shape.size << box.dim.x, box.dim.y, box.dim.z;
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = dynamic_cast<const urdf::Cylinder&>(*g);
      shape.type = CollisionShape::Type::kCylinder;
      shape.size << cylinder.radius, cylinder.length, 0.0;
      break;
    }
    case urdf::Geometry::SPHERE:
      shape.type = CollisionShape::Type::kSphere;
      shape.size << dynamic_cast<const urdf::Sphere&>(*g).radius, 0.0, 0.0;
      break;
    default:
      throw ModelError(where + ": only box, cylinder and sphere collision shapes are supported");
  }
  if (!shape.size.allFinite() || (shape.size.array() < 0).any() || shape.size[0] <= 0)
    throw ModelError(where + ": collision shape with invalid size");
  return shape;
}

/// A link's <inertial>; none for a link without one, and for a frame (a
/// link without collision geometry) whose mass is 0.
std::optional<Inertial> toInertial(const urdf::InertialSharedPtr& in, bool frame,
                                   const std::string& where) {
  if (!in || (frame && in->mass == 0.0)) return std::nullopt;
  Inertial out;
  out.mass = in->mass;
  out.origin = toIsometry(in->origin);
  out.inertia << in->ixx, in->ixy, in->ixz, in->ixy, in->iyy, in->iyz, in->ixz, in->iyz, in->izz;
  if (!(out.mass > 0.0) || !std::isfinite(out.mass) || !out.inertia.allFinite() ||
      (out.inertia.diagonal().array() <= 0.0).any())
    throw ModelError(where + ": <inertial> needs a positive mass and positive moments of inertia");
  return out;
}

}  // namespace

Eigen::Vector3d halfExtents(const CollisionShape& shape) {
  switch (shape.type) {
    case CollisionShape::Type::kBox:
      return shape.size / 2;
    case CollisionShape::Type::kCylinder:
      return {shape.size.x(), shape.size.x(), shape.size.y() / 2};
    case CollisionShape::Type::kSphere:
    default:
      return Eigen::Vector3d::Constant(shape.size.x());
  }
}

/// Builds a RobotModel step by step; every step validates what it adds.
class RobotModelBuilder {
 public:
  RobotModelBuilder(const urdf::ModelInterface& urdf, const json& config, const std::string& what,
                    const std::string& srdf)
      : urdf_(urdf), config_(config, what), what_(what), srdf_(srdf) {}

  RobotModel build() {
    model_.name_ = config_.string("name");
    addTree();
    addDofs();
    addLimitsAndPostures();
    addFingertips();
    addContactModel();
    addHandMapSettings();
    addPlannerDefaults();
    addHandActuation();
    addDisabledCollisions();
    markHandLinks();
    model_.countJointsApart();
    return std::move(model_);
  }

 private:
  /// Breadth-first from the base link, so parents precede children.
  void addTree() {
    const std::string base = config_.string("base_link");
    if (!urdf_.getLink(base)) config_.failAt("base_link", "'" + base + "' is not in the URDF");
    std::deque<std::pair<urdf::LinkConstSharedPtr, int>> queue{{urdf_.getLink(base), -1}};
    while (!queue.empty()) {
      const auto [link, parentJoint] = queue.front();
      queue.pop_front();
      const int index = static_cast<int>(model_.links_.size());
      const std::string where = what_ + ": link '" + link->name + "'";
      Link out{link->name,
               parentJoint,
               {},
               toInertial(link->inertial, link->collision_array.empty(), where),
               nullptr};
      for (const auto& collision : link->collision_array)
        out.shapes.push_back(toShape(*collision, where));
      model_.links_.push_back(std::move(out));
      if (parentJoint >= 0)
        model_.joints_[static_cast<std::size_t>(parentJoint)].child_link = index;
      for (const auto& child : link->child_joints) {
        Joint joint;
        joint.name = child->name;
        joint.parent_link = index;
        joint.origin = toIsometry(child->parent_to_joint_origin_transform);
        joint.axis = Eigen::Vector3d(child->axis.x, child->axis.y, child->axis.z);
        joint.type = jointType(*child);
        if (child->limits && joint.type != Joint::Type::kFixed)
          joint.effort = child->limits->effort;
        if (joint.type != Joint::Type::kFixed) {
          if (joint.axis.norm() < 1e-9) config_.fail("joint '" + child->name + "' has no axis");
          joint.axis.normalize();
        }
        precomputeMotion(joint);
        model_.joints_.push_back(joint);
        queue.emplace_back(urdf_.getLink(child->child_link_name),
                           static_cast<int>(model_.joints_.size()) - 1);
      }
    }
  }

  Joint::Type jointType(const urdf::Joint& joint) const {
    switch (joint.type) {
      case urdf::Joint::FIXED:
        return Joint::Type::kFixed;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        return Joint::Type::kRevolute;
      case urdf::Joint::PRISMATIC:
        return Joint::Type::kPrismatic;
      default:
        config_.fail("joint '" + joint.name + "' has an unsupported type (floating/planar)");
    }
  }

  int jointIndex(const std::string& name) const {
    for (std::size_t j = 0; j < model_.joints_.size(); ++j)
      if (model_.joints_[j].name == name) return static_cast<int>(j);
    return -1;
  }

  void addDofs() {
    const std::vector<std::string> arm = config_.strings("arm_joints");
    // An arm without a hand (motion-only) lists no hand joints.
    const std::vector<std::string> hand =
        config_.has("hand_joints") ? config_.strings("hand_joints") : std::vector<std::string>{};
    if (arm.empty()) config_.failAt("arm_joints", "is empty");
    model_.num_arm_dofs_ = static_cast<int>(arm.size());
    model_.dof_names_ = arm;
    model_.dof_names_.insert(model_.dof_names_.end(), hand.begin(), hand.end());
    for (std::size_t d = 0; d < model_.dof_names_.size(); ++d) {
      const std::string key = d < arm.size() ? "arm_joints" : "hand_joints";
      const int j = jointIndex(model_.dof_names_[d]);
      if (j < 0)
        config_.failAt(key, "joint '" + model_.dof_names_[d] +
                                "' is not in the URDF (reachable from the base link)");
      Joint& joint = model_.joints_[static_cast<std::size_t>(j)];
      if (joint.type == Joint::Type::kFixed)
        config_.failAt(key, "joint '" + joint.name + "' is fixed");
      if (joint.dof >= 0) config_.failAt(key, "joint '" + joint.name + "' is listed twice");
      joint.dof = static_cast<int>(d);
    }
    const std::map<std::string, double> held = heldJoints();
    for (Joint& joint : model_.joints_) {
      if (joint.type == Joint::Type::kFixed || joint.dof >= 0) continue;
      const urdf::JointConstSharedPtr source = urdf_.getJoint(joint.name);
      if (const auto it = held.find(joint.name); it != held.end()) {
        hold(joint, it->second);
        continue;
      }
      if (!source->mimic)
        config_.fail("joint '" + joint.name +
                     "' is movable but neither listed, held (fixed_joints) nor a mimic joint");
      const int mimicked = jointIndex(source->mimic->joint_name);
      if (const auto it = held.find(source->mimic->joint_name); it != held.end()) {
        hold(joint, source->mimic->multiplier * it->second + source->mimic->offset);
        continue;
      }
      if (mimicked < 0 || model_.joints_[static_cast<std::size_t>(mimicked)].dof < 0)
        config_.fail("joint '" + joint.name + "' mimics '" + source->mimic->joint_name +
                     "', which is not a listed joint");
      joint.dof = model_.joints_[static_cast<std::size_t>(mimicked)].dof;
      joint.multiplier = source->mimic->multiplier;
      joint.offset = source->mimic->offset;
    }
  }

  /// The config's optional `fixed_joints`: movable URDF joints held at a
  /// value (within their limits), not part of the configuration.
  std::map<std::string, double> heldJoints() const {
    std::map<std::string, double> out;
    if (!config_.has("fixed_joints")) return out;
    const json& held = config_.at("fixed_joints");
    if (!held.is_object())
      config_.failAt("fixed_joints", "must be an object of joint values by name");
    for (const auto& item : held.items()) {
      const std::string key = "fixed_joints." + item.key();
      const int j = jointIndex(item.key());
      if (j < 0) config_.failAt(key, "is not a joint of the URDF (reachable from the base link)");
      const Joint& joint = model_.joints_[static_cast<std::size_t>(j)];
      if (joint.type == Joint::Type::kFixed) config_.failAt(key, "the joint is fixed already");
      if (joint.dof >= 0) config_.failAt(key, "the joint is listed in arm_joints or hand_joints");
      if (!item.value().is_number() || !std::isfinite(item.value().get<double>()))
        config_.failAt(key, "must be a finite number");
      const double v = item.value().get<double>();
      const urdf::JointConstSharedPtr source = urdf_.getJoint(item.key());
      if (source->limits && source->type != urdf::Joint::CONTINUOUS &&
          !(v >= source->limits->lower - 1e-9 && v <= source->limits->upper + 1e-9))
        config_.failAt(key, "outside the joint's limits [" + std::to_string(source->limits->lower) +
                                ", " + std::to_string(source->limits->upper) + "]");
      out[item.key()] = v;
    }
    return out;
  }

  /// A movable joint held at value v: a fixed joint whose origin carries
  /// the motion.
  static void hold(Joint& joint, double v) {
    if (joint.type == Joint::Type::kRevolute)
      joint.origin = joint.origin * Eigen::AngleAxisd(v, joint.axis);
    else
      joint.origin = joint.origin * Eigen::Translation3d(v * joint.axis);
    joint.type = Joint::Type::kFixed;
    joint.effort = 0.0;
    joint.rotation_cos.setZero();
    joint.rotation_sin.setZero();
    joint.slide.setZero();
    precomputeMotion(joint);
  }

  void addLimitsAndPostures() {
    const auto n = static_cast<Eigen::Index>(model_.dof_names_.size());
    model_.lower_.resize(n);
    model_.upper_.resize(n);
    model_.velocity_.resize(n);
    for (Eigen::Index d = 0; d < n; ++d) {
      const auto& name = model_.dof_names_[static_cast<std::size_t>(d)];
      const urdf::JointConstSharedPtr joint = urdf_.getJoint(name);
      if (!joint->limits || joint->type == urdf::Joint::CONTINUOUS)
        config_.fail("joint '" + name + "' needs position limits");
      model_.lower_(d) = joint->limits->lower;
      model_.upper_(d) = joint->limits->upper;
      model_.velocity_(d) = joint->limits->velocity;
      if (!(model_.lower_(d) < model_.upper_(d)))
        config_.fail("joint '" + name + "' has an empty range");
      if (!(model_.velocity_(d) > 0.0) || !std::isfinite(model_.velocity_(d)))
        config_.fail("joint '" + name + "' needs a positive velocity limit");
    }
    if (config_.has("max_accelerations")) {
      model_.acceleration_ = config_.numbers("max_accelerations", n);
      if ((model_.acceleration_.array() <= 0).any())
        config_.failAt("max_accelerations", "must be positive");
    }
    model_.weights_ = config_.numbers("dof_weights", n);
    if ((model_.weights_.array() <= 0).any()) config_.failAt("dof_weights", "must be positive");
    model_.home_ = config_.numbers("home", n);
    std::string why;
    if (!model_.withinLimits(model_.home_, 1e-9, &why)) config_.failAt("home", why);
    const bool hand = n > model_.num_arm_dofs_;
    // An arm without a hand needs none of the hand's keys; its palm is the
    // flange unless the config names another link.
    model_.hand_open_ = hand || config_.has("hand_open")
                            ? config_.numbers("hand_open", n - model_.num_arm_dofs_)
                            : Eigen::VectorXd();
    Eigen::VectorXd open = model_.home_;
    open.tail(n - model_.num_arm_dofs_) = model_.hand_open_;
    if (!model_.withinLimits(open, 1e-9, &why)) config_.failAt("hand_open", why);
    model_.pregrasp_offset_ =
        hand || config_.has("pregrasp_offset") ? config_.number("pregrasp_offset") : 0.0;
    model_.flange_link_ = linkOf("flange_link");
    model_.palm_link_ =
        hand || config_.has("palm_link") ? linkOf("palm_link") : model_.flange_link_;
  }

  int linkOf(const char* key) const {
    const std::string name = config_.string(key);
    for (std::size_t l = 0; l < model_.links_.size(); ++l)
      if (model_.links_[l].name == name) return static_cast<int>(l);
    config_.failAt(key, "names link '" + name + "', which is not in the URDF");
  }

  void addFingertips() {
    const bool hand = model_.numHandDofs() > 0;
    if (!hand && !config_.has("fingertips")) return;  // an arm without a hand
    if (!hand)
      config_.failAt("fingertips", "need hand_joints (an arm without a hand has no fingertips)");
    const json& tips = config_.at("fingertips");
    if (!tips.is_array() || tips.empty()) config_.failAt("fingertips", "must be a non-empty array");
    for (std::size_t i = 0; i < tips.size(); ++i) {
      const json& tip = tips[i];
      if (!tip.is_object())
        config_.failAt("fingertips[" + std::to_string(i) + "]", "must be a JSON object");
      const ConfigReader reader(tip, what_, "fingertips[" + std::to_string(i) + "].");
      Fingertip f;
      f.name = reader.string("name");
      const std::string link = reader.string("link");
      f.link = -1;
      for (std::size_t l = 0; l < model_.links_.size(); ++l)
        if (model_.links_[l].name == link) f.link = static_cast<int>(l);
      if (f.link < 0) reader.failAt("link", "names unknown link '" + link + "'");
      f.point = reader.numbers("point", 3);
      f.normal = reader.numbers("normal", 3);
      if (f.normal.norm() < 1e-9) reader.failAt("normal", "must not be zero");
      f.normal.normalize();
      model_.fingertips_.push_back(f);
    }
  }

  void addContactModel() {
    const std::string contact =
        config_.has("contact_model") ? config_.string("contact_model") : "hard_finger";
    if (contact == "hard_finger") {
      if (config_.has("torsional_friction"))
        config_.failAt("torsional_friction", "applies only to \"contact_model\": \"soft_finger\"");
      return;
    }
    if (contact != "soft_finger")
      config_.failAt("contact_model",
                     "must be \"hard_finger\" or \"soft_finger\", got '" + contact + "'");
    model_.torsional_friction_ = config_.number("torsional_friction");
    if (!(model_.torsional_friction_ > 0.0))
      config_.failAt("torsional_friction", "must be > 0 (m of torque per unit normal force)");
  }

  void addPlannerDefaults() {
    if (!config_.has("planner_defaults")) return;
    const json& defaults = config_.at("planner_defaults");
    if (!defaults.is_object())
      config_.failAt("planner_defaults", "must be an object of planner parameter values by name");
    for (const auto& item : defaults.items()) {
      const json& v = item.value();
      if (v.is_number_integer())
        model_.planner_defaults_[item.key()] = v.dump();
      else if (v.is_number() && std::isfinite(v.get<double>()))
        model_.planner_defaults_[item.key()] = v.dump();
      else if (v.is_string())
        model_.planner_defaults_[item.key()] = v.get<std::string>();
      else
        config_.failAt("planner_defaults." + item.key(), "must be a finite number or a string");
    }
  }

  /// `hand_actuation`: {"efforts": [one per hand DoF], "kp", "kv", "source"}.
  void addHandActuation() {
    if (!config_.has("hand_actuation")) return;
    const json& section = config_.at("hand_actuation");
    if (!section.is_object())
      config_.failAt("hand_actuation", "must be an object with efforts, kp, kv and source");
    const ConfigReader reader(section, what_, "hand_actuation.");
    HandActuation actuation;
    actuation.efforts = reader.numbers("efforts", model_.numHandDofs());
    if ((actuation.efforts.array() <= 0.0).any())
      reader.failAt("efforts", "must be positive (N m or N, one per hand DoF)");
    actuation.kp = reader.number("kp");
    if (!(actuation.kp > 0.0)) reader.failAt("kp", "must be > 0");
    actuation.kv = reader.number("kv");
    if (actuation.kv < 0.0) reader.failAt("kv", "must be >= 0");
    actuation.source = reader.string("source");
    if (actuation.source.empty()) reader.failAt("source", "must name where the efforts come from");
    model_.hand_actuation_ = std::move(actuation);
  }

  void addHandMapSettings() {
    if (!config_.has("hand_map_normal_weight")) return;
    model_.hand_map_normal_weight_ = config_.number("hand_map_normal_weight");
    if (!(model_.hand_map_normal_weight_ > 0.0))
      config_.failAt("hand_map_normal_weight", "must be > 0 (m)");
  }

  void addDisabledCollisions() {
    // From the config's list, the SRDF's <disable_collisions>, or both.
    if (config_.has("srdf")) addSrdfDisabledCollisions();
    const json* pairs = config_.has("srdf") && !config_.has("disabled_collisions")
                            ? nullptr
                            : &config_.at("disabled_collisions");
    if (pairs != nullptr && !pairs->is_array())
      config_.failAt("disabled_collisions", "must be an array of name pairs");
    for (std::size_t i = 0; pairs != nullptr && i < pairs->size(); ++i) {
      const json& pair = (*pairs)[i];
      if (!pair.is_array() || pair.size() != 2 || !pair[0].is_string() || !pair[1].is_string())
        config_.failAt("disabled_collisions", "entries must be pairs of link names");
      const int a = model_.linkIndex(pair[0].get<std::string>());
      const int b = model_.linkIndex(pair[1].get<std::string>());
      model_.disabled_.emplace_back(std::min(a, b), std::max(a, b));
    }
    std::sort(model_.disabled_.begin(), model_.disabled_.end());
    model_.disabled_.erase(std::unique(model_.disabled_.begin(), model_.disabled_.end()),
                           model_.disabled_.end());
  }

  /// The SRDF's (config `srdf`) <disable_collisions link1 link2> pairs.
  void addSrdfDisabledCollisions() {
    (void)config_.string("srdf");  // a file name (read by RobotModel::load)
    if (srdf_.empty()) config_.failAt("srdf", "names an SRDF whose text was not given");
    tinyxml2::XMLDocument doc;
    if (doc.Parse(srdf_.c_str(), srdf_.size()) != tinyxml2::XML_SUCCESS ||
        doc.FirstChildElement("robot") == nullptr)
      config_.failAt("srdf", "the SRDF cannot be parsed (no <robot> element)");
    for (const tinyxml2::XMLElement* e =
             doc.FirstChildElement("robot")->FirstChildElement("disable_collisions");
         e != nullptr; e = e->NextSiblingElement("disable_collisions")) {
      const char* first = e->Attribute("link1");
      const char* second = e->Attribute("link2");
      if (first == nullptr || second == nullptr)
        config_.failAt("srdf", "a <disable_collisions> without link1 and link2");
      const auto index = [&](const char* name) {
        for (std::size_t l = 0; l < model_.links_.size(); ++l)
          if (model_.links_[l].name == name) return static_cast<int>(l);
        config_.failAt("srdf", std::string("<disable_collisions> names link '") + name +
                                   "', which is not in the URDF");
      };
      const int a = index(first), b = index(second);
      model_.disabled_.emplace_back(std::min(a, b), std::max(a, b));
    }
  }

  /// Joint::rotation_* and slide (Rodrigues: R(v) = a a^T + cos(v) (I - a a^T) + sin(v) [a]x).
  static void precomputeMotion(Joint& joint) {
    const Eigen::Matrix3d origin = joint.origin.linear();
    joint.rotation_fixed = origin;
    if (joint.type == Joint::Type::kRevolute) {
      const Eigen::Vector3d& a = joint.axis;
      const Eigen::Matrix3d outer = a * a.transpose();
      Eigen::Matrix3d cross;
      cross << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
      joint.rotation_fixed = origin * outer;
      joint.rotation_cos = origin * (Eigen::Matrix3d::Identity() - outer);
      joint.rotation_sin = origin * cross;
    } else if (joint.type == Joint::Type::kPrismatic) {
      joint.slide = origin * joint.axis;
    }
  }

  void markHandLinks() {
    model_.hand_links_.assign(model_.links_.size(), false);
    if (!model_.hasHand()) return;
    model_.hand_links_[static_cast<std::size_t>(model_.palm_link_)] = true;
    for (const Joint& joint : model_.joints_) {
      const bool parentInHand = model_.hand_links_[static_cast<std::size_t>(joint.parent_link)];
      if (parentInHand) model_.hand_links_[static_cast<std::size_t>(joint.child_link)] = true;
    }
  }

  const urdf::ModelInterface& urdf_;
  ConfigReader config_;
  std::string what_;
  const std::string& srdf_;
  RobotModel model_;
};

RobotModel RobotModel::load(const std::filesystem::path& configPath) {
  const std::string what = "robot config '" + configPath.string() + "'";
  const std::string configText = readFile(configPath, what);
  json config;
  try {
    config = json::parse(configText);
  } catch (const json::exception& e) {
    throw ModelError(what + ": not valid JSON (" + e.what() + ")");
  }
  if (!config.is_object() || !config.contains("urdf") || !config["urdf"].is_string())
    throw ModelError(what + ": urdf: is required (the URDF file, relative to the config)");
  const std::filesystem::path urdfPath =
      configPath.parent_path() / config["urdf"].get<std::string>();
  const std::string srdf =
      config.contains("srdf") && config["srdf"].is_string()
          ? readFile(configPath.parent_path() / config["srdf"].get<std::string>(), what)
          : std::string();
  return fromStrings(readFile(urdfPath, what), configText, what, srdf);
}

RobotModel RobotModel::fromStrings(const std::string& urdfXml, const std::string& configJson,
                                   const std::string& what, const std::string& srdfXml) {
  json config;
  try {
    config = json::parse(configJson);
  } catch (const json::exception& e) {
    throw ModelError(what + ": not valid JSON (" + e.what() + ")");
  }
  if (!config.is_object()) throw ModelError(what + ": the config must be a JSON object");
  const urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDF(urdfXml);
  if (!urdf) throw ModelError(what + ": the URDF cannot be parsed");
  return RobotModelBuilder(*urdf, config, what, srdfXml).build();
}

int RobotModel::linkIndex(const std::string& name) const {
  for (std::size_t l = 0; l < links_.size(); ++l)
    if (links_[l].name == name) return static_cast<int>(l);
  throw ModelError("robot '" + name_ + "' has no link '" + name + "'");
}

bool RobotModel::isCollisionDisabled(int a, int b) const {
  return std::binary_search(disabled_.begin(), disabled_.end(),
                            std::make_pair(std::min(a, b), std::max(a, b)));
}

int RobotModel::movingJointsBetween(int a, int b) const {
  const std::size_t links = links_.size();
  const std::size_t other = b < 0 ? links : static_cast<std::size_t>(b);
  return joints_apart_[static_cast<std::size_t>(a) * (links + 1) + other];
}

/// RobotModel::movingJointsBetween for every pair of links and each link
/// and the root: the moving joints on one link's chain to the root and
/// not on the other's (those both share lie above the common ancestor).
void RobotModel::countJointsApart() {
  const std::size_t links = links_.size();
  std::vector<std::vector<int>> chains(links + 1);  // sorted; the root's empty
  for (std::size_t l = 0; l < links; ++l) {
    for (int j = links_[l].parent_joint; j >= 0;
         j = links_[static_cast<std::size_t>(joints_[static_cast<std::size_t>(j)].parent_link)]
                 .parent_joint)
      if (joints_[static_cast<std::size_t>(j)].type != Joint::Type::kFixed) chains[l].push_back(j);
    std::sort(chains[l].begin(), chains[l].end());
  }
  joints_apart_.assign(links * (links + 1), 0);
  std::vector<int> apart;
  for (std::size_t a = 0; a < links; ++a)
    for (std::size_t b = 0; b <= links; ++b) {
      apart.clear();
      std::set_symmetric_difference(chains[a].begin(), chains[a].end(), chains[b].begin(),
                                    chains[b].end(), std::back_inserter(apart));
      joints_apart_[a * (links + 1) + b] = static_cast<int>(apart.size());
    }
}

bool RobotModel::withinLimits(const Eigen::VectorXd& q, double tolerance, std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why != nullptr) *why = text;
    return false;
  };
  if (q.size() != numDofs())
    return fail("has " + std::to_string(q.size()) + " values, expected " +
                std::to_string(numDofs()));
  for (Eigen::Index d = 0; d < q.size(); ++d) {
    const std::string& name = dof_names_[static_cast<std::size_t>(d)];
    if (!std::isfinite(q(d))) return fail("value of '" + name + "' is not finite");
    if (q(d) < lower_(d) - tolerance || q(d) > upper_(d) + tolerance)
      return fail("value " + std::to_string(q(d)) + " of '" + name + "' is outside [" +
                  std::to_string(lower_(d)) + ", " + std::to_string(upper_(d)) + "]");
  }
  return true;
}

}  // namespace hfts::robot
