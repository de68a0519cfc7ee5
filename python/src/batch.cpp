#include "batch.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::python {
namespace {

std::string indexed(const char* field, std::size_t i) {
  return std::string(field) + "[" + std::to_string(i) + "]";
}

}  // namespace

void graspQualities(const double* positions, const double* normals, std::size_t grasps,
                    int contacts, const grasp::GraspQualityRequest& common, double* epsilons) {
  grasp::GraspQualityRequest request = common;
  const std::size_t stride = 3 * static_cast<std::size_t>(contacts);
  for (std::size_t g = 0; g < grasps; ++g) {
    request.positions = Eigen::Map<const Eigen::Matrix3Xd>(positions + g * stride, 3, contacts);
    request.normals = Eigen::Map<const Eigen::Matrix3Xd>(normals + g * stride, 3, contacts);
    try {
      epsilons[g] = grasp::graspQuality(request).epsilon;
    } catch (const std::invalid_argument& e) {
      // graspQuality's message is "<field>: <problem>".
      const std::string what = e.what();
      const std::size_t colon = what.find(": ");
      if (colon == std::string::npos) throw InvalidArgument(indexed("grasps", g), what);
      throw InvalidArgument(indexed("grasps", g) + "." + what.substr(0, colon),
                            what.substr(colon + 2));
    }
  }
}

IkSolutions armIkBatch(const robot::ArmIk& ik, const double* poses, std::size_t count, bool palm,
                       std::uint64_t seed) {
  IkSolutions out;
  for (std::size_t i = 0; i < count; ++i) {
    std::mt19937_64 rng(seed + i);
    const Eigen::Matrix4d m =
        Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(poses + 16 * i);
    const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
    if (!m.allFinite() || !(m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).isZero(1e-9) ||
        !(r.transpose() * r).isIdentity(1e-6) || r.determinant() < 0.0)
      throw InvalidArgument(indexed("poses", i),
                            "must be a finite rigid transform (rotation, translation, last row "
                            "0 0 0 1)");
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = r;
    pose.translation() = m.topRightCorner<3, 1>();
    const std::vector<Eigen::VectorXd> solutions =
        palm ? ik.solvePalm(pose, rng) : ik.solveFlange(pose, rng);
    for (const Eigen::VectorXd& q : solutions) {
      out.configurations.insert(out.configurations.end(), q.data(), q.data() + q.size());
      out.pose_index.push_back(static_cast<std::int64_t>(i));
    }
  }
  return out;
}

std::size_t collisionBatch(robot::CollisionChecker& checker, const double* configurations,
                           std::size_t count, int dofs, const robot::CollisionRequest& request,
                           bool* colliding) {
  std::vector<Eigen::VectorXd> states(count);
  std::vector<const Eigen::VectorXd*> pointers(count);
  for (std::size_t i = 0; i < count; ++i) {
    states[i] = Eigen::Map<const Eigen::VectorXd>(
        configurations + i * static_cast<std::size_t>(dofs), dofs);
    std::string why;
    if (!checker.model().withinLimits(states[i], 1e-9, &why))
      throw InvalidArgument(indexed("configurations", i), why);
    pointers[i] = &states[i];
  }
  return checker.inCollision(pointers.data(), count, request, colliding);
}

}  // namespace hfts::python
