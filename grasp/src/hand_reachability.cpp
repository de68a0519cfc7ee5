// R(h) of the paper's Eq. (1) from the hand map: k-d tree over the
// descriptors for every finger order, closed-form alignment of the
// candidates, local refinement of the best (docs/hand_reachability.md).

#include "grasp/hand_reachability.h"

#include <nanoflann.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "core/invalid_argument.h"
#include "hand_alignment.h"
#include "robot/hand_chain.h"

namespace hfts::grasp {
namespace {

/// The ways to put m contacts on m fingers: order[f] is the contact on
/// finger f. All m! permutations, grouped by cyclic rotation (for m = 3:
/// the three rotations of the identity, then those of its reflection).
using Order = std::array<int, robot::hand::kMaxFingers>;

std::vector<Order> fingerOrders(int m) {
  Order first{};
  std::iota(first.begin(), first.begin() + m, 0);
  std::vector<Order> out;
  for (Order p = first;;) {
    if (std::find(out.begin(), out.end(), p) == out.end())
      for (int r = 0; r < m; ++r) {
        Order rotated{};
        for (int f = 0; f < m; ++f)
          rotated[static_cast<std::size_t>(f)] = p[static_cast<std::size_t>((f + r) % m)];
        out.push_back(rotated);
      }
    if (!std::next_permutation(p.begin(), p.begin() + m)) break;
  }
  return out;
}

/// Descriptors searched in single precision: the search only proposes
/// candidates, and floats make it faster.
using DescriptorRows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// nanoflann's view of the descriptor rows, Dim floats each (row-major):
/// the row stride is a compile-time constant in the distance loops.
template <int Dim>
struct DescriptorCloud {
  const float* data = nullptr;
  std::size_t rows = 0;
  std::size_t kdtree_get_point_count() const { return rows; }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return data[i * Dim + d]; }
  template <typename Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

/// A k-d tree over the descriptor rows, of the descriptor's size fixed at
/// compile time (the distance loops unroll) behind one interface.
class DescriptorIndex {
 public:
  virtual ~DescriptorIndex() = default;
  /// Up to `k` approximate nearest rows (relative tolerance `eps`);
  /// returns how many were found.
  virtual std::size_t nearest(const float* query, std::size_t k, float eps, std::uint32_t* indices,
                              float* distances) const = 0;
};

template <int Dim>
class FixedDescriptorIndex final : public DescriptorIndex {
 public:
  explicit FixedDescriptorIndex(const DescriptorRows& rows)
      : cloud_{rows.data(), static_cast<std::size_t>(rows.rows())},
        tree_(Dim, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}

  std::size_t nearest(const float* query, std::size_t k, float eps, std::uint32_t* indices,
                      float* distances) const override {
    nanoflann::KNNResultSet<float, std::uint32_t> result(k);
    result.init(indices, distances);
    tree_.findNeighbors(result, query, nanoflann::SearchParams(0, eps));
    return result.size();
  }

