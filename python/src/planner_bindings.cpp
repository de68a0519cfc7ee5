// Plans, their validation, trajectories and the ROS shapes of a plan.

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <future>
#include <thread>

#include "bindings.h"
#include "client/plan_page.h"
#include "core/atomic_file.h"
#include "core/invalid_argument.h"
#include "planner/grasp_motion_planner.h"
#include "planner/time_parameterization.h"
#include "robot/scene.h"
#include "service/plan_result_json.h"
#include "service/ros_messages.h"
#include "service/validation_json.h"

namespace hfts::python {
namespace {

using planner::PlanningWorld;

/// A plan with what it was asked and the world it was made in: what its
/// conversions (JSON, ROS, glTF, the viewer page) need.
struct Plan {
  std::shared_ptr<const PlanningWorld> world;
  planner::PlanRequest request;
  planner::PlanResult result;

  /// The plan as the service's result, made once on first use.
  const nlohmann::json& json() const {
    if (!asJson) {
      asJson = service::planResultToJson(result, request);
      (*asJson)["robot"] = world->robot().name();
    }
    return *asJson;
  }

 private:
  mutable std::optional<nlohmann::json> asJson;
};

/// A trajectory and the joints it moves.
struct Trajectory {
  planner::GraspTrajectory trajectory;
  std::vector<std::string> joint_names;

  /// The points' `member` stacked: an (T, dofs) array.
  py::array_t<double> stacked(Eigen::VectorXd planner::TrajectoryPoint::*member) const {
    const auto rows = static_cast<py::ssize_t>(trajectory.points.size());
    const auto cols = static_cast<py::ssize_t>(joint_names.size());
    py::array_t<double> out({rows, cols});
    double* data = out.mutable_data();
    for (const planner::TrajectoryPoint& p : trajectory.points) {
      const Eigen::VectorXd& v = p.*member;
      std::copy(v.data(), v.data() + v.size(), data);
      data += cols;
    }
    return out;
  }
};

/// A flag another thread sets to stop a plan.
struct Cancel {
  std::atomic<bool> flag{false};
};

/// The plan as an animated binary glTF. Throws InvalidArgument ("plan")
/// for a failed plan, ("trajectory") for one without a trajectory.
std::string glbOf(const Plan& p) {
  if (!p.result.success) throw InvalidArgument("plan", "a failed plan has nothing to show");
  return planner::planGlb(*p.world, p.request, p.result);
}

planner::PlanAlgorithm algorithmOf(const std::string& name) {
  if (name == "coupled") return planner::PlanAlgorithm::kCoupled;
  if (name == "decoupled") return planner::PlanAlgorithm::kDecoupled;
  if (name == "rrtconnect") return planner::PlanAlgorithm::kRrtConnect;
  throw InvalidArgument(
      "algorithm", "must be \"coupled\", \"decoupled\" or \"rrtconnect\", got \"" + name + "\"");
}

planner::PlannerPreset presetOf(const std::string& name) {
  if (name == "default") return planner::PlannerPreset::kDefault;
  if (name == "paper") return planner::PlannerPreset::kPaper;
  throw InvalidArgument("preset", "must be \"default\" or \"paper\", got \"" + name + "\"");
}

py::array_t<double> pathArray(const std::vector<Eigen::VectorXd>& path, int dofs) {
  py::array_t<double> out({static_cast<py::ssize_t>(path.size()), static_cast<py::ssize_t>(dofs)});
  double* data = out.mutable_data();
  for (const Eigen::VectorXd& q : path) {
    std::copy(q.data(), q.data() + q.size(), data);
    data += dofs;
  }
  return out;
}

/// Whether the calling thread is Python's main thread, the only one that
/// sees signals (Ctrl-C). Needs the GIL.
bool onPythonsMainThread() {
  static const py::handle mainThread =
      py::module_::import("threading").attr("main_thread")().release();
  return mainThread.attr("ident").cast<unsigned long>() == PyThread_get_thread_ident();
}

/// A thread joined, after `stop` is set, however its owner's scope ends
/// (an exception, or the interpreter ending the owner's thread).
class StoppingThread {
 public:
  StoppingThread(std::atomic<bool>& stop, std::thread thread)
      : stop_(stop), thread_(std::move(thread)) {}
  ~StoppingThread() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  StoppingThread(const StoppingThread&) = delete;
  StoppingThread& operator=(const StoppingThread&) = delete;

