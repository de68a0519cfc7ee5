// Compiled once per SIMD target (SSE4, AVX2, AVX-512, ...) through
// Highway's foreach_target; batchSize() and findTouching() dispatch to the
// best one the CPU supports.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sphere_kernel.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/aligned_allocator.h>
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>

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
                         hn::LoadU(d, q + static_cast<std::size_t>(step.dof) * n),
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
M nodesTouch(D d, const Program& program, const Pose& pa, int a, const Vec3& ca, const Pose& pb,
             int b, const Vec3& cb, M active) {
  const Node& na = program.nodes[static_cast<std::size_t>(a)];
  const Node& nb = program.nodes[static_cast<std::size_t>(b)];
  const Vec3 gap{hn::Sub(ca.x, cb.x), hn::Sub(ca.y, cb.y), hn::Sub(ca.z, cb.z)};
  const V reach = hn::Set(d, na.r + nb.r);
  const M touching = hn::And(active, hn::Le(squaredNorm(gap), hn::Mul(reach, reach)));
  if (hn::AllFalse(d, touching) || (na.left < 0 && nb.left < 0)) return touching;
  // Descend the larger node (or the one that can); the other keeps its centre.
  const bool splitA = nb.left < 0 || (na.left >= 0 && na.r >= nb.r);
  const Pose& split = splitA ? pa : pb;
  auto child = [&](int node, M lanes) {
    const Node& n = program.nodes[static_cast<std::size_t>(node)];
    const Vec3 c = transform(d, split, n.x, n.y, n.z);
    return splitA ? nodesTouch(d, program, pa, node, c, pb, b, cb, lanes)
                  : nodesTouch(d, program, pa, a, ca, pb, node, c, lanes);
  };
  const M left = child(splitA ? na.left : nb.left, touching);
  const M rest = hn::AndNot(left, touching);
  if (hn::AllFalse(d, rest)) return left;
  return hn::Or(left, child(splitA ? na.right : nb.right, rest));
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

/// The lanes whose configuration lies in a cell where the self pair's map
/// proves it apart (none where the pair has no map).
M mapApart(D d, const SelfMap& map, const float* q) {
  const std::size_t n = hn::Lanes(d);
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  M valid = hn::FirstN(d, n);
  auto cell = hn::Zero(di);
  for (int k = 0; k < SelfMap::kDofs; ++k) {
    const V t = hn::Mul(hn::Sub(hn::LoadU(d, q + static_cast<std::size_t>(map.dof[k]) * n),
                                hn::Set(d, map.lower[k])),
                        hn::Set(d, map.inverse[k]));
    valid = hn::And(valid, hn::And(hn::Ge(t, hn::Zero(d)), hn::Lt(t, hn::Set(d, map.cells[k]))));
    cell = hn::Add(cell, hn::Mul(hn::Set(di, map.stride[k]), hn::ConvertTo(di, t)));
  }
  if (hn::AllFalse(d, valid)) return valid;
  cell = hn::IfThenElseZero(hn::RebindMask(di, valid), cell);
  const auto words =
      hn::BitCast(du, hn::GatherIndex(di, reinterpret_cast<const std::int32_t*>(map.bits),
                                      hn::ShiftRight<5>(cell)));
  const auto bit = hn::And(hn::BitCast(du, cell), hn::Set(du, 31u));
  const auto set = hn::And(hn::operator>>(words, bit), hn::Set(du, 1u));
  return hn::And(valid, hn::RebindMask(d, hn::Eq(set, hn::Set(du, 1u))));
}

/// One configuration: does the self pair's map prove it apart?
HWY_INLINE bool mapApartOne(const SelfMap& map, const float* q) {
  std::uint32_t cell = 0;
  for (int k = 0; k < SelfMap::kDofs; ++k) {
    const float t = (q[map.dof[k]] - map.lower[k]) * map.inverse[k];
    if (!(t >= 0.0f && t < map.cells[k])) return false;
    cell += static_cast<std::uint32_t>(map.stride[k]) * static_cast<std::uint32_t>(t);
  }
  return ((map.bits[cell / 32] >> (cell % 32)) & 1u) != 0;
}

// ---------------------------------------------------------------------------
// The broadphase shared by both: link spheres (one configuration's root
// spheres, or a batch's swept spheres) against the items and each other,
// a vector of links at a time.

/// A sphere per link, a field per array, padded to a multiple of the
/// lanes with spheres far from everything.
struct LinkSpheres {
  float* x;
  float* y;
  float* z;
  float* r;
  std::size_t padded;
};

/// The pairs whose link spheres touch, in the exact check's order: indices
/// into Program::env (by link, then item) and into Program::self (by a,
/// then b).
void broadphase(D d, const Program& program, const LinkSpheres& s, std::vector<int>& env,
                std::vector<int>& self) {
  const std::size_t n = hn::Lanes(d), links = static_cast<std::size_t>(program.num_links);
  const std::size_t words = program.link_words, items = program.items.size();
  thread_local std::vector<std::uint64_t> near, touching;
  // Sets of links as bit words (chunks of n lanes never straddle a word),
  // each gathered in a register and stored once.
  const std::size_t padded = s.padded;
  const float *sx = s.x, *sy = s.y, *sz = s.z, *sr = s.r;
  auto wordEnds = [&](std::size_t l) { return (l + n) % 64 == 0 || l + n >= padded; };
  near.assign(items * words, 0);
  for (std::size_t i = 0; i < items; ++i) {
    const Item& item = program.items[i];
    const Vec3 center{hn::Set(d, item.bound[0]), hn::Set(d, item.bound[1]),
                      hn::Set(d, item.bound[2])};
    const V radius = hn::Set(d, item.bound[3]);
    std::uint64_t word = 0;
    for (std::size_t l = 0; l < padded; l += n) {
      const Vec3 c{hn::Load(d, sx + l), hn::Load(d, sy + l), hn::Load(d, sz + l)};
      const V r = hn::Load(d, sr + l);
      // The item's bounding sphere first: one distance, no frame change.
      const Vec3 gap{hn::Sub(c.x, center.x), hn::Sub(c.y, center.y), hn::Sub(c.z, center.z)};
      const V reach = hn::Add(r, radius);
      const M bound = hn::Le(squaredNorm(gap), hn::Mul(reach, reach));
      if (!hn::AllFalse(d, bound))
        word |= static_cast<std::uint64_t>(laneBits(d, itemTouches(d, item, c, r, bound)))
                << (l % 64);
      if (wordEnds(l)) {
        near[i * words + l / 64] = word;
        word = 0;
      }
    }
  }
  // The pairs in the exact check's order (by link, then item: env_index
  // grows that way), over the few items some link is near.
  thread_local std::vector<std::size_t> nearItems;
  nearItems.clear();
  for (std::size_t i = 0; i < items; ++i)
    for (std::size_t w = 0; w < words; ++w)
      if (near[i * words + w] != 0) {
        nearItems.push_back(i);
        break;
      }
  env.clear();
  for (std::size_t link = 0; link < links && !nearItems.empty(); ++link) {
    const std::size_t w = link / 64;
    const std::uint64_t bit = std::uint64_t{1} << (link % 64);
    for (const std::size_t i : nearItems) {
      if ((near[i * words + w] & bit) == 0) continue;
      const int index = program.env_index[link * items + i];
      if (index >= 0) env.push_back(index);
    }
  }
  touching.assign(links * words, 0);
  for (std::size_t a = 0; a < links; ++a) {
    if (program.root[a] < 0) continue;
    const Vec3 c{hn::Set(d, sx[a]), hn::Set(d, sy[a]), hn::Set(d, sz[a])};
    const V r = hn::Set(d, sr[a]);
    std::uint64_t word = 0;
    for (std::size_t l = 0; l < padded; l += n) {
      const Vec3 gap{hn::Sub(c.x, hn::Load(d, sx + l)), hn::Sub(c.y, hn::Load(d, sy + l)),
                     hn::Sub(c.z, hn::Load(d, sz + l))};
      const V reach = hn::Add(r, hn::Load(d, sr + l));
      word |=
          static_cast<std::uint64_t>(laneBits(d, hn::Le(squaredNorm(gap), hn::Mul(reach, reach))))
          << (l % 64);
      if (wordEnds(l)) {
        touching[a * words + l / 64] = word;
        word = 0;
      }
    }
  }
  self.clear();
  for (std::size_t a = 0; a < links; ++a)
    for (std::size_t w = 0; w < words; ++w)
      for (std::uint64_t bits = touching[a * words + w] & program.self_mask[a * words + w];
           bits != 0; bits &= bits - 1) {
        const std::size_t b = 64 * w + static_cast<std::size_t>(__builtin_ctzll(bits));
        self.push_back(program.self_index[a * links + b]);
      }
}

/// Padded link sphere arrays in an aligned buffer.
struct LinkSphereBuffer {
  hwy::AlignedFreeUniquePtr<float[]> data;
  std::size_t size = 0;
  LinkSpheres spheres(D d, std::size_t links) {
    const std::size_t n = hn::Lanes(d), padded = (links + n - 1) / n * n;
    if (size < 4 * padded) {
      size = 4 * padded;
      data = hwy::AllocateAligned<float>(size);
    }
    LinkSpheres s{data.get(), data.get() + padded, data.get() + 2 * padded, data.get() + 3 * padded,
                  padded};
    for (std::size_t l = links; l < padded; ++l) {  // far from everything
      s.x[l] = s.y[l] = s.z[l] = 1e30f;
      s.r[l] = 0.0f;
    }
    return s;
  }
};

// ---------------------------------------------------------------------------
// A batch: a configuration per lane.

std::size_t BatchSizeImpl() {
  return hn::Lanes(D());
}

void FindTouchingImpl(const Program& program, const float* q, std::size_t count, Visit visit,
                      void* context) {
  const D d;
  const std::size_t n = hn::Lanes(d);
  const std::size_t links = static_cast<std::size_t>(program.num_links);
  // Link poses, then each link's root centre: 15 vectors per link.
  thread_local hwy::AlignedFreeUniquePtr<float[]> scratch;
  thread_local std::size_t scratchSize = 0;
  thread_local LinkSphereBuffer swept;
  thread_local std::vector<int> envPairs, selfPairs;
  if (scratchSize < links * 15 * n) {
    scratchSize = links * 15 * n;
    scratch = hwy::AllocateAligned<float>(scratchSize);
  }
  float* poses = scratch.get();
  float* roots = poses + links * 12 * n;
  forwardKinematics(d, program, q, poses);
  auto pose = [&](std::size_t link) { return Pose{poses + link * 12 * n, n}; };
  auto rootCenter = [&](std::size_t link) {
    return Vec3{hn::Load(d, roots + (3 * link) * n), hn::Load(d, roots + (3 * link + 1) * n),
                hn::Load(d, roots + (3 * link + 2) * n)};
  };
  M active = hn::FirstN(d, count);
  // Each link's root spheres in all lanes, and a sphere holding them (a
  // batch's configurations are usually states of one short motion).
  const LinkSpheres sweep = swept.spheres(d, links);
  for (std::size_t l = 0; l < links; ++l) {
    const int root = program.root[l];
    if (root < 0) {
      sweep.x[l] = sweep.y[l] = sweep.z[l] = 1e30f;
      sweep.r[l] = 0.0f;
      continue;
    }
    const Node& node = program.nodes[static_cast<std::size_t>(root)];
    Vec3 c = transform(d, pose(l), node.x, node.y, node.z);
    // Inactive lanes repeat lane 0 (always active).
    c = Vec3{hn::IfThenElse(active, c.x, hn::Set(d, hn::GetLane(c.x))),
             hn::IfThenElse(active, c.y, hn::Set(d, hn::GetLane(c.y))),
             hn::IfThenElse(active, c.z, hn::Set(d, hn::GetLane(c.z)))};
    hn::Store(c.x, d, roots + (3 * l) * n);
    hn::Store(c.y, d, roots + (3 * l + 1) * n);
    hn::Store(c.z, d, roots + (3 * l + 2) * n);
    const Vec3 mid{hn::Set(d, hn::GetLane(c.x)), hn::Set(d, hn::GetLane(c.y)),
                   hn::Set(d, hn::GetLane(c.z))};
    const Vec3 gap{hn::Sub(c.x, mid.x), hn::Sub(c.y, mid.y), hn::Sub(c.z, mid.z)};
    sweep.x[l] = hn::GetLane(mid.x);
    sweep.y[l] = hn::GetLane(mid.y);
    sweep.z[l] = hn::GetLane(mid.z);
    // Rounded up a little: the swept sphere must hold every lane's sphere.
    sweep.r[l] =
        std::sqrt(hn::GetLane(hn::MaxOfLanes(d, squaredNorm(gap)))) * 1.0001f + 1e-6f + node.r;
  }
  broadphase(d, program, sweep, envPairs, selfPairs);
  // Hands the touching lanes of pair `index` to the visitor; false when no lane is left.
  auto report = [&](std::size_t index, M touching) {
    if (hn::AllFalse(d, touching)) return true;
    active = hn::And(active, laneMask(d, visit(context, static_cast<std::uint32_t>(index),
                                               laneBits(d, touching))));
    return !hn::AllFalse(d, active);
  };
  for (const int index : envPairs) {
    const EnvPair& pair = program.env[static_cast<std::size_t>(index)];
    const Item& item = program.items[pair.item];
    const int root = program.root[pair.link];
    const Vec3 c = rootCenter(pair.link);
    const Vec3 gap{hn::Sub(c.x, hn::Set(d, item.bound[0])), hn::Sub(c.y, hn::Set(d, item.bound[1])),
                   hn::Sub(c.z, hn::Set(d, item.bound[2]))};
    const V reach = hn::Set(d, program.nodes[static_cast<std::size_t>(root)].r + item.bound[3]);
    const M near = hn::And(active, hn::Le(squaredNorm(gap), hn::Mul(reach, reach)));
    if (hn::AllFalse(d, near)) continue;
    if (!report(static_cast<std::size_t>(index),
                nodeTouchesItem(d, program, pose(pair.link), root, item, near)))
      return;
  }
  for (const int index : selfPairs) {
    const SelfPair& pair = program.self[static_cast<std::size_t>(index)];
    const int ra = program.root[pair.a], rb = program.root[pair.b];
    const Vec3 a = rootCenter(pair.a), b = rootCenter(pair.b);
    const Vec3 gap{hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)};
    const V reach = hn::Set(d, program.nodes[static_cast<std::size_t>(ra)].r +
                                   program.nodes[static_cast<std::size_t>(rb)].r);
    M near = hn::And(active, hn::Le(squaredNorm(gap), hn::Mul(reach, reach)));
    if (hn::AllFalse(d, near)) continue;
    const SelfMap& map = program.self_maps[static_cast<std::size_t>(index)];
    if (map.bits != nullptr) {
      near = hn::AndNot(mapApart(d, map, q), near);
      if (hn::AllFalse(d, near)) continue;
    }
    if (!report(program.env.size() + static_cast<std::size_t>(index),
                nodesTouch(d, program, pose(pair.a), ra, a, pose(pair.b), rb, b, near)))
      return;
  }
}