 private:
  using Cloud = DescriptorCloud<Dim>;
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>,
                                                   Cloud, Dim, std::uint32_t>;
  Cloud cloud_;
  Tree tree_;
};

std::unique_ptr<DescriptorIndex> makeIndex(const DescriptorRows& rows) {
  switch (rows.cols()) {
    case 5:
      return std::make_unique<FixedDescriptorIndex<5>>(rows);
    case 12:
      return std::make_unique<FixedDescriptorIndex<12>>(rows);
    case 18:
      return std::make_unique<FixedDescriptorIndex<18>>(rows);
    default:
      throw std::logic_error("no descriptor index of size " + std::to_string(rows.cols()));
  }
}

constexpr std::size_t kMaxNeighbours = 256;

/// R(h) below 1e-6 m counts as exactly reached: no further probe is finished.
constexpr double kExactResidual2 = 1e-12;

struct Candidate {
  double cost = 0.0;
  std::uint32_t sample = 0;
  std::size_t order = 0;  ///< index into the finger orders
};

[[noreturn]] void mismatch(const std::string& robot, const std::string& problem) {
  throw robot::ModelError("hand map does not match robot '" + robot + "': " + problem);
}

void checkOptions(const HandQueryOptions& o) {
  const auto atLeast = [](int value, int minimum, const char* name) {
    if (value < minimum)
      throw InvalidArgument(
          std::string("HandQueryOptions::") + name,
          "must be >= " + std::to_string(minimum) + ", got " + std::to_string(value));
  };
  atLeast(o.neighbours, 1, "neighbours");
  atLeast(o.refined_candidates, 1, "refined_candidates");
  atLeast(o.tracking_stages, 0, "tracking_stages");
  atLeast(o.stage_iterations, 0, "stage_iterations");
  atLeast(o.finished_candidates, 1, "finished_candidates");
  atLeast(o.refine_iterations, 0, "refine_iterations");
  if (o.neighbours > static_cast<int>(kMaxNeighbours))
    throw InvalidArgument(
        "HandQueryOptions::neighbours",
        "must be <= " + std::to_string(kMaxNeighbours) + ", got " + std::to_string(o.neighbours));
  if (!(o.search_tolerance >= 0.0) || !std::isfinite(o.search_tolerance))
    throw InvalidArgument("HandQueryOptions::search_tolerance", "must be >= 0");
}

void checkInput(const Eigen::Matrix3Xd& m, Eigen::Index fingers, const char* name, bool unit) {
  if (m.cols() != fingers)
    throw InvalidArgument(name, "must be 3 x " + std::to_string(fingers) +
                                    " (one column per contact), got 3 x " +
                                    std::to_string(m.cols()));
  if (!m.allFinite()) throw InvalidArgument(name, "holds a non-finite value");
  for (Eigen::Index c = 0; unit && c < fingers; ++c)
    if (std::abs(m.col(c).norm() - 1.0) > 1e-3)
      throw InvalidArgument(name, "column " + std::to_string(c) + " is not a unit vector (norm " +
                                      std::to_string(m.col(c).norm()) + ")");
}

/// Pads within this angle (rad) of the line through two fingertips face
/// along it: turning about the line moves neither tips nor pads.
constexpr double kPadAlongLine = 1e-9;

/// The line through two placed fingertips when both pads face along it.
std::optional<Eigen::ParametrizedLine<double, 3>> freeTurn(const robot::hand::Tips& tips,
                                                           const robot::hand::Tips& pads) {
  const Eigen::Vector3d u = (tips.col(1) - tips.col(0)).normalized();
  for (Eigen::Index f = 0; f < 2; ++f)
    if (!(pads.col(f).cross(u).norm() <= kPadAlongLine)) return std::nullopt;
  return Eigen::ParametrizedLine<double, 3>(tips.col(0), u);
}

robot::hand::Tips tipsOf(const db::RowMatrixXd& rows, std::uint32_t sample) {
  return Eigen::Map<const Eigen::Matrix3Xd>(rows.row(sample).data(), 3, rows.cols() / 3);
}

}  // namespace

struct HandReachability::Impl {
  robot::hand::HandChains chains;
  db::HandMap map;
  HandQueryOptions options;
  int fingers;
  std::vector<Order> orders;
  /// Row (number of orders) s + o: the descriptor of sample s's fingertips
  /// as they sit on contacts given in canonical order under finger order
  /// orders[o], so one k-d tree search covers every assignment of contacts
  /// to fingers.
  DescriptorRows ordered;
  std::unique_ptr<DescriptorIndex> index;
  double span = 0.0;  ///< largest fingertip distance over the samples

  Impl(const robot::RobotModel& model, db::HandMap m, HandQueryOptions o)
      : chains(model),
        map(std::move(m)),
        options(o),
        fingers(chains.numFingers()),
        orders(fingerOrders(fingers)) {
    checkOptions(options);
    db::validateHandMap(map, "hand map of '" + map.robot_name + "'");
    checkMatchesRobot(model.name());
    checkReproducedByKinematics(model.name());
    ordered = orderedDescriptors();
    index = makeIndex(ordered);
    span = largestFingertipDistance();
  }

  double largestFingertipDistance() const {
    double out = 0.0;
    for (std::uint32_t s = 0; s < map.numSamples(); ++s) {
      const robot::hand::Tips tips = tipsOf(map.positions, s);
      for (int i = 0; i < fingers; ++i)
        for (int j = i + 1; j < fingers; ++j)
          out = std::max(out, (tips.col(i) - tips.col(j)).norm());
    }
    return out;
  }