 private:
  std::atomic<bool>& stop_;
  std::thread thread_;
};

/// planGrasp in a thread of its own while this one, the GIL released,
/// looks every 50 ms at the request's Cancel and, on Python's main thread,
/// at its signals (Ctrl-C): either stops the plan. A signal's exception
/// (KeyboardInterrupt) is raised once the plan has stopped.
planner::PlanResult planInterruptibly(const PlanningWorld& world,
                                      const planner::PlanRequest& request, const Cancel* cancel) {
  const bool watchSignals = onPythonsMainThread();
  std::atomic<bool> stop{false};
  std::promise<planner::PlanResult> promise;
  std::future<planner::PlanResult> done = promise.get_future();
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    const StoppingThread planning(stop, std::thread([&] {
                                    try {
                                      promise.set_value(planner::planGrasp(world, request, &stop));
                                    } catch (...) {
                                      promise.set_exception(std::current_exception());
                                    }
                                  }));
    while (done.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      if (cancel != nullptr && cancel->flag.load()) stop = true;
      if (watchSignals && !interrupted) {
        py::gil_scoped_acquire python;
        if (PyErr_CheckSignals() != 0) {
          interrupted = true;  // the error stays set until the plan has stopped
          stop = true;
        }
      }
    }
  }
  if (interrupted) throw py::error_already_set();
  return done.get();
}

/// A lift given as a dict: {"height": m, "held_speed": fraction}, either
/// key optional, as the service's.
planner::LiftOptions liftOf(const py::dict& lift) {
  planner::LiftOptions out;
  for (const auto& [key, value] : lift) {
    const std::string name = py::str(key).cast<std::string>();
    if (name == "height")
      out.height = value.cast<double>();
    else if (name == "held_speed")
      out.held_speed = value.cast<double>();
    else
      throw InvalidArgument("lift." + name, "unknown key (known: height, held_speed)");
  }
  return out;
}

/// `place`: {"on": obstacle, "area": ((x0, y0), (x1, y1)), "upright":
/// bool, "search": "coupled" | "decoupled"}, as the service's.
void placeOf(const py::dict& place, planner::PlanRequest& r) {
  planner::PlaceGoal goal;
  for (const auto& [key, value] : place) {
    const std::string name = py::str(key).cast<std::string>();
    if (name == "on") {
      goal.on = value.cast<std::string>();
    } else if (name == "area") {
      const auto corners = value.cast<std::vector<std::vector<double>>>();
      if (corners.size() != 2 || corners[0].size() != 2 || corners[1].size() != 2)
        throw InvalidArgument("place.area", "must be ((x_min, y_min), (x_max, y_max))");
      goal.area = Eigen::AlignedBox2d(Eigen::Vector2d(corners[0][0], corners[0][1]),
                                      Eigen::Vector2d(corners[1][0], corners[1][1]));
    } else if (name == "upright") {
      goal.upright = value.cast<bool>();
    } else if (name == "search") {
      const std::string search = value.cast<std::string>();
      if (search != "coupled" && search != "decoupled")
        throw InvalidArgument("place.search", "must be \"coupled\" or \"decoupled\"");
      r.place_search =
          search == "coupled" ? planner::PlaceSearch::kCoupled : planner::PlaceSearch::kDecoupled;
    } else {
      throw InvalidArgument("place." + name, "unknown key (known: on, area, upright, search)");
    }
  }
  if (goal.on.empty()) throw InvalidArgument("place.on", "names the obstacle to place on");
  r.place = goal;
}

Plan plan(std::shared_ptr<PlanningWorld> world, const robot::Scene& scene,
          const std::string& object, const std::optional<DoubleArray>& objectPose,
          const std::optional<Eigen::VectorXd>& start,
          const std::vector<planner::MotionGoal>& goals, const std::string& algorithm,
          const std::optional<planner::PlanSettings>& settings, const std::string& preset,
          const std::optional<int>& iterations, const py::object& seed, double timeLimit,
          const py::dict& parameters, double trajectoryRate, bool explored, bool validate,
          const std::optional<physics::SimulationOptions>& simulation, Cancel* cancel,
          const py::object& lift, const std::optional<py::dict>& place) {
  Plan out;
  out.world = world;
  planner::PlanRequest& r = out.request;
  r.scene = scene;
  r.object = object.empty() ? scene.target_object : object;
  if (objectPose) r.object_pose = isometryOf(*objectPose, "object_pose");
  r.start = start;
  r.goals = goals;
  r.algorithm = algorithmOf(algorithm);
  r.settings = settings;
  r.preset = presetOf(preset);
  r.iterations = iterations;
  r.seed = seedOf(seed);
  r.time_limit = timeLimit;
  for (const auto& [key, value] : parameters) {
    const std::string name = py::str(key).cast<std::string>();
    r.parameters[name] = parameterText(name, value);
  }
  r.trajectory_rate = trajectoryRate;
  r.explored = explored;
  r.validate = validate;
  if (simulation) r.simulation = *simulation;
  // None: the default lift, none for the paper's planner; True: the
  // default lift; False: none; a number: its height (m); a dict: height
  // and held speed.
  if (lift.is_none()) {
    if (r.preset == planner::PlannerPreset::kPaper) r.lift.reset();
  } else if (py::isinstance<py::bool_>(lift)) {
    if (!lift.cast<bool>()) r.lift.reset();
  } else if (py::isinstance<py::float_>(lift) || py::isinstance<py::int_>(lift)) {
    r.lift = planner::LiftOptions{lift.cast<double>()};
  } else if (py::isinstance<py::dict>(lift)) {
    r.lift = liftOf(lift.cast<py::dict>());
  } else {
    throw InvalidArgument("lift",
                          "must be None, True, False, a height in metres or a dict "
                          "{height, held_speed}");
  }
  if (r.lift && !r.goals.empty()) r.lift.reset();  // a motion plan holds no object
  if (place) placeOf(*place, r);
  out.result = planInterruptibly(*world, r, cancel);
  return out;
}

py::object validate(const PlanningWorld& world, const Plan& p,
                    const std::optional<physics::SimulationOptions>& simulation,
                    const std::optional<robot::Scene>& scene) {
  planner::PlanRequest request = p.request;
  if (simulation) request.simulation = *simulation;
  if (scene) {  // the plan in another scene: the true one of a sensed scene
    request.scene = *scene;
    const std::string planned =
        p.request.object.empty() ? p.request.scene.target_object : p.request.object;
    if (scene->target_object == planned) {
      request.object_pose = p.result.object_pose;  // the object where the plan had it
    } else {  // the true object of one built from a view, where it truly is
      request.object = scene->target_object;
      const db::ObjectDatabase* truth = world.object(scene->target_object);
      if (truth == nullptr)
        throw InvalidArgument(
            "scene", "its target '" + scene->target_object + "' is not an object of this world");
      request.object_pose = robot::targetPose(*scene, truth->geometry.mesh_vertices);
    }
  }
  planner::Validation v;
  {
    py::gil_scoped_release release;
    v = planner::validatePlan(world, request, p.result);
  }
  nlohmann::json out = {{"holds", v.holds()}, {"check", service::graspCheckToJson(v.check)}};
  if (v.physics) out["physics"] = service::physicsToJson(*v.physics, /*motion=*/true);
  if (v.place) out["place_physics"] = service::placePhysicsToJson(*v.place);
  return toPython(out);
}

Trajectory timeParameterize(const robot::RobotModel& robot, const DoubleArray& path, double rate,
                            double maxDeviation) {
  checkShape(path, "path", {-1, robot.numDofs()});
  if (path.shape(0) < 2) throw InvalidArgument("path", "needs at least two configurations");
  if (robot.maxAccelerations().size() != robot.numDofs())
    throw InvalidArgument(
        "robot", "'" + robot.name() + "' has no max_accelerations in its config: no trajectory");
  std::vector<Eigen::VectorXd> waypoints;
  for (py::ssize_t i = 0; i < path.shape(0); ++i)
    waypoints.emplace_back(Eigen::Map<const Eigen::VectorXd>(path.data(i, 0), robot.numDofs()));
  planner::TrajectoryOptions options;
  options.max_deviation = maxDeviation;
  Trajectory out;
  out.joint_names = robot.dofNames();
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    std::string why;
    if (!robot.withinLimits(waypoints[i], 1e-9, &why))
      throw InvalidArgument("path[" + std::to_string(i) + "]", why);
  }
  py::gil_scoped_release release;
  const planner::TimeOptimalTrajectory t(waypoints, robot.maxVelocities(), robot.maxAccelerations(),
                                         options);
  out.trajectory.points = t.sample(rate);
  out.trajectory.duration = t.duration();
  out.trajectory.closing_start = t.duration();
  out.trajectory.lift_start = out.trajectory.carry_start = out.trajectory.place_start =
      out.trajectory.release_start = out.trajectory.retreat_start = t.duration();
  out.trajectory.deviation = t.deviation();
  return out;
}

}  // namespace

