#pragma once
// The arithmetic of the sphere tier (sphere_tier.h): forward kinematics and
// sphere tests for a batch of configurations at once, one configuration per
// SIMD lane (Highway; the widest vectors the CPU offers, chosen at run
// time). Single precision, made conservative by padding every robot sphere
// (kPadding). Plain data in, touching pairs out; internal to the robot
// library.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hfts::robot::kernel {

/// Added to every robot sphere's radius: covers the rounding of forward
/// kinematics, item transforms and distances in single precision (well
/// under 0.1 mm for a robot a few metres across), so that a pair the
/// double-precision geometry puts in contact is never called clear.
inline constexpr float kPadding = 5e-4f;

/// One joint of forward kinematics: child = parent * joint(v) with
/// v = multiplier * q[dof] + offset. Rotation (row-major 3x3):
/// a + cos(v) b + sin(v) c for a revolute joint, a otherwise; translation
/// t + v dt (dt = 0 unless prismatic).
struct FkStep {
  int parent = 0;
  int child = 0;
  int dof = -1;  ///< -1: fixed
  bool revolute = false;
  float multiplier = 1.0f;
  float offset = 0.0f;
  float a[9] = {};
  float b[9] = {};
  float c[9] = {};
  float t[3] = {};
  float dt[3] = {};
};

/// An FkStep for the one-configuration kernel: the joint's transform as
/// three rows of four (rotation, then translation), a + cos(v) b + sin(v) c
/// + v dt.
struct FkRows {
  alignas(16) float a[12];
  alignas(16) float b[12];
  alignas(16) float c[12];
  alignas(16) float dt[12];
};

/// A node of a link's sphere tree (link frame; radius padded).
struct Node {
  float x = 0, y = 0, z = 0, r = 0;
  int left = -1;  ///< index into Program::nodes, -1 for a leaf
  int right = -1;
};

/// Up to 16 spheres of a link (link frame; radii padded), each a leaf or
/// the bound of the spheres of wide node `below`; unused slots far away.
struct WideNode {
  static constexpr std::size_t kSlots = 16;
  alignas(64) float x[kSlots];
  alignas(64) float y[kSlots];
  alignas(64) float z[kSlots];
  alignas(64) float r[kSlots];
  int below[kSlots];
  std::size_t count = 0;
};

enum class ItemType : std::uint8_t { kBox, kCylinder, kSphere, kGrid };

/// An environment item in its own frame: p_item = rotation * p_world + translation.
struct Item {
  ItemType type = ItemType::kBox;
  bool target = false;
  float rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  float translation[3] = {};
  /// Box and grid: half extents (the grid item's frame is centred on the
  /// mesh's bounding box). Cylinder: radius, half length. Sphere: radius.
  float half[3] = {};
  float bound[4] = {};  ///< a sphere holding the item, world frame: x, y, z, radius
  /// Grid only: lower bounds of the signed distance to the mesh at the
  /// nodes origin + spacing * (i, j, k) (item frame), x fastest.
  const float* values = nullptr;
  float origin[3] = {};
  float spacing = 0;
  int dims[3] = {};
};

struct EnvPair {
  std::uint16_t link = 0;
  std::uint16_t item = 0;
};

struct SelfPair {
  std::uint16_t a = 0;
  std::uint16_t b = 0;
};

/// A self pair's map of where in joint space it is apart
/// (robot/pair_maps.h): apart when t_k = (q[dof[k]] - lower[k]) * inverse[k]
/// lies in [0, cells[k]) for k = 0, 1, 2 and bit sum of floor(t_k)
/// stride[k] is set. An unused DoF has inverse 0 and one cell.
struct SelfMap {
  static constexpr int kDofs = 3;
  int dof[kDofs] = {};
  float lower[kDofs] = {};
  float inverse[kDofs] = {};
  float cells[kDofs] = {};
  int stride[kDofs] = {};
  const std::uint32_t* bits = nullptr;  ///< nullptr: no map
};

/// Everything the kernel needs, built once per collision scene.
struct Program {
  int num_dofs = 0;
  int num_links = 0;
  float base[12] = {1, 0, 0, 0, 1, 0,
                    0, 0, 1, 0, 0, 0};  ///< root link in the world: R row-major, then t
  std::vector<FkStep> steps;            ///< parents before children
  std::vector<FkRows> fk_rows;          ///< [step], filled by buildWideTrees
  std::vector<int> root;                ///< [link]: its root node, -1 for a link without spheres
  std::vector<Node> nodes;
  /// The same trees with up to 16 children a node, for the
  /// one-configuration kernel; wide_root[link]: the wide node holding the
  /// children of the link's root sphere (-1: the root is a leaf or absent).
  std::vector<WideNode> wide;
  std::vector<int> wide_root;
  /// Lookups of the one-configuration kernel: env_index[link * items +
  /// item] and self_index[a * links + b] (a < b) are indices into env and
  /// self (-1: not tested); self_mask[a * words + w]: bit b % 64 of word
  /// b / 64 is set when (a, b) is a self pair; words = link_words = links / 64 + 1.
  std::vector<int> env_index, self_index;
  std::vector<std::uint64_t> self_mask;
  std::size_t link_words = 1;
  std::vector<Item> items;
  std::vector<EnvPair> env;        ///< link-item pairs to test, ordered by link, then item
  std::vector<SelfPair> self;      ///< link pairs to test
  std::vector<SelfMap> self_maps;  ///< [self pair]: bits == nullptr where it has none
};

/// Called for each pair whose spheres touch in some of the active lanes:
/// `pair` < env.size() is an environment pair, else self pair
/// pair - env.size(); bit i of `lanes` for lane i. Returns the lanes that
/// stay active (a subset of `lanes`' complement and the other active
/// lanes): e.g. without the lanes FCL has found colliding.
using Visit = std::uint32_t (*)(void* context, std::uint32_t pair, std::uint32_t lanes);

/// Lanes of a batch on this CPU (4, 8 or 16).
std::size_t batchSize();

/// Fills Program::wide and wide_root from Program::nodes and fk_rows from
/// steps: the robot's part, once.
void buildWideTrees(Program& program);

/// Fills the lookups env_index, self_index and self_mask from env and self
/// (again whenever those change).
void buildLookups(Program& program);

/// Tests one configuration q[0 .. num_dofs) like findTouching (lane 0),
/// with the SIMD lanes spread over link pairs and sphere pairs instead of
/// configurations.
void findTouchingOne(const Program& program, const float* q, Visit visit, void* context);

/// Tests the configurations of a batch: q[d * batchSize() + lane] is DoF d
/// of lane `lane`; lanes >= `count` are ignored. Calls `visit` for every
/// pair whose spheres touch in some active lane, in the order of
/// Program::env, then Program::self, and stops when no lane is active.
void findTouching(const Program& program, const float* q, std::size_t count, Visit visit,
                  void* context);

}  // namespace hfts::robot::kernel
