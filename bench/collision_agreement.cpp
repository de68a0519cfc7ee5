// collision_agreement: the two-tier collision checker (spheres, then FCL)
// against FCL alone on many configurations and motions in every bundled
// scene, and certified segments against a dense sweep; any disagreement is
// a bug (docs/collision.md). Exit status 1 when one is found.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "robot/arm_ik.h"
#include "robot/collision_checker.h"
#include "robot/motion_bound.h"
#include "robot/robot_model.h"
#include "robot/scene.h"
#include "robot/segment_certificate.h"
#include "robot/sensed_scene.h"

namespace {

using namespace hfts;
namespace fs = std::filesystem;

struct Tally {
  long configurations = 0, colliding = 0, fingertipOnly = 0, settled = 0, disagreements = 0;
  long motions = 0, states = 0, motionDisagreements = 0;
  double secondsTwoTiers = 0, secondsFcl = 0;
  // isMotionValid on the same motions, per resolution: answers compared,
  // time of the free ones.
  struct Validation {
    long motions = 0, free = 0, disagreements = 0;
    double secondsTwoTiers = 0, secondsFcl = 0;
  };
  std::map<double, Validation> validations;
};

class Comparison {
 public:
  Comparison(const robot::CollisionModel& model, const robot::Scene& scene,
             const db::ObjectGeometry& target)
      : model_(model.robot), tiers_(model, scene, &target), fcl_(model, scene, &target) {
    fcl_.setSphereTier(false);
  }

  /// Both rules, both checkers; returns whether q collides (FCL, no grasp rule).
  bool compare(const Eigen::VectorXd& q, Tally& tally) {
    const auto t0 = std::chrono::steady_clock::now();
    const bool a = tiers_.inCollision(q),
               aGrasp = tiers_.inCollision(q, robot::CollisionRequest::grasp());
    const auto t1 = std::chrono::steady_clock::now();
    const bool b = fcl_.inCollision(q),
               bGrasp = fcl_.inCollision(q, robot::CollisionRequest::grasp());
    const auto t2 = std::chrono::steady_clock::now();
    tally.secondsTwoTiers += std::chrono::duration<double>(t1 - t0).count();
    tally.secondsFcl += std::chrono::duration<double>(t2 - t1).count();
    if (a != b || aGrasp != bGrasp) {
      ++tally.disagreements;
      std::fprintf(stderr, "disagreement at q = [");
      for (Eigen::Index i = 0; i < q.size(); ++i) std::fprintf(stderr, " %.17g", q(i));
      std::fprintf(stderr, " ]: two tiers %d/%d, FCL %d/%d\n", a, aGrasp, b, bGrasp);
    }
    return b;
  }

  /// isMotionValid from a to b at `resolution`, both rules, both checkers.
  void compareValidation(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double resolution,
                         Tally::Validation& tally) {
    for (const bool grasp : {false, true}) {
      const auto t0 = std::chrono::steady_clock::now();
      const robot::CollisionRequest request =
          grasp ? robot::CollisionRequest::grasp() : robot::CollisionRequest{};
      const bool x = tiers_.isMotionValid(a, b, resolution, request);
      const auto t1 = std::chrono::steady_clock::now();
      const bool y = fcl_.isMotionValid(a, b, resolution, request);
      const auto t2 = std::chrono::steady_clock::now();
      ++tally.motions;
      if (y) {
        ++tally.free;
        tally.secondsTwoTiers += std::chrono::duration<double>(t1 - t0).count();
        tally.secondsFcl += std::chrono::duration<double>(t2 - t1).count();
      }
      if (x == y) continue;
      ++tally.disagreements;
      std::fprintf(stderr,
                   "motion disagreement at resolution %g (grasp rule %d): two tiers %d, FCL %d\n",
                   resolution, grasp, x, y);
    }
  }

  robot::CollisionChecker& fcl() { return fcl_; }
  robot::CollisionChecker& tiers() { return tiers_; }
  std::uint64_t settled() const { return tiers_.sphereSettledCount(); }