  void checkMatchesRobot(const std::string& robot) const {
    if (map.robot_name != robot) mismatch(robot, "it was built for '" + map.robot_name + "'");
    if (map.dof_names != chains.dofNames()) mismatch(robot, "hand DoF names differ");
    if (map.finger_names != chains.fingerNames()) mismatch(robot, "fingers differ");
    if ((map.lower_limits - chains.lower()).cwiseAbs().maxCoeff() > 1e-12 ||
        (map.upper_limits - chains.upper()).cwiseAbs().maxCoeff() > 1e-12)
      mismatch(robot, "hand joint limits differ");
    const std::string descriptor = handDescriptorName(fingers);
    if (map.descriptor != descriptor || map.descriptors.cols() != handDescriptorSize(fingers))
      mismatch(robot, "descriptor '" + map.descriptor + "' is not '" + descriptor + "'");
  }

  /// A map of another hand geometry (other fingertip points or links)
  /// would give wrong answers silently: spot-check samples across the map.
  void checkReproducedByKinematics(const std::string& robot) const {
    const std::size_t n = map.numSamples(), checks = std::min<std::size_t>(n, 32);
    robot::hand::TipState tips;
    for (std::size_t k = 0; k < checks; ++k) {
      const auto s = static_cast<std::uint32_t>(k * n / checks);
      chains.evaluate(map.configurations.row(s).data(), tips, false);
      const double error = std::max((tips.positions - tipsOf(map.positions, s)).norm(),
                                    (tips.normals - tipsOf(map.normals, s)).norm());
      const auto d = handDescriptor(tips.positions, tips.normals, map.parameters.normal_weight);
      if (error > 1e-9 || (d.transpose() - map.descriptors.row(s)).norm() > 1e-9)
        mismatch(robot, "forward kinematics does not reproduce sample " + std::to_string(s));
    }
  }

  DescriptorRows orderedDescriptors() const {
    const auto n = static_cast<Eigen::Index>(map.numSamples());
    const auto count = static_cast<Eigen::Index>(orders.size());
    DescriptorRows out(n * count, handDescriptorSize(fingers));
    for (Eigen::Index s = 0; s < n; ++s) {
      const robot::hand::Tips tips = tipsOf(map.positions, static_cast<std::uint32_t>(s));
      const robot::hand::Tips pads = tipsOf(map.normals, static_cast<std::uint32_t>(s));
      for (std::size_t o = 0; o < orders.size(); ++o) {
        robot::hand::Tips p(3, fingers), a(3, fingers);  // column c: the finger on contact c
        for (int f = 0; f < fingers; ++f) {
          p.col(orders[o][static_cast<std::size_t>(f)]) = tips.col(f);
          a.col(orders[o][static_cast<std::size_t>(f)]) = pads.col(f);
        }
        out.row(s * count + static_cast<Eigen::Index>(o)) =
            handDescriptor(p, a, map.parameters.normal_weight).transpose().cast<float>();
      }
    }
    return out;
  }

  /// The contacts in the finger order orders[order]; pads face inwards.
  hand::Target target(const Eigen::Matrix3Xd& contacts, const Eigen::Matrix3Xd& outward,
                      std::size_t order) const {
    hand::Target t;
    t.contacts.resize(3, fingers);
    t.pad_normals.resize(3, fingers);
    for (int f = 0; f < fingers; ++f) {
      const int c = orders[order][static_cast<std::size_t>(f)];
      t.contacts.col(f) = contacts.col(c);
      t.pad_normals.col(f) = -outward.col(c);
    }
    t.lambda = map.parameters.normal_weight;
    return t;
  }

