#include "robot/plan_export.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/atomic_file.h"
#include "core/invalid_argument.h"
#include "robot/kinematics.h"
#include "robot/primitive_meshes.h"

#include "glb_builder.h"

namespace hfts::robot {
namespace {

using namespace glb;

/// Palm positions drawn along each path segment.
constexpr int kPathSteps = 16;
constexpr double kMarkerRadius = 0.004, kNormalLength = 0.03;

/// Times and configurations of one animation; fields named with `prefix`.
void checkMotion(const RobotModel& model, const std::vector<double>& times,
                 const std::vector<Eigen::VectorXd>& configurations, const std::string& prefix) {
  if (times.size() != configurations.size())
    throw InvalidArgument(prefix + "configurations",
                          "one per time expected: " + std::to_string(times.size()) + " times, " +
                              std::to_string(configurations.size()));
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i]) || (i > 0 && !(times[i] > times[i - 1])))
      throw InvalidArgument(prefix + "times",
                            "must be finite and increasing (at " + std::to_string(i) + ")");
    if (configurations[i].size() != model.numDofs() || !configurations[i].allFinite())
      throw InvalidArgument(prefix + "configurations[" + std::to_string(i) + "]",
                            std::to_string(model.numDofs()) + " finite values expected");
  }
}

void check(const RobotModel& model, const PlanAnimation& plan) {
  if (plan.times.empty()) throw InvalidArgument("times", "must not be empty");
  checkMotion(model, plan.times, plan.configurations, "");
  for (const Eigen::VectorXd& q : plan.path)
    if (q.size() != model.numDofs()) throw InvalidArgument("path", "configuration of wrong size");
  if (plan.contacts.cols() != plan.inward_normals.cols())
    throw InvalidArgument("inward_normals", "one per contact expected");
  checkMotion(model, plan.simulated_times, plan.simulated_configurations, "simulated_");
  if (plan.simulated_object.size() != plan.simulated_times.size())
    throw InvalidArgument("simulated_object", "one pose per simulated time expected");
  for (const Eigen::Isometry3d& pose : plan.simulated_object)
    if (!pose.matrix().allFinite()) throw InvalidArgument("simulated_object", "must be finite");
  if (!plan.object_motion.empty() && plan.object_motion.size() != plan.times.size())
    throw InvalidArgument("object_motion", "one pose per time expected (or none)");
  for (const Eigen::Isometry3d& pose : plan.object_motion)
    if (!pose.matrix().allFinite()) throw InvalidArgument("object_motion", "must be finite");
}

/// A link's collision primitives in its own frame.
std::vector<Part> linkParts(const RobotModel& model, std::size_t l) {
  const Link& link = model.links()[l];
  std::vector<Part> parts;
  for (std::size_t s = 0; s < link.shapes.size(); ++s) {
    const CollisionShape& shape = link.shapes[s];
    parts.push_back(
        {transformed(primitiveMesh(static_cast<int>(shape.type), shape.size), shape.origin),
         linkMaterial(model, l), link.name + "_" + std::to_string(s)});
  }
  return parts;
}

aiMatrix4x4 toAi(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix4d m = pose.matrix();
  return aiMatrix4x4(static_cast<float>(m(0, 0)), static_cast<float>(m(0, 1)),
                     static_cast<float>(m(0, 2)), static_cast<float>(m(0, 3)),
                     static_cast<float>(m(1, 0)), static_cast<float>(m(1, 1)),
                     static_cast<float>(m(1, 2)), static_cast<float>(m(1, 3)),
                     static_cast<float>(m(2, 0)), static_cast<float>(m(2, 1)),
                     static_cast<float>(m(2, 2)), static_cast<float>(m(2, 3)), 0.f, 0.f, 0.f, 1.f);
}

/// A node's channel keyed at `times` with the poses pose(k), world frame.
template <typename PoseAt>
aiNodeAnim* channel(const std::string& node, const std::vector<double>& times, PoseAt&& pose) {
  auto* c = new aiNodeAnim;
  c->mNodeName = node;
  const auto keys = static_cast<unsigned>(times.size());
  c->mNumPositionKeys = c->mNumRotationKeys = keys;
  c->mPositionKeys = new aiVectorKey[keys];
  c->mRotationKeys = new aiQuatKey[keys];
  for (unsigned k = 0; k < keys; ++k) {
    const Eigen::Isometry3d p = pose(k);
    const Eigen::Vector3d t = p.translation();
    const Eigen::Quaterniond q(p.rotation());
    c->mPositionKeys[k] =
        aiVectorKey(times[k], aiVector3D(static_cast<float>(t.x()), static_cast<float>(t.y()),
                                         static_cast<float>(t.z())));
    c->mRotationKeys[k] =
        aiQuatKey(times[k], aiQuaternion(static_cast<float>(q.w()), static_cast<float>(q.x()),
                                         static_cast<float>(q.y()), static_cast<float>(q.z())));
  }
  return c;
}

/// The object's node, moved by `motion(k)` (world frame; the node's mesh
/// stands where the plan has the object).
struct ObjectTrack {
  std::string node;
  std::function<Eigen::Isometry3d(unsigned)> motion;
};