// ---------------------------------------------------------------------------
// One configuration: lanes over link pairs and sphere pairs.

using DI = hn::RebindToSigned<D>;
using VI = hn::Vec<DI>;

/// A link's pose, row by row: m[4 r + c] is rotation entry (r, c) for
/// c < 3 and m[4 r + 3] translation component r.
struct ScalarPose {
  alignas(16) float m[12];
};

/// Single-precision forward kinematics of one configuration; the sines
/// and cosines of every joint in one SIMD pass, then a pose's three rows
/// as vectors of four.
void forwardKinematicsOne(D d, const Program& program, const float* q, ScalarPose* poses,
                          float* angles) {
  const std::size_t n = hn::Lanes(d), steps = program.steps.size();
  const std::size_t padded = (steps + n - 1) / n * n;
  float* sines = angles + padded;
  float* cosines = sines + padded;
  for (std::size_t i = 0; i < padded; ++i) {
    const FkStep* step = i < steps ? &program.steps[i] : nullptr;
    angles[i] = step != nullptr && step->dof >= 0
                    ? step->multiplier * q[static_cast<std::size_t>(step->dof)] + step->offset
                    : 0.0f;
  }
  for (std::size_t i = 0; i < padded; i += n) {
    const V v = hn::Load(d, angles + i);
    hn::Store(hn::Sin(d, v), d, sines + i);
    hn::Store(hn::Cos(d, v), d, cosines + i);
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) poses[0].m[4 * r + c] = program.base[3 * r + c];
    poses[0].m[4 * r + 3] = program.base[9 + r];
  }
