"""Type stubs of the extension module hfts._hfts (python/src/*.cpp).

Arrays given to the module may be anything numpy converts to float64
(lists, tuples, arrays of another dtype); arrays it returns are numpy
arrays. Poses are 4 x 4 homogeneous matrices. tests/python/test_stubs.py
checks that these stubs name every class, method, property and argument
of the built module.
"""

import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy
from numpy.typing import ArrayLike, NDArray

_Path = Union[str, "os.PathLike[str]"]
_Floats = NDArray[numpy.float64]
_Json = Dict[str, Any]
_ParameterValue = Union[float, int, bool, str]

# Errors. Every exception the module raises for a bad input is an Error
# and (all but Error itself) a ValueError.

class Error(Exception):
    """Every error of hfts; `field` names the input that is wrong (may be empty)."""

    field: str
    """The input that is wrong ("start", "parameters.p_max", "poses[3]"); may be empty."""
    problem: str
    """What is wrong with it."""

class InvalidArgument(Error, ValueError):
    """A bad argument: `field` names it, `problem` says what is wrong."""

class SceneError(Error, ValueError):
    """A scene that cannot be read; `field` is the bad member's path."""

class ModelError(Error, ValueError):
    """A robot description (URDF, config) that cannot be used; `field` is empty."""

class MeshError(Error, ValueError):
    """A mesh that cannot be read or holds nothing graspable; `field` is empty."""

class DatabaseError(Error, ValueError):
    """An object database or hand map file that cannot be read or written; `field` is empty."""

# Grasp quality.

def grasp_quality(
    positions: ArrayLike,
    normals: ArrayLike,
    center: Optional[ArrayLike] = None,
    torque_scale: float = 1.0,
    friction: float = 0.5,
    cone_edges: int = 8,
    torsional_friction: float = 0.0,
    normal_direction: str = "inward",
) -> float:
    """Ferrari-Canny epsilon of k contacts: positions and unit normals (k, 3)."""

def grasp_quality_batch(
    positions: ArrayLike,
    normals: ArrayLike,
    center: Optional[ArrayLike] = None,
    torque_scale: float = 1.0,
    friction: float = 0.5,
    cone_edges: int = 8,
    torsional_friction: float = 0.0,
    normal_direction: str = "inward",
) -> _Floats:
    """Epsilon of N grasps of k contacts each (positions, normals (N, k, 3)): an array of N."""

# Object databases and hand maps.

class BuildParameters:
    """How an object database is built (hfts-preprocess's options)."""

    scale: float
    sample_density: float
    max_samples: int
    viewpoints: int
    pad_radius: float
    filters: List[str]
    """A copy: assign a new list to change it."""
    max_curvature: float
    branching: List[int]
    """A copy: assign a new list to change it."""
    seed: int
    def __init__(self) -> None: ...

class ObjectDatabase:
    """An object's HFTS database: contacts in hierarchy order with outward normals."""

    @staticmethod
    def load(path: _Path) -> ObjectDatabase:
        """Reads a database file (HDF5)."""
    @staticmethod
    def build(
        mesh: _Path, parameters: BuildParameters = ..., density: float = 1000.0
    ) -> ObjectDatabase:
        """Builds the database of a mesh file, as hfts-preprocess does."""
    @staticmethod
    def from_arrays(
        vertices: ArrayLike,
        triangles: ArrayLike,
        name: str,
        parameters: BuildParameters = ...,
        density: float = 1000.0,
    ) -> ObjectDatabase:
        """Builds the database of a mesh given as vertices (V, 3) and triangles (T, 3)."""
    def save(self, path: _Path) -> None:
        """Writes the database (HDF5, atomically)."""
    @property
    def name(self) -> str: ...
    @property
    def num_contacts(self) -> int: ...
    @property
    def num_levels(self) -> int: ...
    @property
    def positions(self) -> _Floats:
        """Contact positions (n, 3), hierarchy order (a read-only view)."""
    @property
    def normals(self) -> _Floats:
        """Unit normals (n, 3) pointing out of the object (a read-only view)."""
    @property
    def center_of_mass(self) -> _Floats:
        """(3,), object frame."""
    @property
    def rho(self) -> float:
        """Largest distance (m) from the centre of mass to the surface: the torque scale."""
    @property
    def mass(self) -> float:
        """Density times volume (kg)."""
    @property
    def mesh_vertices(self) -> _Floats:
        """(V, 3), a read-only view."""
    @property
    def mesh_triangles(self) -> NDArray[numpy.uint32]:
        """(T, 3) vertex indices, a read-only view."""
    def grasp_quality(
        self,
        contacts: Sequence[int],
        friction: float = 0.5,
        cone_edges: int = 8,
        torsional_friction: float = 0.0,
    ) -> float:
        """Epsilon of contacts of this database (indices) about its centre of mass, scale rho."""