void bindPlanner(py::module_& m) {
  py::class_<Cancel>(m, "Cancel", "Stops a plan from another thread: pass it to World.plan.")
      .def(py::init<>())
      .def(
          "cancel", [](Cancel& c) { c.flag = true; }, "Asks the plan to stop.")
      .def_property_readonly("cancelled", [](const Cancel& c) { return c.flag.load(); })
      .def("__repr__", [](const Cancel& c) {
        return std::string("<hfts.Cancel ") + (c.flag.load() ? "set" : "not set") + ">";
      });

  py::class_<Trajectory>(m, "Trajectory",
                         "A trajectory sampled at a fixed rate: times (T,), positions, "
                         "velocities, accelerations (T, num_dofs).")
      .def_property_readonly(
          "times",
          [](const Trajectory& t) {
            py::array_t<double> out(static_cast<py::ssize_t>(t.trajectory.points.size()));
            double* data = out.mutable_data();
            for (const auto& p : t.trajectory.points) *data++ = p.time;
            return out;
          })
      .def_property_readonly(
          "positions",
          [](const Trajectory& t) { return t.stacked(&planner::TrajectoryPoint::positions); })
      .def_property_readonly(
          "velocities",
          [](const Trajectory& t) { return t.stacked(&planner::TrajectoryPoint::velocities); })
      .def_property_readonly(
          "accelerations",
          [](const Trajectory& t) { return t.stacked(&planner::TrajectoryPoint::accelerations); })
      .def_readonly("joint_names", &Trajectory::joint_names)
      .def_property_readonly("duration", [](const Trajectory& t) { return t.trajectory.duration; })
      .def_property_readonly("closing_start",
                             [](const Trajectory& t) { return t.trajectory.closing_start; })
      .def_property_readonly(
          "lift_start", [](const Trajectory& t) { return t.trajectory.lift_start; },
          "When the palm starts lifting the object (the duration without a lift).")
      .def_property_readonly(
          "carry_start", [](const Trajectory& t) { return t.trajectory.carry_start; },
          "A pick and place's: when the carry starts (the lift's end; the duration without).")
      .def_property_readonly(
          "place_start", [](const Trajectory& t) { return t.trajectory.place_start; },
          "When the palm descends to put the object down (the duration without a place).")
      .def_property_readonly(
          "release_start", [](const Trajectory& t) { return t.trajectory.release_start; },
          "When the hand opens (the duration without a place).")
      .def_property_readonly(
          "retreat_start", [](const Trajectory& t) { return t.trajectory.retreat_start; },
          "When the open hand retreats (the duration without a place).")
      .def_property_readonly("deviation",
                             [](const Trajectory& t) { return t.trajectory.deviation; })
      .def(
          "to_ros",
          [](const Trajectory& t) {
            return toPython(service::rosJointTrajectory(t.trajectory, t.joint_names));
          },
          "The trajectory as a dict shaped like trajectory_msgs/JointTrajectory.")
      .def("__len__", [](const Trajectory& t) { return t.trajectory.points.size(); })
      .def("__repr__", [](const Trajectory& t) {
        return "<hfts.Trajectory of " + std::to_string(t.trajectory.points.size()) +
               " points over " + std::to_string(t.trajectory.duration) + " s>";
      });

  py::class_<Plan>(m, "Plan", "A plan: success or why not, the path, the grasp, the trajectory.")
      .def_property_readonly(
          "success", [](const Plan& p) { return p.result.success; },
          "A grasp (or motion) was found and the path reaches it.")
      .def_property_readonly(
          "failure", [](const Plan& p) { return planner::toString(p.result.failure); },
          "\"none\" on success, else why not: \"time_limit\", \"cancelled\", "
          "\"no_valid_goal\", ... (docs/python.md)")
      .def_property_readonly(
          "message", [](const Plan& p) { return p.result.message; },
          "Why not, in words (empty on success).")
      .def_property_readonly("joint_names", [](const Plan& p) { return p.result.joint_names; })
      .def_property_readonly(
          "path",
          [](const Plan& p) { return pathArray(p.result.path, p.world->robot().numDofs()); },
          "The path, one configuration per row: start, ..., pre-grasp, grasp.")
      .def_property_readonly(
          "seed", [](const Plan& p) { return p.result.seed; },
          "The seed of the search the plan is from (with racing, the winner's): one thread and "
          "this seed plan the same path again.")
      .def_property_readonly("object", [](const Plan& p) { return p.request.object; })
      .def_property_readonly("object_pose",
                             [](const Plan& p) { return p.result.object_pose.matrix(); })
      .def_property_readonly(
          "clearance", [](const Plan& p) { return p.result.clearance; },
          "With certify_path: the smallest distance (m) the path's proofs measured; else None.")
      .def_property_readonly(
          "reached_goal", [](const Plan& p) { return p.result.reached_goal; },
          "A motion plan's: the index of the goal the path ends at.")
      .def_property_readonly(
          "lift",
          [](const Plan& p) -> py::object {
            if (!p.result.lift) return py::none();
            return py::dict(
                py::arg("direction") = p.result.lift->direction,
                py::arg("path") = pathArray(p.result.lift->path, p.world->robot().numDofs()));
          },
          "The lift from the grasp (dict: direction, path one configuration per row, the grasp "
          "first), the object in the hand; None without one.")
      .def_property_readonly(
          "place",
          [](const Plan& p) -> py::object {
            if (!p.request.place) return py::none();
            return toPython(p.json()["place"]);
          },
          "A pick and place's placement (dict: object_pose, face_normal, tipping_angle, carry, "
          "descent, open, retreat, retreat_direction, rest); None without one or when it failed.")
      .def_property_readonly(
          "place_rejected",
          [](const Plan& p) -> py::object {
            if (!p.request.place) return py::none();
            return toPython(p.json()["place_rejected"]);
          },
          "A pick and place's placements tried without a goal, by reason (dict).")
      .def_property_readonly(
          "grasp", [](const Plan& p) { return toPython(p.json()["grasp"]); },
          "The grasp as executed (dict; None for a failed or motion plan): contacts with inward "
          "normals, epsilon, penetration, hand_configuration, ...")
      .def_property_readonly(
          "trajectory",
          [](const Plan& p) -> std::optional<Trajectory> {
            if (p.result.trajectory.points.empty()) return std::nullopt;
            return Trajectory{p.result.trajectory, p.result.joint_names};
          },
          "The time-parameterised path (None when not asked for or not possible).")
      .def_property_readonly(
          "stats", [](const Plan& p) { return toPython(p.json()["stats"]); },
          "The search's statistics (dict): planning_time (s), collision_checks, rejections by "
          "reason, ...")
      .def_property_readonly("validation",
                             [](const Plan& p) -> py::object {
                               const nlohmann::json j = p.json();
                               if (!j.contains("validation")) return py::none();
                               return toPython({{"check", j["validation"]},
                                                {"physics", j.value("physics", nlohmann::json())},
                                                {"holds", p.result.validation->holds()}});
                             })
      .def(
          "to_dict", [](const Plan& p) { return toPython(p.json()); },
          "The plan as the service's plan result (docs/protocol.md).")
      .def(
          "to_ros",
          [](const Plan& p) { return toPython(service::rosPlan(*p.world, p.request, p.result)); },
          "{\"grasp\": moveit_msgs/Grasp, \"trajectory\": trajectory_msgs/JointTrajectory} as "
          "dicts (docs/python.md#ros-shaped-results).")
      .def(
          "glb",
          [](const Plan& p) {
            std::string bytes;
            {
              py::gil_scoped_release release;
              bytes = glbOf(p);
            }
            return py::bytes(bytes);
          },
          "The plan as an animated binary glTF (needs a trajectory).")
      .def(
          "write_viewer_page",
          [](const Plan& p, const std::filesystem::path& path,
             const std::filesystem::path& viewer_dir) {
            for (const char* file : {"src/page.html", "dist/viewer.js"})
              if (!std::filesystem::is_regular_file(viewer_dir / file))
                throw InvalidArgument("viewer_dir", "has no " + std::string(file) +
                                                        " (scripts/setup.sh bundles the viewer)");
            const std::string page = client::planPage(p.json(), glbOf(p), viewer_dir);
            try {
              core::writeFileAtomically(path, page);
            } catch (const std::exception& e) {
              throw InvalidArgument("path", e.what());
            }
          },
          py::arg("path"), py::arg("viewer_dir"),
          "Writes the plan's page with the viewer (docs/viewer.md): one HTML file that opens "
          "from disk.")
      .def("__repr__", [](const Plan& p) {
        return std::string("<hfts.Plan ") +
               (p.result.success ? "success" : planner::toString(p.result.failure)) + ", " +
               std::to_string(p.result.path.size()) + " waypoints>";
      });

  auto world = py::reinterpret_borrow<py::class_<PlanningWorld, std::shared_ptr<PlanningWorld>>>(
      m.attr("World"));
  world
      .def(
          "default_settings",
          [](const PlanningWorld& w, const std::string& preset) {
            return planner::defaultSettings(w.robot(), presetOf(preset));
          },
          py::arg("preset") = "default",
          "The settings a plan starts from for this robot: \"default\" (the planner as "
          "measured best) or \"paper\" (the paper's algorithm exactly).")
      .def(
          "parameters",
          [](const PlanningWorld& w) {
            py::list out;
            for (const planner::PlannerParameterInfo& p : planner::plannerParameters(w))
              out.append(py::dict(py::arg("name") = p.name, py::arg("default") = p.default_value,
                                  py::arg("range") = p.range));
            return out;
          },
          "Every planner parameter by name with its default and range.")
      .def("plan", &plan, py::arg("scene"), py::arg("object") = "",
           py::arg("object_pose") = py::none(), py::arg("start") = py::none(),
           py::arg("goals") = std::vector<planner::MotionGoal>{}, py::arg("algorithm") = "coupled",
           py::arg("settings") = py::none(), py::arg("preset") = "default",
           py::arg("iterations") = py::none(), py::arg("seed") = py::int_(1),
           py::arg("time_limit") = 60.0, py::arg("parameters") = py::dict(),
           py::arg("trajectory_rate") = 100.0, py::arg("explored") = false,
           py::arg("validate") = false, py::arg("simulation") = py::none(),
           py::arg("cancel") = py::none(), py::arg("lift") = py::none(),
           py::arg("place") = py::none(),
           "Plans a grasp of `object` (default the scene's target) and a path to it (or, with "
           "goals, a path to one of them), then a lift of the object clear of its support "
           "(`lift`: None, the default height but none with preset 'paper'; True, the default "
           "height; False, none; a number, the height in m), and with `place` (dict: on, "
           "area, upright, search) the carry to a stable placement, the release and the "
           "retreat (docs/placement.md). The GIL "
           "is released while it plans. Raises InvalidArgument naming the field for a malformed "
           "request.")
      .def("validate", &validate, py::arg("plan"), py::arg("simulation") = py::none(),
           py::arg("scene") = py::none(),
           "A successful plan's grasp checked again and simulated in MuJoCo, in this world: "
           "{holds, check, physics}; with `scene`, in that scene instead of the plan's, e.g. the "
           "true scene of a plan made from a depth image: the object where the plan had it, or, "
           "when the scene's target is another object (the true one of an object built from a "
           "view), that object where the scene has it.");

  m.def("time_parameterize", &timeParameterize, py::arg("robot"), py::arg("path"),
        py::arg("rate") = 100.0,
        py::arg("max_deviation") = planner::TrajectoryOptions{}.max_deviation,
        "A time-optimal trajectory through a path (N, num_dofs) under the robot's limits, "
        "sampled at `rate` Hz. Not collision-checked: plans' own trajectories are.");
}

}  // namespace hfts::python