#if HWY_TARGET == HWY_SCALAR
  for (std::size_t i = 0; i < steps; ++i) {
    const FkRows& step = program.fk_rows[i];
    const float* p = poses[program.steps[i].parent].m;
    float* c = poses[program.steps[i].child].m;
    float joint[12];
    for (int k = 0; k < 12; ++k)
      joint[k] = step.a[k] + cosines[i] * step.b[k] + sines[i] * step.c[k] + angles[i] * step.dt[k];
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 4; ++col)
        c[4 * r + col] = p[4 * r] * joint[col] + p[4 * r + 1] * joint[4 + col] +
                         p[4 * r + 2] * joint[8 + col] + (col == 3 ? p[4 * r + 3] : 0.0f);
  }
#else
  // child row r = p[r][0] J row 0 + p[r][1] J row 1 + p[r][2] J row 2 + (0, 0, 0, p[r][3]),
  // with the joint's translation in lane 3 of its rows.
  const hn::FixedTag<float, 4> d4;
  using V4 = hn::Vec<decltype(d4)>;
  alignas(16) static constexpr float kLast[4] = {0, 0, 0, 1};
  const V4 last = hn::Load(d4, kLast);
  for (std::size_t i = 0; i < steps; ++i) {
    const FkStep& step = program.steps[i];
    const FkRows& rows = program.fk_rows[i];
    V4 joint[3];
    for (int r = 0; r < 3; ++r) joint[r] = hn::Load(d4, rows.a + 4 * r);
    if (step.revolute) {
      const V4 c = hn::Set(d4, cosines[i]), s = hn::Set(d4, sines[i]);
      for (int r = 0; r < 3; ++r)
        joint[r] = hn::MulAdd(s, hn::Load(d4, rows.c + 4 * r),
                              hn::MulAdd(c, hn::Load(d4, rows.b + 4 * r), joint[r]));
    } else if (step.dof >= 0) {
      const V4 v = hn::Set(d4, angles[i]);
      for (int r = 0; r < 3; ++r) joint[r] = hn::MulAdd(v, hn::Load(d4, rows.dt + 4 * r), joint[r]);
    }
    const float* p = poses[step.parent].m;
    float* c = poses[step.child].m;
    for (int r = 0; r < 3; ++r) {
      const V4 row = hn::Load(d4, p + 4 * r);
      hn::Store(
          hn::MulAdd(hn::Broadcast<0>(row), joint[0],
                     hn::MulAdd(hn::Broadcast<1>(row), joint[1],
                                hn::MulAdd(hn::Broadcast<2>(row), joint[2], hn::Mul(row, last)))),
          d4, c + 4 * r);
    }
  }