  /// The k nearest (sample, finger order) pairs in descriptor space, each
  /// scored by its best alignment, ordered for probing: the best of every
  /// finger order first (near-symmetric hands put wrong orders close to the
  /// right one), then the rest by cost.
  std::vector<Candidate> candidates(const Eigen::Matrix3Xd& contacts,
                                    const Eigen::Matrix3Xd& outward) const {
    std::array<std::uint32_t, kMaxNeighbours> indices;
    std::array<float, kMaxNeighbours> distances;
    const hand::Target given = target(contacts, outward, 0);
    const Eigen::Matrix<float, Eigen::Dynamic, 1, 0, kMaxHandDescriptorSize, 1> d =
        handDescriptor(given.contacts, given.pad_normals, given.lambda).cast<float>();
    const std::size_t found = index->nearest(
        d.data(),
        std::min<std::size_t>(static_cast<std::size_t>(options.neighbours), kMaxNeighbours),
        static_cast<float>(options.search_tolerance), indices.data(), distances.data());
    std::vector<Candidate> out(found);
    for (std::size_t i = 0; i < out.size(); ++i) {
      const std::uint32_t s = static_cast<std::uint32_t>(indices[i] / orders.size());
      const std::size_t o = indices[i] % orders.size();
      const hand::Target t = target(contacts, outward, o);
      out[i] = {hand::alignmentCost(tipsOf(map.positions, s), tipsOf(map.normals, s), t), s, o};
    }
    std::sort(out.begin(), out.end(),
              [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
    std::vector<bool> seen(orders.size());
    auto front = out.begin();
    for (auto c = out.begin(); c != out.end(); ++c)
      if (!seen[c->order]) {
        seen[c->order] = true;
        std::rotate(front++, c, c + 1);
      }
    return out;
  }

  /// Tracks the first refined_candidates from their samples to the triple
  /// (continuation), then finishes the best of them, best first, until one
  /// reaches the triple.
  HandQuery query(const Eigen::Matrix3Xd& contacts, const Eigen::Matrix3Xd& outward) const {
    const std::vector<Candidate> found = candidates(contacts, outward);
    const std::size_t probed =
        std::min(found.size(), static_cast<std::size_t>(options.refined_candidates));
    std::vector<hand::Refinement> probes;
    probes.reserve(probed);
    for (std::size_t c = 0; c < probed; ++c)
      probes.push_back(tracked(found[c], target(contacts, outward, found[c].order)));
    if (probes.empty()) throw std::logic_error("hand map search found no candidate");
    std::array<std::size_t, kMaxNeighbours> rank;
    std::iota(rank.begin(), rank.begin() + static_cast<std::ptrdiff_t>(probed), 0);
    std::sort(rank.begin(), rank.begin() + static_cast<std::ptrdiff_t>(probed),
              [&](std::size_t a, std::size_t b) { return probes[a].cost() < probes[b].cost(); });
    std::size_t best = rank[0];
    const std::size_t finished =
        std::min(probed, static_cast<std::size_t>(options.finished_candidates));
    const double exactCost = kExactResidual2 * fingers;
    for (std::size_t i = 0; i < finished && probes[best].cost() > exactCost; ++i) {
      probes[rank[i]].iterate(options.refine_iterations);
      if (probes[rank[i]].cost() < probes[best].cost()) best = rank[i];
    }
    return answer(probes[best], found[best], target(contacts, outward, found[best].order));
  }

  std::vector<HandQuery> queryAlternatives(const Eigen::Matrix3Xd& contacts,
                                           const Eigen::Matrix3Xd& outward, double maxError,
                                           double minDifference) const {
    const std::vector<Candidate> found = candidates(contacts, outward);
    const std::size_t probed =
        std::min(found.size(), static_cast<std::size_t>(options.refined_candidates));
    std::vector<HandQuery> reached;
    for (std::size_t c = 0; c < probed; ++c) {
      const hand::Target t = target(contacts, outward, found[c].order);
      hand::Refinement probe = tracked(found[c], t);
      probe.iterate(options.refine_iterations);
      HandQuery a = answer(probe, found[c], t);
      if (a.position_error <= maxError) reached.push_back(std::move(a));
    }
    std::sort(reached.begin(), reached.end(),
              [](const HandQuery& a, const HandQuery& b) { return a.residual < b.residual; });
    std::vector<HandQuery> distinct;
    for (HandQuery& a : reached) {
      const bool seen = std::any_of(distinct.begin(), distinct.end(), [&](const HandQuery& b) {
        return samePosture(a, b, minDifference);
      });
      if (!seen) distinct.push_back(std::move(a));
    }
    return distinct;
  }

  /// A candidate's map sample, tracked to the triple (continuation).
  hand::Refinement tracked(const Candidate& from, const hand::Target& t) const {
    const robot::hand::HandVector q0 = map.configurations.row(from.sample).transpose();
    hand::Refinement probe(chains, map.parameters, t, q0);
    probe.track(options.tracking_stages, options.stage_iterations);
    return probe;
  }

  HandQuery answer(const hand::Refinement& refined, const Candidate& from,
                   const hand::Target& t) const {
    const hand::Solution& best = refined.solution();
    const robot::hand::TipState& tips = refined.tips();
    const Eigen::Matrix3d& rot = best.pose.rotation;
    const robot::hand::Tips placed = (rot * tips.positions).colwise() + best.pose.translation;
    const Eigen::RowVectorXd cosines =
        (rot * tips.normals).cwiseProduct(t.pad_normals).colwise().sum();
    HandQuery out;
    out.residual = std::sqrt(best.pose.cost / fingers);
    out.position_error = std::sqrt((placed - t.contacts).squaredNorm() / fingers);
    out.normal_error = std::acos(std::clamp(cosines.minCoeff(), -1.0, 1.0));
    out.hand_configuration = best.q;
    out.palm_pose.linear() = rot;
    out.palm_pose.translation() = best.pose.translation;
    out.finger_of_contact.assign(static_cast<std::size_t>(fingers), -1);
    for (int f = 0; f < fingers; ++f)
      out.finger_of_contact[static_cast<std::size_t>(
          orders[from.order][static_cast<std::size_t>(f)])] = f;
    out.map_sample = from.sample;
    if (fingers == 2) out.free_turn = freeTurn(placed, rot * tips.normals);
    return out;
  }
};

Eigen::Isometry3d turnedPalm(const HandQuery& answer, double angle) {
  if (!answer.free_turn) return answer.palm_pose;
  const Eigen::Vector3d& at = answer.free_turn->origin();
  const Eigen::Isometry3d turn = Eigen::Translation3d(at) *
                                 Eigen::AngleAxisd(angle, answer.free_turn->direction()) *
                                 Eigen::Translation3d(-at);
  return turn * answer.palm_pose;
}

bool samePosture(const HandQuery& a, const HandQuery& b, double minHandDifference) {
  return a.finger_of_contact == b.finger_of_contact &&
         (a.hand_configuration - b.hand_configuration).cwiseAbs().maxCoeff() < minHandDifference;
}

HandReachability::HandReachability(const robot::RobotModel& model, db::HandMap map,
                                   HandQueryOptions options)
    : impl_(std::make_unique<Impl>(model, std::move(map), options)) {}

HandReachability::~HandReachability() = default;
HandReachability::HandReachability(HandReachability&&) noexcept = default;
HandReachability& HandReachability::operator=(HandReachability&&) noexcept = default;

const db::HandMap& HandReachability::map() const {
  return impl_->map;
}

const HandQueryOptions& HandReachability::options() const {
  return impl_->options;
}

double HandReachability::maxFingertipDistance() const {
  return impl_->span;
}

HandQuery HandReachability::query(const Eigen::Matrix3Xd& contactPositions,
                                  const Eigen::Matrix3Xd& outwardContactNormals) const {
  checkInput(contactPositions, impl_->fingers, "contactPositions", false);
  checkInput(outwardContactNormals, impl_->fingers, "outwardContactNormals", true);
  return impl_->query(contactPositions, outwardContactNormals);
}

std::vector<HandQuery> HandReachability::queryAlternatives(
    const Eigen::Matrix3Xd& contactPositions, const Eigen::Matrix3Xd& outwardContactNormals,
    double maxPositionError, double minHandDifference) const {
  checkInput(contactPositions, impl_->fingers, "contactPositions", false);
  checkInput(outwardContactNormals, impl_->fingers, "outwardContactNormals", true);
  if (!(maxPositionError >= 0.0)) throw InvalidArgument("maxPositionError", "must be >= 0");
  if (!(minHandDifference >= 0.0)) throw InvalidArgument("minHandDifference", "must be >= 0");
  return impl_->queryAlternatives(contactPositions, outwardContactNormals, maxPositionError,
                                  minHandDifference);
}

}  // namespace hfts::grasp