class HandMap:
    """A hand reachability map: fingertip positions and pad normals of sampled hand postures."""

    @staticmethod
    def load(path: _Path) -> HandMap:
        """Reads a hand map file (HDF5)."""
    @staticmethod
    def build(robot: Robot) -> HandMap:
        """Builds the robot's hand map with its default options (as hfts-preprocess --hand)."""
    def save(self, path: _Path) -> None:
        """Writes the map (HDF5, atomically)."""
    @property
    def robot_name(self) -> str: ...
    @property
    def num_samples(self) -> int: ...
    @property
    def configurations(self) -> _Floats:
        """The sampled hand postures (num_samples, num_hand_dofs), a read-only view."""

# Robots, scenes, worlds, collision checks and IK.

class Robot:
    """A robot: URDF kinematics and its config; joint order: the arm's DoF, then the hand's."""

    @staticmethod
    def load(config: _Path) -> Robot:
        """Loads a robot config (JSON) and the URDF it names."""
    @staticmethod
    def from_strings(urdf: str, config: str, srdf: str = "") -> Robot:
        """A robot from URDF text and config JSON text (and optionally SRDF text)."""
    @property
    def name(self) -> str: ...
    @property
    def num_dofs(self) -> int: ...
    @property
    def num_arm_dofs(self) -> int: ...
    @property
    def num_hand_dofs(self) -> int: ...
    @property
    def dof_names(self) -> List[str]: ...
    @property
    def lower_limits(self) -> _Floats: ...
    @property
    def upper_limits(self) -> _Floats: ...
    @property
    def max_velocities(self) -> _Floats: ...
    @property
    def max_accelerations(self) -> _Floats:
        """Empty when the config gives none (then no trajectories)."""
    @property
    def home(self) -> _Floats: ...
    @property
    def has_hand(self) -> bool: ...
    @property
    def link_names(self) -> List[str]: ...
    @property
    def palm_link(self) -> str: ...
    @property
    def flange_link(self) -> str: ...
    def link_poses(self, configuration: ArrayLike, base: Optional[ArrayLike] = None) -> _Floats:
        """Every link's pose (L, 4, 4) in link_names order, the robot's base at `base`."""