#endif
}

/// World centres of a wide node's slots, the link at `pose`.
HWY_INLINE Vec3 slotCenters(D d, const WideNode& node, std::size_t first, const ScalarPose& pose) {
  const V x = hn::Load(d, node.x + first), y = hn::Load(d, node.y + first),
          z = hn::Load(d, node.z + first);
  const float* m = pose.m;
  return Vec3{
      hn::MulAdd(
          hn::Set(d, m[0]), x,
          hn::MulAdd(hn::Set(d, m[1]), y, hn::MulAdd(hn::Set(d, m[2]), z, hn::Set(d, m[3])))),
      hn::MulAdd(
          hn::Set(d, m[4]), x,
          hn::MulAdd(hn::Set(d, m[5]), y, hn::MulAdd(hn::Set(d, m[6]), z, hn::Set(d, m[7])))),
      hn::MulAdd(
          hn::Set(d, m[8]), x,
          hn::MulAdd(hn::Set(d, m[9]), y, hn::MulAdd(hn::Set(d, m[10]), z, hn::Set(d, m[11]))))};
}

/// Calls f(slot) for every set bit of a mask of `first`.. slots.
template <typename F>
HWY_INLINE void forEachSlot(D d, M mask, std::size_t first, F&& f) {
  for (std::uint32_t bits = laneBits(d, mask); bits != 0; bits &= bits - 1)
    f(first + static_cast<std::size_t>(__builtin_ctz(bits)));
}