 private:
  const robot::RobotModel& model_;
  robot::CollisionChecker tiers_, fcl_;
};

Eigen::VectorXd uniform(const robot::RobotModel& m, std::mt19937_64& rng) {
  Eigen::VectorXd q(m.numDofs());
  for (int d = 0; d < m.numDofs(); ++d)
    q(d) = std::uniform_real_distribution<double>(m.lowerLimits()(d), m.upperLimits()(d))(rng);
  return q;
}

/// The arm reaching a random palm pose within 0.25 m of the object's centre
/// (random hand joints), or a uniform configuration when IK finds none:
/// where spheres touch the object and fingertips touch it.
Eigen::VectorXd nearTarget(const robot::RobotModel& m, const robot::ArmIk& ik,
                           const robot::Scene& scene, const Eigen::Vector3d& centre,
                           std::mt19937_64& rng) {
  Eigen::VectorXd q = uniform(m, rng);
  std::normal_distribution<double> n;
  Eigen::Isometry3d palm = Eigen::Isometry3d::Identity();
  palm.linear() =
      Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
  palm.translation() = centre + 0.25 *
                                    std::cbrt(std::uniform_real_distribution<double>(0, 1)(rng)) *
                                    Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  const auto solutions = ik.solvePalm(scene.robot_base.inverse() * palm, rng);
  if (!solutions.empty())
    q.head(m.numArmDofs()) =
        solutions[std::uniform_int_distribution<std::size_t>(0, solutions.size() - 1)(rng)];
  return q;
}

bool isFingertip(const robot::RobotModel& m, const std::string& link) {
  return std::any_of(m.fingertips().begin(), m.fingertips().end(), [&](const robot::Fingertip& f) {
    return m.links()[static_cast<std::size_t>(f.link)].name == link;
  });
}

/// A collision-free start and an end 0.5 rad away (Eq. (3) metric, inside
/// the limits).
std::pair<Eigen::VectorXd, Eigen::VectorXd> randomMotion(const robot::RobotModel& m,
                                                         robot::CollisionChecker& checker,
                                                         std::mt19937_64& rng) {
  Eigen::VectorXd a = uniform(m, rng);
  // A scene where (almost) nothing is free gives up instead of looping.
  for (int tries = 1; checker.inCollision(a); ++tries) {
    if (tries == 100000)
      throw std::runtime_error("no free configuration in 100000 tries: no motion to compare");
    a = uniform(m, rng);
  }
  std::normal_distribution<double> n;
  Eigen::VectorXd direction(m.numDofs());
  for (int d = 0; d < m.numDofs(); ++d) direction(d) = n(rng);
  direction *= 0.5 / checker.metric().distance(Eigen::VectorXd::Zero(m.numDofs()), direction);
  return {a, (a + direction).cwiseMax(m.lowerLimits()).cwiseMin(m.upperLimits())};
}

/// A random motion (randomMotion); every state at `resolution` compared.
void compareMotion(const robot::RobotModel& m, Comparison& c, double resolution,
                   std::mt19937_64& rng, Tally& tally) {
  const auto [a, b] = randomMotion(m, c.fcl(), rng);
  const int steps =
      std::max(1, static_cast<int>(std::ceil(c.fcl().metric().distance(a, b) / resolution)));
  for (int s = 0; s <= steps; ++s) c.compare(a + (b - a) * (static_cast<double>(s) / steps), tally);
  tally.states += steps + 1;
  ++tally.motions;
  for (const double r : {resolution, 0.0025}) c.compareValidation(a, b, r, tally.validations[r]);
}

/// Certified segments against a dense sweep: a segment certified free
/// whose sweep (`sweep` + 1 states, strict rule, the two-tier checker: FCL
/// decides every state whose spheres touch, and its answers are FCL
/// alone's, the comparison above) finds a collision is a disagreement.
struct CertifiedTally {
  long segments = 0, free = 0, disagreements = 0, queries = 0, selfQueries = 0;
  double seconds = 0;
};

void compareCertified(const robot::RobotModel& m, const robot::MotionBound& bound,
                      robot::CollisionChecker& checker, robot::CollisionChecker& sweeper, int sweep,
                      std::mt19937_64& rng, CertifiedTally& tally) {
  const auto [a, b] = randomMotion(m, checker, rng);
  const auto t0 = std::chrono::steady_clock::now();
  const robot::MotionCertificate certificate = robot::certifySegment(checker, bound, a, b);
  tally.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ++tally.segments;
  tally.queries += static_cast<long>(certificate.queries);
  tally.selfQueries += static_cast<long>(certificate.self_queries);
  if (!certificate.free) return;
  ++tally.free;
  for (int s = 0; s <= sweep; ++s) {
    const double t = static_cast<double>(s) / sweep;
    if (!sweeper.inCollision(a + t * (b - a))) continue;
    ++tally.disagreements;
    std::fprintf(stderr, "certified free, but the sweep collides at t = %.6f\n", t);
    return;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Compares the two-tier collision checker with FCL alone in every bundled scene."};
  std::string dbDir = "build/databases", robotConfig = "robots/kr5_sdh/kr5_sdh.json",
              sceneDir = "objects/scenes";
  long configurations = 1000000, motions = 1000, certified = 0;
  int sweep = 1000;
  std::uint64_t seed = 1;
  app.add_option("--db", dbDir, "Object databases (the scenes' targets)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--robot", robotConfig, "Robot config")->check(CLI::ExistingFile);
  app.add_option("--scene-dir", sceneDir, "Scenes (every *.json)")->check(CLI::ExistingDirectory);
  app.add_option("--configurations", configurations,
                 "Configurations per scene (half near the target)")
      ->check(CLI::Range(1L, 1000000000L));
  app.add_option("--motions", motions, "Random 0.5-rad motions per scene")
      ->check(CLI::Range(0L, 10000000L));
  app.add_option("--certified", certified,
                 "Random 0.5-rad segments per scene certified (clearance 0) and swept")
      ->check(CLI::Range(0L, 100000000L));
  app.add_option("--sweep", sweep, "States of the dense sweep of a certified segment")
      ->check(CLI::Range(2, 1000000));
  app.add_option("--seed", seed, "Random seed");
  CLI11_PARSE(app, argc, argv);

  try {
    const robot::RobotModel model = robot::RobotModel::load(robotConfig);
    const robot::ArmIk ik(model);
    std::vector<fs::path> scenes;
    for (const auto& e : fs::directory_iterator(sceneDir))
      if (e.path().extension() == ".json") scenes.push_back(e.path());
    std::sort(scenes.begin(), scenes.end());
    long disagreements = 0;
    const std::shared_ptr<const robot::CollisionModel> collision =
        robot::buildCollisionModel(model);
    std::printf("%-8s %11s %9s %13s %8s %9s %8s %9s %9s %9s %9s\n", "scene", "configs", "colliding",
                "tip-contact", "settled", "disagree", "motions", "states", "disagree", "us/2tier",
                "us/fcl");
    for (const fs::path& path : scenes) {
      robot::Scene scene = robot::loadScene(path);
      const db::ObjectDatabase target =
          db::loadObjectDatabase(fs::path(dbDir) / (scene.target_object + ".h5"));
      scene.target_pose = robot::targetPose(scene, target.geometry.mesh_vertices);
      // A sensed scene as the planner sees it: without what another view
      // saw through, what the camera saw of the target and of the robot at
      // its start, with an object from views' hidden space
      // (docs/point_clouds.md).
      scene = robot::asPlannerSees(scene, target, model,
                                   scene.startFor(model.name()).value_or(model.home()));
      const Eigen::Vector3d centre =
          scene.target_pose * (0.5 * (target.geometry.bbox_min + target.geometry.bbox_max));
      Comparison c(*collision, scene, target.geometry);
      std::mt19937_64 rng(seed);
      Tally t;
      for (long i = 0; i < configurations; ++i) {
        const Eigen::VectorXd q =
            i % 2 == 0 ? uniform(model, rng) : nearTarget(model, ik, scene, centre, rng);
        const bool colliding = c.compare(q, t);
        t.colliding += colliding;
        // A fingertip on the target: the grasp rule measured its depth.
        robot::CollisionPair pair;
        t.fingertipOnly += colliding && c.fcl().inCollision(q, &pair) &&
                           pair.second.rfind("target", 0) == 0 && isFingertip(model, pair.first);
      }
      t.configurations = configurations;
      t.settled = static_cast<long>(c.settled());
      for (long i = 0; i < motions; ++i) {
        const long before = t.disagreements;
        compareMotion(model, c, 0.02, rng, t);
        t.motionDisagreements += t.disagreements - before;
      }
      const double checks = 2.0 * static_cast<double>(t.configurations + t.states);
      std::printf("%-8s %11ld %9ld %13ld %7.1f%% %9ld %8ld %9ld %9ld %9.2f %9.2f\n",
                  path.stem().c_str(), t.configurations, t.colliding, t.fingertipOnly,
                  100.0 * static_cast<double>(t.settled) / checks,
                  t.disagreements - t.motionDisagreements, t.motions, t.states,
                  t.motionDisagreements, 1e6 * t.secondsTwoTiers / checks,
                  1e6 * t.secondsFcl / checks);
      for (const auto& [resolution, v] : t.validations) {
        std::printf(
            "  isMotionValid at resolution %g: %ld motions (both rules), %ld free, %ld "
            "disagreements; free ones %.1f us two tiers, %.1f us FCL alone\n",
            resolution, v.motions, v.free, v.disagreements,
            v.free > 0 ? 1e6 * v.secondsTwoTiers / static_cast<double>(v.free) : 0.0,
            v.free > 0 ? 1e6 * v.secondsFcl / static_cast<double>(v.free) : 0.0);
        disagreements += v.disagreements;
      }
      if (certified > 0) {
        const robot::MotionBound bound(model);
        CertifiedTally ct;
        for (long i = 0; i < certified; ++i)
          compareCertified(model, bound, c.fcl(), c.tiers(), sweep, rng, ct);
        std::printf(
            "  certifySegment: %ld segments, %ld certified free, %ld disagreements with a "
            "%d-state sweep; %.1f distance queries (%.1f between links) and %.0f us per segment\n",
            ct.segments, ct.free, ct.disagreements, sweep + 1,
            static_cast<double>(ct.queries) / static_cast<double>(ct.segments),
            static_cast<double>(ct.selfQueries) / static_cast<double>(ct.segments),
            1e6 * ct.seconds / static_cast<double>(ct.segments));
        disagreements += ct.disagreements;
      }
      std::fflush(stdout);
      disagreements += t.disagreements;
    }
    return disagreements == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "collision_agreement: %s\n", e.what());
    return 2;
  }
}
