#pragma once
// The hand reachability map: fingertip positions and pad normals of a
// hand, sampled over its joint space, in the palm frame. Built once per hand
// by hfts::grasp::buildHandMap and stored as one HDF5 file (schema:
// docs/database.md, "Hand reachability map"); hfts::grasp answers R(h) of
// the paper's Eq. (1) from it (docs/hand_reachability.md).

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"  // DatabaseError

namespace hfts::db {

/// Name and version of the hand map file format.
inline constexpr const char* kHandMapFormatName = "hfts-hand-map";
inline constexpr std::uint32_t kHandMapFormatVersion = 2;

using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Every parameter that shaped a hand map, stored with it. Meaning and
/// defaults: docs/hand_reachability.md.
struct HandMapParameters {
  std::uint32_t num_samples = 8192;   ///< grasp postures kept
  std::uint64_t max_draws = 4000000;  ///< give up after this many random configurations
  std::uint64_t seed = 1;             ///< shifts the joint-space (Halton) sampling
  /// lambda (m): weight of a unit pad-normal error against a position
  /// error, in the residual R(h) and in the descriptor.
  double normal_weight = 0.03;
  double min_fingertip_distance = 0.01;  ///< m; closer fingertips grasp nothing
  double friction = 0.5;                 ///< friction coefficient of the "pads can squeeze" test
};

/// A complete hand map. Fingertip i of sample s is at
/// positions.row(s).segment<3>(3 * i), with its unit pad normal (pointing
/// out of the pad, the direction the finger pushes) at the same place in
/// `normals`; both in the palm frame, metres.
struct HandMap {
  std::string robot_name;                 ///< RobotModel::name()
  std::string producer;                   ///< program that built the map
  std::vector<std::string> dof_names;     ///< the hand DoF, D of them
  Eigen::VectorXd lower_limits;           ///< D hand joint limits the map was sampled in
  Eigen::VectorXd upper_limits;           ///< D
  std::vector<std::string> finger_names;  ///< the m fingertips, column order
  std::string descriptor;                 ///< name of the descriptor in `descriptors`
  HandMapParameters parameters;           ///< how it was built
  std::uint64_t num_draws = 0;            ///< configurations drawn to find the samples
  RowMatrixXd configurations;             ///< N x D hand configurations
  RowMatrixXd positions;                  ///< N x 3m fingertip positions (m)
  RowMatrixXd normals;                    ///< N x 3m unit pad normals
  RowMatrixXd descriptors;                ///< N x K rigid-motion-invariant descriptors

  std::size_t numSamples() const { return static_cast<std::size_t>(configurations.rows()); }
  std::size_t numFingers() const { return finger_names.size(); }
};

/// Checks shapes, names, finite values, unit normals, configurations within
/// the limits and sane parameters. Throws DatabaseError naming `what` and
/// the first violation.
void validateHandMap(const HandMap& map, const std::string& what);

/// Writes `map` to `path` atomically (temporary sibling, then rename),
/// after validating it. No timestamps: the same map gives the same bytes.
/// Throws DatabaseError, leaving an existing file at `path` untouched.
void saveHandMap(const HandMap& map, const std::filesystem::path& path);

/// Reads and validates a hand map. Throws DatabaseError for a missing,
/// truncated, corrupt (checksum), foreign or other-version file.
HandMap loadHandMap(const std::filesystem::path& path);

}  // namespace hfts::db