/// World centres of wide nodes' slots (x, then y, then z, kSlots each per
/// node), each computed at most once per configuration: a link pair's
/// descent meets the same nodes again, and so do the pairs of one link.
class CentreCache {
 public:
  /// Forgets the last configuration's centres.
  void reset(std::size_t nodes) {
    if (stamp_.size() < nodes) {
      stamp_.assign(nodes, 0);
      xyz_ = hwy::AllocateAligned<float>(nodes * 3 * WideNode::kSlots);
      generation_ = 0;
    }
    if (++generation_ == 0) {  // wrapped: every stamp is stale
      std::fill(stamp_.begin(), stamp_.end(), 0u);
      generation_ = 1;
    }
  }
  /// The centres of wide node `index` (of the link at `pose`).
  const float* centres(D d, const Program& program, int index, const ScalarPose& pose) {
    const auto i = static_cast<std::size_t>(index);
    float* out = xyz_.get() + i * 3 * WideNode::kSlots;
    if (stamp_[i] == generation_) return out;
    stamp_[i] = generation_;
    const WideNode& node = program.wide[i];
    for (std::size_t first = 0; first < node.count; first += hn::Lanes(d)) {
      const Vec3 c = slotCenters(d, node, first, pose);
      hn::Store(c.x, d, out + first);
      hn::Store(c.y, d, out + WideNode::kSlots + first);
      hn::Store(c.z, d, out + 2 * WideNode::kSlots + first);
    }
    return out;
  }

