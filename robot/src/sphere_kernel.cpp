// Compiled once per SIMD target (SSE4, AVX2, AVX-512, ...) through
// Highway's foreach_target; batchSize() and findTouching() dispatch to the
// best one the CPU supports.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sphere_kernel.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/aligned_allocator.h>
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include "sphere_kernel.h"

HWY_BEFORE_NAMESPACE();
namespace hfts::robot::kernel {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

struct Vec3 {
  V x, y, z;
};

/// A link's pose in every lane: rotation rows r[0..8], translation t[0..2].
struct Pose {
  const float* data;  ///< 12 vectors of Lanes(D) floats
  std::size_t lanes;
  V at(D d, int k) const { return hn::Load(d, data + static_cast<std::size_t>(k) * lanes); }
};

/// p = pose * (x, y, z): the world position of a point fixed in the link.
HWY_INLINE Vec3 transform(D d, const Pose& pose, float x, float y, float z) {
  const V px = hn::Set(d, x), py = hn::Set(d, y), pz = hn::Set(d, z);
  Vec3 out;
  out.x = hn::MulAdd(pose.at(d, 0), px,
                     hn::MulAdd(pose.at(d, 1), py, hn::MulAdd(pose.at(d, 2), pz, pose.at(d, 9))));
  out.y = hn::MulAdd(pose.at(d, 3), px,
                     hn::MulAdd(pose.at(d, 4), py, hn::MulAdd(pose.at(d, 5), pz, pose.at(d, 10))));
  out.z = hn::MulAdd(pose.at(d, 6), px,
                     hn::MulAdd(pose.at(d, 7), py, hn::MulAdd(pose.at(d, 8), pz, pose.at(d, 11))));
  return out;
}

/// Poses of every link in every lane (world frame), into `poses`.
void forwardKinematics(D d, const Program& program, const float* q, float* poses) {
  const std::size_t n = hn::Lanes(d);
  for (int k = 0; k < 12; ++k) hn::Store(hn::Set(d, program.base[k]), d, poses + k * n);
  for (const FkStep& step : program.steps) {
    const float* parent = poses + static_cast<std::size_t>(step.parent) * 12 * n;
    float* child = poses + static_cast<std::size_t>(step.child) * 12 * n;
    V joint[9], translation[3];
    V value = hn::Zero(d);
    if (step.dof >= 0)
      value = hn::MulAdd(hn::Set(d, step.multiplier),
                         hn::Load(d, q + static_cast<std::size_t>(step.dof) * n),
                         hn::Set(d, step.offset));
    if (step.revolute) {
      const V c = hn::Cos(d, value), s = hn::Sin(d, value);
      for (int k = 0; k < 9; ++k)
        joint[k] = hn::MulAdd(s, hn::Set(d, step.c[k]),
                              hn::MulAdd(c, hn::Set(d, step.b[k]), hn::Set(d, step.a[k])));
    } else {
      for (int k = 0; k < 9; ++k) joint[k] = hn::Set(d, step.a[k]);
    }
    for (int k = 0; k < 3; ++k)
      translation[k] = hn::MulAdd(value, hn::Set(d, step.dt[k]), hn::Set(d, step.t[k]));
    for (int i = 0; i < 3; ++i) {
      const V p0 = hn::Load(d, parent + (3 * i) * n), p1 = hn::Load(d, parent + (3 * i + 1) * n),
              p2 = hn::Load(d, parent + (3 * i + 2) * n);
      for (int j = 0; j < 3; ++j)
        hn::Store(hn::MulAdd(p0, joint[j], hn::MulAdd(p1, joint[3 + j], hn::Mul(p2, joint[6 + j]))),
                  d, child + (3 * i + j) * n);
      hn::Store(
          hn::MulAdd(p0, translation[0],
                     hn::MulAdd(p1, translation[1],
                                hn::MulAdd(p2, translation[2], hn::Load(d, parent + (9 + i) * n)))),
          d, child + (9 + i) * n);
    }
  }
}

HWY_INLINE V squaredNorm(const Vec3& v) {
  return hn::MulAdd(v.x, v.x, hn::MulAdd(v.y, v.y, hn::Mul(v.z, v.z)));
}

HWY_INLINE V squaredPositive(D d, V v) {
  const V p = hn::Max(v, hn::Zero(d));
  return hn::Mul(p, p);
}

/// Box (half extents h) at the origin against spheres at p with radius r:
/// inside, or nearer than r to the surface.
HWY_INLINE M boxTouches(D d, const Vec3& p, const float* h, V r) {
  const V qx = hn::Sub(hn::Abs(p.x), hn::Set(d, h[0]));
  const V qy = hn::Sub(hn::Abs(p.y), hn::Set(d, h[1]));
  const V qz = hn::Sub(hn::Abs(p.z), hn::Set(d, h[2]));
  const V outside =
      hn::Add(squaredPositive(d, qx), hn::Add(squaredPositive(d, qy), squaredPositive(d, qz)));
  return hn::Le(outside, hn::Mul(r, r));  // 0 inside the box
}

/// The grid's lower bound of the signed distance at p, from the node
/// nearest to p (any node gives a valid bound: distances are 1-Lipschitz).
HWY_INLINE V gridBound(D d, const Item& item, const Vec3& p) {
  const hn::RebindToSigned<D> di;
  const V inv = hn::Set(d, 1.0f / item.spacing), spacing = hn::Set(d, item.spacing);
  Vec3 node;
  hn::Vec<decltype(di)> index[3];
  const V local[3] = {hn::Sub(p.x, hn::Set(d, item.origin[0])),
                      hn::Sub(p.y, hn::Set(d, item.origin[1])),
                      hn::Sub(p.z, hn::Set(d, item.origin[2]))};
  for (int k = 0; k < 3; ++k) {
    const V cell = hn::Min(hn::Max(hn::Round(hn::Mul(local[k], inv)), hn::Zero(d)),
                           hn::Set(d, static_cast<float>(item.dims[k] - 1)));
    index[k] = hn::ConvertTo(di, cell);
    const V offset = hn::NegMulAdd(cell, spacing, local[k]);  // p - node
    (k == 0 ? node.x : k == 1 ? node.y : node.z) = offset;
  }
  const auto flat =
      hn::Add(index[0], hn::Mul(hn::Set(di, item.dims[0]),
                                hn::Add(index[1], hn::Mul(hn::Set(di, item.dims[1]), index[2]))));
  const V value = hn::GatherIndex(d, item.values, flat);
  return hn::Sub(value, hn::Sqrt(squaredNorm(node)));
}

/// Spheres (world frame) against an item.
HWY_INLINE M itemTouches(D d, const Item& item, const Vec3& c, V r, M active) {
  const float* R = item.rotation;
  Vec3 p;
  p.x = hn::MulAdd(hn::Set(d, R[0]), c.x,
                   hn::MulAdd(hn::Set(d, R[1]), c.y,
                              hn::MulAdd(hn::Set(d, R[2]), c.z, hn::Set(d, item.translation[0]))));
  p.y = hn::MulAdd(hn::Set(d, R[3]), c.x,
                   hn::MulAdd(hn::Set(d, R[4]), c.y,
                              hn::MulAdd(hn::Set(d, R[5]), c.z, hn::Set(d, item.translation[1]))));
  p.z = hn::MulAdd(hn::Set(d, R[6]), c.x,
                   hn::MulAdd(hn::Set(d, R[7]), c.y,
                              hn::MulAdd(hn::Set(d, R[8]), c.z, hn::Set(d, item.translation[2]))));
  switch (item.type) {
    case ItemType::kBox:
      return hn::And(active, boxTouches(d, p, item.half, r));
    case ItemType::kCylinder: {
      const V radial =
          hn::Sub(hn::Sqrt(hn::MulAdd(p.x, p.x, hn::Mul(p.y, p.y))), hn::Set(d, item.half[0]));
      const V axial = hn::Sub(hn::Abs(p.z), hn::Set(d, item.half[1]));
      const V outside = hn::Add(squaredPositive(d, radial), squaredPositive(d, axial));
      return hn::And(active, hn::Le(outside, hn::Mul(r, r)));
    }
    case ItemType::kSphere: {
      const V reach = hn::Add(r, hn::Set(d, item.half[0]));
      return hn::And(active, hn::Le(squaredNorm(p), hn::Mul(reach, reach)));
    }
    case ItemType::kGrid: {
      const M box = hn::And(active, boxTouches(d, p, item.half, r));
      if (hn::AllFalse(d, box)) return box;
      return hn::And(box, hn::Le(gridBound(d, item, p), r));
    }
  }
  return active;
}

/// Lanes (of `active`) where a leaf below `node` of the link at `pose`
/// touches the item.
M nodeTouchesItem(D d, const Program& program, const Pose& pose, int node, const Item& item,
                  M active) {
  const Node& n = program.nodes[static_cast<std::size_t>(node)];
  const M touching =
      itemTouches(d, item, transform(d, pose, n.x, n.y, n.z), hn::Set(d, n.r), active);
  if (n.left < 0 || hn::AllFalse(d, touching)) return touching;
  const M left = nodeTouchesItem(d, program, pose, n.left, item, touching);
  const M rest = hn::AndNot(left, touching);
  if (hn::AllFalse(d, rest)) return left;
  return hn::Or(left, nodeTouchesItem(d, program, pose, n.right, item, rest));
}

/// Lanes (of `active`) where a leaf below node a (link at pa) touches a
/// leaf below node b (link at pb).
M nodesTouch(D d, const Program& program, const Pose& pa, int a, const Pose& pb, int b, M active) {
  const Node& na = program.nodes[static_cast<std::size_t>(a)];
  const Node& nb = program.nodes[static_cast<std::size_t>(b)];
  const Vec3 ca = transform(d, pa, na.x, na.y, na.z), cb = transform(d, pb, nb.x, nb.y, nb.z);
  const Vec3 gap{hn::Sub(ca.x, cb.x), hn::Sub(ca.y, cb.y), hn::Sub(ca.z, cb.z)};
  const V reach = hn::Set(d, na.r + nb.r);
  const M touching = hn::And(active, hn::Le(squaredNorm(gap), hn::Mul(reach, reach)));
  if (hn::AllFalse(d, touching) || (na.left < 0 && nb.left < 0)) return touching;
  // Descend the larger node (or the one that can).
  const bool splitA = nb.left < 0 || (na.left >= 0 && na.r >= nb.r);
  const int first = splitA ? na.left : nb.left, second = splitA ? na.right : nb.right;
  const M left = splitA ? nodesTouch(d, program, pa, first, pb, b, touching)
                        : nodesTouch(d, program, pa, a, pb, first, touching);
  const M rest = hn::AndNot(left, touching);
  if (hn::AllFalse(d, rest)) return left;
  return hn::Or(left, splitA ? nodesTouch(d, program, pa, second, pb, b, rest)
                             : nodesTouch(d, program, pa, a, pb, second, rest));
}

std::uint32_t laneBits(D d, M mask) {
  std::uint8_t bytes[8] = {};
  hn::StoreMaskBits(d, mask, bytes);
  return static_cast<std::uint32_t>(bytes[0]) | (static_cast<std::uint32_t>(bytes[1]) << 8);
}

M laneMask(D d, std::uint32_t bits) {
  const std::uint8_t bytes[8] = {static_cast<std::uint8_t>(bits & 0xffu),
                                 static_cast<std::uint8_t>(bits >> 8),
                                 0,
                                 0,
                                 0,
                                 0,
                                 0,
                                 0};
  return hn::LoadMaskBits(d, bytes);
}

std::size_t BatchSizeImpl() {
  return hn::Lanes(D());
}

void FindTouchingImpl(const Program& program, const float* q, std::size_t count,
                      bool allowFingertipContact, Visit visit, void* context) {
  const D d;
  const std::size_t n = hn::Lanes(d);
  const std::size_t links = static_cast<std::size_t>(program.num_links);
  // Link poses, then each link's root centre: 15 vectors per link.
  thread_local hwy::AlignedFreeUniquePtr<float[]> scratch;
  thread_local std::size_t scratchSize = 0;
  if (scratchSize < links * 15 * n) {
    scratchSize = links * 15 * n;
    scratch = hwy::AllocateAligned<float>(scratchSize);
  }
  float* poses = scratch.get();
  float* roots = poses + links * 12 * n;
  forwardKinematics(d, program, q, poses);
  auto pose = [&](std::size_t link) { return Pose{poses + link * 12 * n, n}; };
  for (std::size_t l = 0; l < links; ++l) {
    const int root = program.root[l];
    if (root < 0) continue;
    const Node& node = program.nodes[static_cast<std::size_t>(root)];
    const Vec3 c = transform(d, pose(l), node.x, node.y, node.z);
    hn::Store(c.x, d, roots + (3 * l) * n);
    hn::Store(c.y, d, roots + (3 * l + 1) * n);
    hn::Store(c.z, d, roots + (3 * l + 2) * n);
  }
  auto rootCenter = [&](std::size_t link) {
    return Vec3{hn::Load(d, roots + (3 * link) * n), hn::Load(d, roots + (3 * link + 1) * n),
                hn::Load(d, roots + (3 * link + 2) * n)};
  };
  M active = hn::FirstN(d, count);
  // Hands the touching lanes of pair `index` to the visitor; false when no lane is left.
  auto report = [&](std::size_t index, M touching) {
    if (hn::AllFalse(d, touching)) return true;
    active = hn::And(active, laneMask(d, visit(context, static_cast<std::uint32_t>(index),
                                               laneBits(d, touching))));
    return !hn::AllFalse(d, active);
  };
  for (std::size_t i = 0; i < program.env.size(); ++i) {
    const EnvPair& pair = program.env[i];
    const Item& item = program.items[pair.item];
    if (allowFingertipContact && item.target && program.fingertip[pair.link] != 0) continue;
    const int root = program.root[pair.link];
    // The item's bounding sphere first: one distance, no frame change.
    const Vec3 c = rootCenter(pair.link);
    const Vec3 gap{hn::Sub(c.x, hn::Set(d, item.bound[0])), hn::Sub(c.y, hn::Set(d, item.bound[1])),
                   hn::Sub(c.z, hn::Set(d, item.bound[2]))};
    const V reach = hn::Set(d, program.nodes[static_cast<std::size_t>(root)].r + item.bound[3]);
    const M near = hn::And(active, hn::Le(squaredNorm(gap), hn::Mul(reach, reach)));
    if (hn::AllFalse(d, near)) continue;
    if (!report(i, nodeTouchesItem(d, program, pose(pair.link), root, item, near))) return;
  }
  for (std::size_t i = 0; i < program.self.size(); ++i) {
    const SelfPair& pair = program.self[i];
    const int ra = program.root[pair.a], rb = program.root[pair.b];
    const Vec3 a = rootCenter(pair.a), b = rootCenter(pair.b);
    const Vec3 gap{hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)};
    const V reach = hn::Set(d, program.nodes[static_cast<std::size_t>(ra)].r +
                                   program.nodes[static_cast<std::size_t>(rb)].r);
    const M near = hn::And(active, hn::Le(squaredNorm(gap), hn::Mul(reach, reach)));
    if (hn::AllFalse(d, near)) continue;
    if (!report(program.env.size() + i,
                nodesTouch(d, program, pose(pair.a), ra, pose(pair.b), rb, near)))
      return;
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace hfts::robot::kernel
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace hfts::robot::kernel {

HWY_EXPORT(BatchSizeImpl);
HWY_EXPORT(FindTouchingImpl);

std::size_t batchSize() {
  static const std::size_t size = HWY_DYNAMIC_DISPATCH(BatchSizeImpl)();
  return size;
}

void findTouching(const Program& program, const float* q, std::size_t count,
                  bool allowFingertipContact, Visit visit, void* context) {
  HWY_DYNAMIC_DISPATCH(FindTouchingImpl)(program, q, count, allowFingertipContact, visit, context);
}

}  // namespace hfts::robot::kernel
#endif