class Scene:
    """A scene: obstacles, the robot's base, the target object and where it stands, the start."""

    @staticmethod
    def load(path: _Path) -> Scene:
        """Reads a scene file (mesh obstacles relative to its folder)."""
    @staticmethod
    def from_json(text: str, base_dir: _Path = ".") -> Scene:
        """A scene from JSON text (mesh paths relative to base_dir)."""
    @property
    def name(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def target_object(self) -> str: ...
    @property
    def robot_base(self) -> _Floats:
        """(4, 4), world frame."""
    @property
    def target_pose(self) -> _Floats:
        """(4, 4), world frame."""
    @property
    def obstacle_names(self) -> List[str]: ...
    @property
    def placement_names(self) -> List[str]:
        """The placements by name: the target's own ("target") first, then the others."""
    def start_for(self, robot_name: str) -> Optional[_Floats]:
        """The scene's start for the robot of that name (None: the robot's home)."""
    def with_placement(self, name: str) -> Scene:
        """The scene with one of its placements as the target's."""

class CollisionChecker:
    """Collision checks of a world's robot in one scene (World.checker); thread-safe."""

    def in_collision(
        self,
        configuration: ArrayLike,
        rule: str = "strict",
        target: bool = True,
        self_collision: bool = True,
        obstacles: bool = True,
    ) -> bool:
        """Whether the robot at the configuration touches what counts (rule "strict" or "grasp")."""
    def in_collision_batch(
        self,
        configurations: ArrayLike,
        rule: str = "strict",
        target: bool = True,
        self_collision: bool = True,
        obstacles: bool = True,
    ) -> NDArray[numpy.bool_]:
        """in_collision of each row of an (N, num_dofs) array: N bools."""
    def clearance(self, configuration: ArrayLike) -> float:
        """Smallest distance (m) from the robot to the scene and the target; 0 in collision."""
    @property
    def scene(self) -> Scene: ...

class World:
    """A robot, its hand map and object databases: what plans are made with. Immutable."""

    def __init__(
        self, robot: Robot, hand_map: HandMap, objects: Sequence[ObjectDatabase]
    ) -> None: ...
    @staticmethod
    def load(robot_config: _Path, db_dir: _Path) -> World:
        """A robot config and, from db_dir, its hand map and every object database."""
    @property
    def robot(self) -> Robot: ...
    @property
    def object_names(self) -> List[str]: ...
    def object(self, name: str) -> ObjectDatabase:
        """An object database of the world by name."""
    def checker(
        self, scene: Scene, object: str = "", object_pose: Optional[ArrayLike] = None
    ) -> CollisionChecker:
        """A collision checker of the robot in `scene` with `object` (default: the target)."""
    def ik(self, pose: ArrayLike, link: str = "palm", seed: int = 1) -> _Floats:
        """Every arm IK solution (M, num_arm_dofs) of a palm or flange pose (base frame)."""
    def ik_batch(
        self, poses: ArrayLike, link: str = "palm", seed: int = 1
    ) -> Tuple[_Floats, NDArray[numpy.int64]]:
        """The IK of (N, 4, 4) poses: solutions (M, num_arm_dofs) and each one's pose index (M,)."""
    def default_settings(self, preset: str = "default") -> PlanSettings:
        """The settings a plan starts from for this robot: preset "default" or "paper"."""
    def parameters(self) -> List[Dict[str, str]]:
        """Every planner parameter: {"name", "default", "range" ("low:step:high")}."""
    def plan(
        self,
        scene: Scene,
        object: str = "",
        object_pose: Optional[ArrayLike] = None,
        start: Optional[ArrayLike] = None,
        goals: Sequence[Union[JointGoal, PoseGoal]] = ...,
        algorithm: str = "coupled",
        settings: Optional[PlanSettings] = None,
        preset: str = "default",
        iterations: Optional[int] = None,
        seed: int = 1,
        time_limit: float = 60.0,
        parameters: Mapping[str, _ParameterValue] = ...,
        trajectory_rate: float = 100.0,
        explored: bool = False,
        validate: bool = False,
        simulation: Optional[SimulationOptions] = None,
        cancel: Optional[Cancel] = None,
        lift: Union[None, bool, float, Dict[str, float]] = None,
        place: Optional[Dict[str, Any]] = None,
    ) -> Plan:
        """Plans a grasp of `object` and a path to it, or with goals a path to one of them."""
    def validate(
        self, plan: Plan, simulation: Optional[SimulationOptions] = None, scene: Optional[Scene] = None
    ) -> _Json:
        """A successful plan's grasp checked again and simulated: {holds, check, physics}; in
        `scene` when given (the object where the plan had it)."""

# Planner settings.

class PaperParameters:
    """The paper's parameters (its Fig. 6)."""

    step_size: float
    p_max: float
    p_min: float
    p_w: float
    p_goal_tree: float
    d_m: float
    w_f: float
    w_c: float
    n_a: int
    kappa: int
    i_min: int
    i_max: int
    alpha: float
    friction: float
    cone_edges: int
    weight_arm: Optional[float]
    weight_hand: Optional[float]
    decoupled_iterations: int
    def __init__(self) -> None: ...

class SearchHeuristics:
    """The project's additions to the paper's search; preset "paper" turns every one off."""

    p_local: float
    local_radius: float
    other_postures: bool
    palm_turns: int
    mask_contacts: bool
    unstable_by_reach: bool
    fit_check: bool
    fit_clearance: float
    def __init__(self) -> None: ...

class GoalCriteria:
    """What a goal must pass."""

    max_fingertip_error: float
    min_epsilon: float
    max_penetration: float
    physics_check: bool
    def __init__(self) -> None: ...

class PathCriteria:
    """What a returned motion must be."""

    certify: bool
    clearance: float
    def __init__(self) -> None: ...

class ExecutionOptions:
    """How the search runs (none changes what a plan is)."""

    threads: int
    sphere_tier: bool
    collision_resolution: float
    smoothing_steps: int
    final_resolution: float
    def __init__(self) -> None: ...

class PlanSettings:
    """A plan's settings, typed; start from World.default_settings()."""

    paper: PaperParameters
    heuristics: SearchHeuristics
    goal: GoalCriteria
    path: PathCriteria
    execution: ExecutionOptions
    def __init__(self) -> None: ...
    def set(self, name: str, value: _ParameterValue) -> None:
        """Sets a setting by its parameter name ("p_max", "threads"), checked against its range."""
    def check(self) -> None:
        """Raises InvalidArgument for a value out of its range."""

class SimulationOptions:
    """The physics check's options."""

    density: Optional[float]
    friction: float
    lift_height: float
    perturb: bool
    min_held_fraction: float
    max_displacement: float
    max_rotation: float
    def __init__(self) -> None: ...

class JointGoal:
    """A configuration to reach: every DoF, or the arm's only."""

    def __init__(self, configuration: ArrayLike) -> None: ...
    @property
    def configuration(self) -> _Floats: ...

class PoseGoal:
    """A pose (4 x 4, world frame) of the palm or flange link to reach, within tolerances."""

    def __init__(
        self,
        pose: ArrayLike,
        link: str = "",
        position_tolerance: float = 0.001,
        orientation_tolerance: float = 0.01,
    ) -> None: ...
    @property
    def pose(self) -> _Floats: ...
    @property
    def link(self) -> str:
        """The palm or flange link's name; empty: the palm."""
    @property
    def position_tolerance(self) -> float: ...
    @property
    def orientation_tolerance(self) -> float: ...

# Plans and trajectories.

class Cancel:
    """Stops a plan from another thread: pass it to World.plan."""

    def __init__(self) -> None: ...
    def cancel(self) -> None:
        """Asks the plan to stop."""
    @property
    def cancelled(self) -> bool: ...

class Trajectory:
    """A trajectory sampled at a fixed rate."""

    @property
    def times(self) -> _Floats:
        """(T,) seconds from the start."""
    @property
    def positions(self) -> _Floats:
        """(T, num_dofs)."""
    @property
    def velocities(self) -> _Floats:
        """(T, num_dofs)."""
    @property
    def accelerations(self) -> _Floats:
        """(T, num_dofs)."""
    @property
    def joint_names(self) -> List[str]: ...
    @property
    def duration(self) -> float: ...
    @property
    def closing_start(self) -> float:
        """When the hand starts closing (the duration when it does not close)."""
    @property
    def lift_start(self) -> float:
        """When the palm starts lifting the object (the duration without a lift)."""
    @property
    def carry_start(self) -> float:
        """A pick and place's: when the carry starts (the duration without)."""
    @property
    def place_start(self) -> float:
        """When the palm descends to put the object down (the duration without a place)."""
    @property
    def release_start(self) -> float:
        """When the hand opens (the duration without a place)."""
    @property
    def retreat_start(self) -> float:
        """When the open hand retreats (the duration without a place)."""
    @property
    def deviation(self) -> float:
        """Largest distance (rad) of the approach from the planned path."""
    def to_ros(self) -> _Json:
        """The trajectory as a dict shaped like trajectory_msgs/JointTrajectory."""
    def __len__(self) -> int: ...

class Plan:
    """A plan: success or why not, the path, the grasp, the trajectory."""

    @property
    def success(self) -> bool: ...
    @property
    def failure(self) -> str:
        """Why the plan failed ("cancelled", "no_valid_goal", ...); "none" on success."""
    @property
    def message(self) -> str: ...
    @property
    def joint_names(self) -> List[str]: ...
    @property
    def path(self) -> _Floats:
        """One configuration per row: start, ..., pre-grasp, grasp."""
    @property
    def seed(self) -> int:
        """The seed that replays this plan with one thread."""
    @property
    def object(self) -> str: ...
    @property
    def object_pose(self) -> _Floats: ...
    @property
    def clearance(self) -> Optional[float]: ...
    @property
    def reached_goal(self) -> Optional[int]:
        """The index of the goal a motion plan reached."""
    @property
    def lift(self) -> Optional[_Json]:
        """The lift from the grasp: {direction, path}; None without one."""
    @property
    def place(self) -> Optional[_Json]:
        """A pick and place's placement: object_pose, carry, descent, open, retreat, rest, ..."""
    @property
    def place_rejected(self) -> Optional[_Json]:
        """A pick and place's placements tried without a goal, by reason."""
    @property
    def grasp(self) -> Optional[_Json]:
        """The grasp as executed (None for a failed or motion plan)."""
    @property
    def trajectory(self) -> Optional[Trajectory]:
        """The time-parameterised path (None when not asked for or not possible)."""
    @property
    def stats(self) -> _Json: ...
    @property
    def validation(self) -> Optional[_Json]:
        """{holds, check, physics}: a successful plan made with validate=True; else None."""
    def to_dict(self) -> _Json:
        """The plan as the service's plan result."""
    def to_ros(self) -> _Json:
        """{"grasp": moveit_msgs/Grasp, "trajectory": trajectory_msgs/JointTrajectory} (or None)."""
    def glb(self) -> bytes:
        """The plan as an animated binary glTF (needs a trajectory)."""
    def write_viewer_page(self, path: _Path, viewer_dir: _Path) -> None:
        """Writes the plan's viewer page; hfts.write_viewer_page finds viewer_dir."""

def time_parameterize(
    robot: Robot, path: ArrayLike, rate: float = 100.0, max_deviation: float = 0.0025
) -> Trajectory:
    """The time-optimal trajectory through a path (N, num_dofs); not collision-checked."""