/// The animation `name`: a channel per link node with its world pose along
/// `configurations` at `times`, and one for the object's node when given.
aiAnimation* animation(const char* name, const RobotModel& model, const Scene& scene,
                       const std::vector<double>& times,
                       const std::vector<Eigen::VectorXd>& configurations,
                       const std::vector<std::size_t>& links, const ObjectTrack* object) {
  std::vector<LinkPoses> poses;
  poses.reserve(configurations.size());
  for (const Eigen::VectorXd& q : configurations) poses.push_back(forwardKinematics(model, q));
  std::vector<aiNodeAnim*> channels;
  for (const std::size_t l : links)
    channels.push_back(channel(model.links()[l].name, times,
                               [&](unsigned k) { return scene.robot_base * poses[k][l]; }));
  if (object != nullptr) channels.push_back(channel(object->node, times, object->motion));
  auto* a = new aiAnimation;
  a->mName = name;
  a->mTicksPerSecond = 1.0;
  a->mDuration = times.back();
  a->mNumChannels = static_cast<unsigned>(channels.size());
  a->mChannels = new aiNodeAnim*[channels.size()];
  std::copy(channels.begin(), channels.end(), a->mChannels);
  return a;
}

/// Line segments through the palm's positions along the path.
std::vector<Eigen::Vector3d> palmTrace(const RobotModel& model, const Scene& scene,
                                       const std::vector<Eigen::VectorXd>& path) {
  std::vector<Eigen::Vector3d> points;
  const auto palm = [&](const Eigen::VectorXd& q) {
    return Eigen::Vector3d(
        (scene.robot_base * forwardKinematics(model, q)[model.palmLink()]).translation());
  };
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    for (int s = 0; s < kPathSteps; ++s) {
      points.push_back(palm(path[i] + (path[i + 1] - path[i]) * s / kPathSteps));
      points.push_back(palm(path[i] + (path[i + 1] - path[i]) * (s + 1) / kPathSteps));
    }
  return points;
}

}  // namespace

std::string planGlb(const RobotModel& model, const Scene& scene, const db::ObjectGeometry* target,
                    const PlanAnimation& plan) {
  check(model, plan);
  Builder builder;
  for (const Part& part : environmentParts(scene, target, plan.object_pose))
    builder.addNode(part.name, {part});
  addSensedPoints(builder, scene);
  // The robot: one node per link with geometry, at the first pose (the
  // animation moves it from there).
  const LinkPoses first = forwardKinematics(model, plan.configurations.front());
  std::vector<std::size_t> moving;
  for (std::size_t l = 0; l < model.links().size(); ++l) {
    if (model.links()[l].shapes.empty()) continue;
    aiNode* node = builder.addNode(model.links()[l].name, linkParts(model, l));
    node->mTransformation = toAi(scene.robot_base * first[l]);
    moving.push_back(l);
  }
  std::vector<Part> markers;
  std::vector<Eigen::Vector3d> normals;
  for (Eigen::Index c = 0; c < plan.contacts.cols(); ++c) {
    const Eigen::Vector3d p = plan.contacts.col(c);
    markers.push_back(
        {transformed(sphereMesh(kMarkerRadius, 12), Eigen::Isometry3d(Eigen::Translation3d(p))),
         kMarker, "contact_" + std::to_string(c)});
    normals.push_back(p - kNormalLength * plan.inward_normals.col(c));
    normals.push_back(p);
  }
  if (!markers.empty()) {
    builder.addNode("contacts", markers);
    builder.addLines("contact_normals", normals, kMarker);
  }
  if (plan.path.size() >= 2) builder.addLines("path", palmTrace(model, scene, plan.path), kPath);
  aiScene& ai = builder.scene();
  // The object's mesh stands at the plan's pose: the plan holds it still
  // or carries it (object_motion), the simulation moves it from there.
  const Eigen::Isometry3d back = plan.object_pose.inverse();
  const ObjectTrack still{scene.target_object, [](unsigned) {
                            return Eigen::Isometry3d(Eigen::Isometry3d::Identity());
                          }};
  const ObjectTrack carried{scene.target_object,
                            [&](unsigned k) { return plan.object_motion[k] * back; }};
  const bool withSimulation = !plan.simulated_times.empty() && target != nullptr;
  const ObjectTrack* planned = target == nullptr             ? nullptr
                               : !plan.object_motion.empty() ? &carried
                               : withSimulation              ? &still
                                                             : nullptr;
  if (!withSimulation) {
    ai.mNumAnimations = 1;
    ai.mAnimations = new aiAnimation* [1] {
      animation("plan", model, scene, plan.times, plan.configurations, moving, planned)
    };
    return builder.glb("the plan");
  }
  const ObjectTrack simulated{scene.target_object,
                              [&](unsigned k) { return plan.simulated_object[k] * back; }};
  ai.mNumAnimations = 2;
  ai.mAnimations = new aiAnimation* [2] {
    animation("plan", model, scene, plan.times, plan.configurations, moving, planned),
        animation("simulated", model, scene, plan.simulated_times, plan.simulated_configurations,
                  moving, &simulated)
  };
  return builder.glb("the plan");
}

void exportPlanGlb(const RobotModel& model, const Scene& scene, const db::ObjectGeometry* target,
                   const PlanAnimation& plan, const std::filesystem::path& path) {
  if (path.extension() != ".glb")
    throw InvalidArgument("path", "'" + path.string() + "' must end in .glb (binary glTF)");
  core::writeFileAtomically(path, planGlb(model, scene, target, plan));
}

}  // namespace hfts::robot