 private:
  hwy::AlignedFreeUniquePtr<float[]> xyz_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t generation_ = 0;
};

HWY_INLINE Vec3 loadCentres(D d, const float* centres, std::size_t first) {
  return Vec3{hn::Load(d, centres + first), hn::Load(d, centres + WideNode::kSlots + first),
              hn::Load(d, centres + 2 * WideNode::kSlots + first)};
}

/// A sphere of a descent: world centre, radius, and the wide node of the
/// spheres below it (-1 for a leaf).
struct Sphere {
  float x, y, z, r;
  int below;
};

/// Does a leaf below wide node `top` of a link at `pose` touch the item?
/// Depth first, a wide node's slots at a time.
bool linkTouchesItem(D d, const Program& program, const ScalarPose& pose, int top, const Item& item,
                     CentreCache& cache, std::vector<int>& stack) {
  const std::size_t n = hn::Lanes(d);
  stack.assign(1, top);
  while (!stack.empty()) {
    const int index = stack.back();
    const WideNode& node = program.wide[static_cast<std::size_t>(index)];
    stack.pop_back();
    const float* centres = cache.centres(d, program, index, pose);
    for (std::size_t first = 0; first < node.count; first += n) {
      const M touching =
          itemTouches(d, item, loadCentres(d, centres, first), hn::Load(d, node.r + first),
                      hn::FirstN(d, node.count - first));
      if (hn::AllFalse(d, touching)) continue;
      bool leaf = false;
      forEachSlot(d, touching, first, [&](std::size_t slot) {
        if (node.below[slot] < 0)
          leaf = true;
        else
          stack.push_back(node.below[slot]);
      });
      if (leaf) return true;
    }
  }
  return false;
}

/// Does a leaf of link a touch a leaf of link b, given root spheres that
/// touch? Depth first over sphere pairs: the larger sphere of a pair is
/// replaced by its wide node's slots, tested against the other at once.
bool linksTouchOne(D d, const Program& program, const ScalarPose& pa, Sphere a,
                   const ScalarPose& pb, Sphere b, CentreCache& cache, std::vector<Sphere>& stack) {
  const std::size_t n = hn::Lanes(d);
  stack.clear();
  stack.push_back(a);
  stack.push_back(b);
  while (!stack.empty()) {
    b = stack.back();
    stack.pop_back();
    a = stack.back();
    stack.pop_back();
    if (a.below < 0 && b.below < 0) return true;
    // Split a where b is a leaf or a is at least as large (and can be split).
    const bool splitA = a.below >= 0 && (b.below < 0 || a.r >= b.r);
    const Sphere& kept = splitA ? b : a;
    const int index = splitA ? a.below : b.below;
    const WideNode& node = program.wide[static_cast<std::size_t>(index)];
    const float* centres = cache.centres(d, program, index, splitA ? pa : pb);
    for (std::size_t first = 0; first < node.count; first += n) {
      const Vec3 c = loadCentres(d, centres, first);
      const Vec3 gap{hn::Sub(c.x, hn::Set(d, kept.x)), hn::Sub(c.y, hn::Set(d, kept.y)),
                     hn::Sub(c.z, hn::Set(d, kept.z))};
      const V reach = hn::Add(hn::Load(d, node.r + first), hn::Set(d, kept.r));
      const M touching = hn::And(hn::FirstN(d, node.count - first),
                                 hn::Le(squaredNorm(gap), hn::Mul(reach, reach)));
      if (hn::AllFalse(d, touching)) continue;
      forEachSlot(d, touching, first, [&](std::size_t slot) {
        const Sphere split{centres[slot], centres[WideNode::kSlots + slot],
                           centres[2 * WideNode::kSlots + slot], node.r[slot], node.below[slot]};
        stack.push_back(splitA ? split : kept);
        stack.push_back(splitA ? kept : split);
      });
    }
  }
  return false;
}

