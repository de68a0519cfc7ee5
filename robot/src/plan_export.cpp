#include "robot/plan_export.h"

#include <cmath>

#include "hfts_db/atomic_file.h"
#include "hfts_db/invalid_argument.h"
#include "robot/kinematics.h"
#include "robot/primitive_meshes.h"

#include "glb_builder.h"

namespace hfts::robot {
namespace {

using namespace glb;

/// Palm positions drawn along each path segment.
constexpr int kPathSteps = 16;
constexpr double kMarkerRadius = 0.004, kNormalLength = 0.03;

void check(const RobotModel& model, const PlanAnimation& plan) {
  if (plan.times.empty()) throw InvalidArgument("times", "must not be empty");
  if (plan.times.size() != plan.configurations.size())
    throw InvalidArgument("configurations",
                          "one per time expected: " + std::to_string(plan.times.size()) +
                              " times, " + std::to_string(plan.configurations.size()));
  for (std::size_t i = 0; i < plan.times.size(); ++i) {
    if (!std::isfinite(plan.times[i]) || (i > 0 && !(plan.times[i] > plan.times[i - 1])))
      throw InvalidArgument("times",
                            "must be finite and increasing (at " + std::to_string(i) + ")");
    if (plan.configurations[i].size() != model.numDofs() || !plan.configurations[i].allFinite())
      throw InvalidArgument("configurations[" + std::to_string(i) + "]",
                            std::to_string(model.numDofs()) + " finite values expected");
  }
  for (const Eigen::VectorXd& q : plan.path)
    if (q.size() != model.numDofs()) throw InvalidArgument("path", "configuration of wrong size");
  if (plan.contacts.cols() != plan.inward_normals.cols())
    throw InvalidArgument("inward_normals", "one per contact expected");
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

/// One channel per link node: its world pose at every time.
aiAnimation* animation(const RobotModel& model, const Scene& scene, const PlanAnimation& plan,
                       const std::vector<std::size_t>& links) {
  auto* a = new aiAnimation;
  a->mName = "plan";
  a->mTicksPerSecond = 1.0;
  a->mDuration = plan.times.back();
  a->mNumChannels = static_cast<unsigned>(links.size());
  a->mChannels = new aiNodeAnim*[links.size()];
  const auto keys = static_cast<unsigned>(plan.times.size());
  for (std::size_t c = 0; c < links.size(); ++c) {
    auto* channel = new aiNodeAnim;
    channel->mNodeName = model.links()[links[c]].name;
    channel->mNumPositionKeys = channel->mNumRotationKeys = keys;
    channel->mPositionKeys = new aiVectorKey[keys];
    channel->mRotationKeys = new aiQuatKey[keys];
    a->mChannels[c] = channel;
  }
  for (unsigned k = 0; k < keys; ++k) {
    const LinkPoses poses = forwardKinematics(model, plan.configurations[k]);
    for (std::size_t c = 0; c < links.size(); ++c) {
      const Eigen::Isometry3d pose = scene.robot_base * poses[links[c]];
      const Eigen::Vector3d t = pose.translation();
      const Eigen::Quaterniond q(pose.rotation());
      a->mChannels[c]->mPositionKeys[k] = aiVectorKey(
          plan.times[k], aiVector3D(static_cast<float>(t.x()), static_cast<float>(t.y()),
                                    static_cast<float>(t.z())));
      a->mChannels[c]->mRotationKeys[k] = aiQuatKey(
          plan.times[k], aiQuaternion(static_cast<float>(q.w()), static_cast<float>(q.x()),
                                      static_cast<float>(q.y()), static_cast<float>(q.z())));
    }
  }
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
  ai.mNumAnimations = 1;
  ai.mAnimations = new aiAnimation* [1] { animation(model, scene, plan, moving) };
  return builder.glb("the plan");
}

void exportPlanGlb(const RobotModel& model, const Scene& scene, const db::ObjectGeometry* target,
                   const PlanAnimation& plan, const std::filesystem::path& path) {
  if (path.extension() != ".glb")
    throw InvalidArgument("path", "'" + path.string() + "' must end in .glb (binary glTF)");
  db::writeFileAtomically(path, planGlb(model, scene, target, plan));
}

}  // namespace hfts::robot
