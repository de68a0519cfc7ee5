// A body the robot holds (RobotModel::withHeldBody): one more link, fixed
// to the palm, that collides as a mesh.
#include <algorithm>
#include <string>
#include <utility>

#include "core/invalid_argument.h"
#include "robot/robot_model.h"

namespace hfts::robot {

RobotModel RobotModel::withHeldBody(const std::string& name, const Eigen::Isometry3d& inPalm,
                                    std::shared_ptr<const TriangleMesh> mesh) const {
  const auto fail = [](const std::string& problem) { throw InvalidArgument("held_body", problem); };
  if (!hasHand()) fail("robot '" + name_ + "' has no hand to hold a body with");
  for (const Link& link : links_)
    if (link.name == name) fail("robot '" + name_ + "' already has a link '" + name + "'");
  if (!inPalm.matrix().allFinite()) fail("its pose in the palm must be finite");
  if (mesh == nullptr || mesh->triangles.rows() == 0) fail("'" + name + "' has no triangles");
  RobotModel held = *this;
  const int link = static_cast<int>(links_.size());
  Joint joint;
  joint.name = name + "_held";
  joint.parent_link = palm_link_;
  joint.child_link = link;
  joint.origin = inPalm;
  joint.rotation_fixed = inPalm.linear();
  held.joints_.push_back(joint);
  Link body;
  body.name = name;
  body.parent_joint = static_cast<int>(joints_.size());
  body.mesh = std::move(mesh);
  held.links_.push_back(std::move(body));
  held.hand_links_.push_back(false);
  for (int l = 0; l < link; ++l)
    if (isHandLink(l)) held.disabled_.emplace_back(l, link);
  std::sort(held.disabled_.begin(), held.disabled_.end());
  held.held_link_ = link;
  held.countJointsApart();
  return held;
}

RobotModel RobotModel::withHandFixed(const Eigen::VectorXd& hand) const {
  const int arm = num_arm_dofs_;
  if (hand.size() != numHandDofs() || !hand.allFinite())
    throw InvalidArgument("hand", std::to_string(numHandDofs()) + " finite values expected, got " +
                                      std::to_string(hand.size()));
  for (int i = 0; i < numHandDofs(); ++i)
    if (hand(i) < lower_(arm + i) - 1e-9 || hand(i) > upper_(arm + i) + 1e-9)
      throw InvalidArgument("hand", "joint '" + dof_names_[static_cast<std::size_t>(arm + i)] +
                                        "' at " + std::to_string(hand(i)) +
                                        " lies outside its limits");
  RobotModel fixed = *this;
  fixed.lower_.tail(numHandDofs()) = hand;
  fixed.upper_.tail(numHandDofs()) = hand;
  fixed.home_.tail(numHandDofs()) = hand;
  fixed.hand_open_ = hand;
  return fixed;
}

}  // namespace hfts::robot