void FindTouchingOneImpl(const Program& program, const float* q, Visit visit, void* context) {
  const D d;
  const std::size_t n = hn::Lanes(d);
  const std::size_t links = static_cast<std::size_t>(program.num_links);
  thread_local std::vector<ScalarPose> poses;
  thread_local hwy::AlignedFreeUniquePtr<float[]> angles;
  thread_local std::size_t anglesSize = 0;
  thread_local LinkSphereBuffer roots;
  thread_local std::vector<int> envPairs, selfPairs, itemStack;
  thread_local std::vector<Sphere> pairStack;
  thread_local CentreCache centres;
  const std::size_t needed = 3 * ((program.steps.size() + n - 1) / n * n);
  if (anglesSize < needed) {
    anglesSize = needed;
    angles = hwy::AllocateAligned<float>(anglesSize);
  }
  poses.resize(links);
  forwardKinematicsOne(d, program, q, poses.data(), angles.get());
  const LinkSpheres root = roots.spheres(d, links);
  for (std::size_t l = 0; l < links; ++l) {
    if (program.root[l] < 0) {
      root.x[l] = root.y[l] = root.z[l] = 1e30f;
      root.r[l] = 0.0f;
      continue;
    }
    const Node& node = program.nodes[static_cast<std::size_t>(program.root[l])];
    const float* m = poses[l].m;
    root.x[l] = m[0] * node.x + m[1] * node.y + m[2] * node.z + m[3];
    root.y[l] = m[4] * node.x + m[5] * node.y + m[6] * node.z + m[7];
    root.z[l] = m[8] * node.x + m[9] * node.y + m[10] * node.z + m[11];
    root.r[l] = node.r;
  }
  broadphase(d, program, root, envPairs, selfPairs);
  centres.reset(program.wide.size());
  for (const int index : envPairs) {
    const EnvPair& pair = program.env[static_cast<std::size_t>(index)];
    const int top = program.wide_root[pair.link];
    if ((top < 0 || linkTouchesItem(d, program, poses[pair.link], top, program.items[pair.item],
                                    centres, itemStack)) &&
        visit(context, static_cast<std::uint32_t>(index), 1u) == 0)
      return;
  }
  for (const int index : selfPairs) {
    const SelfMap& map = program.self_maps[static_cast<std::size_t>(index)];
    if (map.bits != nullptr && mapApartOne(map, q)) continue;
    const SelfPair& pair = program.self[static_cast<std::size_t>(index)];
    const Sphere a{root.x[pair.a], root.y[pair.a], root.z[pair.a], root.r[pair.a],
                   program.wide_root[pair.a]};
    const Sphere b{root.x[pair.b], root.y[pair.b], root.z[pair.b], root.r[pair.b],
                   program.wide_root[pair.b]};
    if (linksTouchOne(d, program, poses[pair.a], a, poses[pair.b], b, centres, pairStack) &&
        visit(context,
              static_cast<std::uint32_t>(program.env.size()) + static_cast<std::uint32_t>(index),
              1u) == 0)
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
HWY_EXPORT(FindTouchingOneImpl);

std::size_t batchSize() {
  static const std::size_t size = HWY_DYNAMIC_DISPATCH(BatchSizeImpl)();
  return size;
}

void findTouching(const Program& program, const float* q, std::size_t count, Visit visit,
                  void* context) {
  HWY_DYNAMIC_DISPATCH(FindTouchingImpl)(program, q, count, visit, context);
}

void findTouchingOne(const Program& program, const float* q, Visit visit, void* context) {
  HWY_DYNAMIC_DISPATCH(FindTouchingOneImpl)(program, q, visit, context);
}

namespace {

/// A wide node holding the spheres below binary node `node` (internal): the
/// frontier of its subtree, widened at its largest sphere while it fits.
int collapse(Program& program, int node) {
  const std::vector<Node>& nodes = program.nodes;
  std::vector<int> frontier{nodes[static_cast<std::size_t>(node)].left,
                            nodes[static_cast<std::size_t>(node)].right};
  while (frontier.size() < WideNode::kSlots) {
    std::size_t largest = frontier.size();
    for (std::size_t i = 0; i < frontier.size(); ++i) {
      const Node& f = nodes[static_cast<std::size_t>(frontier[i])];
      if (f.left >= 0 && (largest == frontier.size() ||
                          f.r > nodes[static_cast<std::size_t>(frontier[largest])].r))
        largest = i;
    }
    if (largest == frontier.size()) break;
    const Node& split = nodes[static_cast<std::size_t>(frontier[largest])];
    frontier[largest] = split.left;
    frontier.push_back(split.right);
  }
  int below[WideNode::kSlots];
  for (std::size_t i = 0; i < frontier.size(); ++i)
    below[i] = nodes[static_cast<std::size_t>(frontier[i])].left >= 0
                   ? collapse(program, frontier[i])
                   : -1;
  WideNode wide;
  wide.count = frontier.size();
  for (std::size_t i = 0; i < WideNode::kSlots; ++i) {
    const bool used = i < frontier.size();
    const Node* f = used ? &nodes[static_cast<std::size_t>(frontier[i])] : nullptr;
    wide.x[i] = used ? f->x : 1e30f;  // unused slots: far from everything
    wide.y[i] = used ? f->y : 1e30f;
    wide.z[i] = used ? f->z : 1e30f;
    wide.r[i] = used ? f->r : 0.0f;
    wide.below[i] = used ? below[i] : -1;
  }
  program.wide.push_back(wide);
  return static_cast<int>(program.wide.size()) - 1;
}

}  // namespace

void buildWideTrees(Program& program) {
  program.fk_rows.clear();
  for (const FkStep& step : program.steps) {
    FkRows rows;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        rows.a[4 * r + c] = step.a[3 * r + c];
        rows.b[4 * r + c] = step.revolute ? step.b[3 * r + c] : 0.0f;
        rows.c[4 * r + c] = step.revolute ? step.c[3 * r + c] : 0.0f;
        rows.dt[4 * r + c] = 0.0f;
      }
      rows.a[4 * r + 3] = step.t[r];
      rows.b[4 * r + 3] = rows.c[4 * r + 3] = 0.0f;
      rows.dt[4 * r + 3] = step.dof >= 0 && !step.revolute ? step.dt[r] : 0.0f;
    }
    program.fk_rows.push_back(rows);
  }
  program.wide.clear();
  program.wide_root.assign(program.root.size(), -1);
  for (std::size_t l = 0; l < program.root.size(); ++l) {
    const int root = program.root[l];
    if (root >= 0 && program.nodes[static_cast<std::size_t>(root)].left >= 0)
      program.wide_root[l] = collapse(program, root);
  }
}

void buildLookups(Program& program) {
  const std::size_t links = program.root.size(), items = program.items.size();
  program.env_index.assign(links * items, -1);
  for (std::size_t i = 0; i < program.env.size(); ++i)
    program.env_index[program.env[i].link * items + program.env[i].item] = static_cast<int>(i);
  const std::size_t words = links / 64 + 1;  // room for the kernels' padded link counts
  program.link_words = words;
  program.self_index.assign(links * links, -1);
  program.self_mask.assign(links * words, 0);
  for (std::size_t i = 0; i < program.self.size(); ++i) {
    const SelfPair& pair = program.self[i];
    program.self_index[pair.a * links + pair.b] = static_cast<int>(i);
    program.self_mask[pair.a * words + pair.b / 64] |= std::uint64_t{1} << (pair.b % 64);
  }
}

}  // namespace hfts::robot::kernel
#endif
