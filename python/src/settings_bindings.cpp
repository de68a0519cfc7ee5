// The planner's typed settings (planner/plan_settings.h), the physics
// check's options and the motion goals, as Python classes.

#include "bindings.h"
#include "core/invalid_argument.h"
#include "physics/simulate_grasp.h"
#include "planner/motion_goal.h"
#include "planner/plan_settings.h"

namespace hfts::python {

std::string parameterText(const std::string& name, const py::handle& value) {
  static const py::handle numpyBool =
      py::object(py::module_::import("numpy").attr("bool_")).release();
  if (py::isinstance<py::bool_>(value) || py::isinstance(value, numpyBool))
    return py::cast<bool>(py::bool_(py::reinterpret_borrow<py::object>(value))) ? "1" : "0";
  if (PyIndex_Check(value.ptr()))  // int, numpy's integers
    return py::str(py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr())))
        .cast<std::string>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (PyNumber_Check(value.ptr()))  // float, numpy's floats
    return py::str(py::float_(py::reinterpret_borrow<py::object>(value))).cast<std::string>();
  throw InvalidArgument("parameters." + name, "must be a number, a bool or a string");
}

void bindSettings(py::module_& m) {
  using namespace planner;
  py::class_<PaperParameters> paper(m, "PaperParameters",
                                    "The paper's parameters (its Fig. 6), at its values.");
  paper.def(py::init<>())
      .def_readwrite("step_size", &PaperParameters::step_size)
      .def_readwrite("p_max", &PaperParameters::p_max)
      .def_readwrite("p_min", &PaperParameters::p_min)
      .def_readwrite("p_w", &PaperParameters::p_w)
      .def_readwrite("p_goal_tree", &PaperParameters::p_goal_tree)
      .def_readwrite("d_m", &PaperParameters::d_m)
      .def_readwrite("w_f", &PaperParameters::w_f)
      .def_readwrite("w_c", &PaperParameters::w_c)
      .def_readwrite("n_a", &PaperParameters::n_a)
      .def_readwrite("kappa", &PaperParameters::kappa)
      .def_readwrite("i_min", &PaperParameters::i_min)
      .def_readwrite("i_max", &PaperParameters::i_max)
      .def_readwrite("alpha", &PaperParameters::alpha)
      .def_readwrite("friction", &PaperParameters::friction)
      .def_readwrite("cone_edges", &PaperParameters::cone_edges)
      .def_readwrite("weight_arm", &PaperParameters::weight_arm)
      .def_readwrite("weight_hand", &PaperParameters::weight_hand)
      .def_readwrite("decoupled_iterations", &PaperParameters::decoupled_iterations);
  addRepr(paper, "PaperParameters");

  py::class_<SearchHeuristics> heuristics(
      m, "SearchHeuristics",
      "The project's additions to the paper's search (docs/planning.md); preset \"paper\" turns "
      "every one off.");
  heuristics.def(py::init<>())
      .def_readwrite("p_local", &SearchHeuristics::p_local)
      .def_readwrite("local_radius", &SearchHeuristics::local_radius)
      .def_readwrite("other_postures", &SearchHeuristics::other_postures)
      .def_readwrite("palm_turns", &SearchHeuristics::palm_turns)
      .def_readwrite("mask_contacts", &SearchHeuristics::mask_contacts)
      .def_readwrite("unstable_by_reach", &SearchHeuristics::unstable_by_reach)
      .def_readwrite("fit_check", &SearchHeuristics::fit_check)
      .def_readwrite("fit_clearance", &SearchHeuristics::fit_clearance);
  addRepr(heuristics, "SearchHeuristics");

  py::class_<GoalCriteria> goal(m, "GoalCriteria", "What a goal must pass.");
  goal.def(py::init<>())
      .def_readwrite("max_fingertip_error", &GoalCriteria::max_fingertip_error)
      .def_readwrite("min_epsilon", &GoalCriteria::min_epsilon)
      .def_readwrite("max_penetration", &GoalCriteria::max_penetration)
      .def_readwrite("physics_check", &GoalCriteria::physics_check);
  addRepr(goal, "GoalCriteria");

  py::class_<PathCriteria> path(m, "PathCriteria", "What a returned motion must be.");
  path.def(py::init<>())
      .def_readwrite("certify", &PathCriteria::certify)
      .def_readwrite("clearance", &PathCriteria::clearance);
  addRepr(path, "PathCriteria");

  py::class_<ExecutionOptions> execution(m, "ExecutionOptions",
                                         "How the search runs (none changes what a plan is).");
  execution.def(py::init<>())
      .def_readwrite("threads", &ExecutionOptions::threads)
      .def_readwrite("sphere_tier", &ExecutionOptions::sphere_tier)
      .def_readwrite("collision_resolution", &ExecutionOptions::collision_resolution)
      .def_readwrite("smoothing_steps", &ExecutionOptions::smoothing_steps)
      .def_readwrite("final_resolution", &ExecutionOptions::final_resolution);
  addRepr(execution, "ExecutionOptions");

  py::class_<PlanSettings> settings(
      m, "PlanSettings",
      "A plan's settings, typed (docs/planning.md#parameters). Start from "
      "World.default_settings() to change a few.");
  settings.def(py::init<>())
      .def_readwrite("paper", &PlanSettings::paper)
      .def_readwrite("heuristics", &PlanSettings::heuristics)
      .def_readwrite("goal", &PlanSettings::goal)
      .def_readwrite("path", &PlanSettings::path)
      .def_readwrite("execution", &PlanSettings::execution)
      .def(
          "set",
          [](PlanSettings& s, const std::string& name, const py::handle& value) {
            setSetting(s, name, parameterText(name, value));
          },
          py::arg("name"), py::arg("value"),
          "Sets a setting by its parameter name (\"p_max\", \"threads\"), checked against its "
          "range.")
      .def("check", &checkSettings, "Raises InvalidArgument for a value out of its range.");
  addRepr(settings, "PlanSettings");

  py::class_<physics::SimulationOptions> simulation(
      m, "SimulationOptions", "The physics check's options (docs/physics.md).");
  simulation.def(py::init<>())
      .def_readwrite("density", &physics::SimulationOptions::density)
      .def_readwrite("friction", &physics::SimulationOptions::friction)
      .def_readwrite("lift_height", &physics::SimulationOptions::lift_height)
      .def_readwrite("perturb", &physics::SimulationOptions::perturb)
      .def_readwrite("min_held_fraction", &physics::SimulationOptions::min_held_fraction)
      .def_readwrite("max_displacement", &physics::SimulationOptions::max_displacement)
      .def_readwrite("max_rotation", &physics::SimulationOptions::max_rotation);
  addRepr(simulation, "SimulationOptions");

  py::class_<JointGoal>(m, "JointGoal", "A configuration to reach: every DoF, or the arm's only.")
      .def(py::init([](const Eigen::VectorXd& q) { return JointGoal{q}; }),
           py::arg("configuration"))
      .def_readonly("configuration", &JointGoal::configuration)
      .def("__repr__", [](const JointGoal& g) {
        return "<hfts.JointGoal of " + std::to_string(g.configuration.size()) + " values>";
      });
  py::class_<PoseGoal>(m, "PoseGoal",
                       "A pose (4 x 4, world frame) of the palm or flange link to reach within "
                       "tolerances (m, rad).")
      .def(py::init([](const DoubleArray& pose, const std::string& link, double position_tolerance,
                       double orientation_tolerance) {
             return PoseGoal{link, isometryOf(pose, "pose"), position_tolerance,
                             orientation_tolerance};
           }),
           py::arg("pose"), py::arg("link") = "", py::arg("position_tolerance") = 0.001,
           py::arg("orientation_tolerance") = 0.01)
      .def_property_readonly("pose", [](const PoseGoal& g) { return g.pose.matrix(); })
      .def_readonly("link", &PoseGoal::link)
      .def_readonly("position_tolerance", &PoseGoal::position_tolerance)
      .def_readonly("orientation_tolerance", &PoseGoal::orientation_tolerance)
      .def("__repr__", [](const PoseGoal& g) {
        const Eigen::Vector3d p = g.pose.translation();
        return "<hfts.PoseGoal of " + (g.link.empty() ? std::string("the palm") : g.link) +
               " at (" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " +
               std::to_string(p.z()) + ")>";
      });
}

}  // namespace hfts::python
