"""hfts: integrated fingertip-grasp and motion planning, in process.

Load a robot with its hand map and object databases (``World.load``), a
scene (``Scene.load``), plan (``World.plan``), check the grasp in physics
(``World.validate``), and hand the result to a robot stack as ROS-shaped
messages (``Plan.to_ros``). Arrays are numpy arrays; poses are 4 x 4
homogeneous matrices. See docs/python.md.
"""

import os as _os

from ._hfts import (BuildParameters, Cancel, CollisionChecker, DatabaseError, Error,
                    ExecutionOptions, GoalCriteria, HandMap, InvalidArgument, JointGoal, MeshError,
                    ModelError, ObjectDatabase, PaperParameters, PathCriteria, Plan, PlanSettings,
                    PoseGoal, Robot, Scene, SceneError, SearchHeuristics, SimulationOptions,
                    Trajectory, World, grasp_quality, grasp_quality_batch, time_parameterize)

__all__ = [
    "BuildParameters", "Cancel", "CollisionChecker", "DatabaseError", "Error",
    "ExecutionOptions", "GoalCriteria", "HandMap", "InvalidArgument", "JointGoal", "MeshError",
    "ModelError", "ObjectDatabase", "PaperParameters", "PathCriteria", "Plan", "PlanSettings",
    "PoseGoal", "Robot", "Scene", "SceneError", "SearchHeuristics", "SimulationOptions",
    "Trajectory", "World", "grasp_quality", "grasp_quality_batch", "time_parameterize",
    "viewer_dir", "write_viewer_page",
]


def viewer_dir():
    """The web viewer's folder (its page.html and dist/viewer.js): the copy
    installed with the package, else the source tree's viewer/ the build
    was made from. None when neither has a built viewer."""
    here = _os.path.dirname(_os.path.abspath(__file__))
    for candidate in (_os.path.join(here, "viewer"), _os.environ.get("HFTS_VIEWER_DIR", ""),
                      _SOURCE_VIEWER):
        if candidate and _os.path.isfile(_os.path.join(candidate, "dist", "viewer.js")):
            return candidate
    return None


def write_viewer_page(plan, path):
    """Writes a successful plan (with a trajectory) as one HTML page that
    opens from disk in a web browser (docs/viewer.md)."""
    folder = viewer_dir()
    if folder is None:
        problem = ("no built viewer: run scripts/setup.sh (it bundles viewer/dist/viewer.js) "
                   "or set HFTS_VIEWER_DIR")
        error = Error("viewer: " + problem)
        error.field, error.problem = "viewer", problem
        raise error
    plan.write_viewer_page(path, folder)


try:
    from ._build_info import SOURCE_VIEWER as _SOURCE_VIEWER
except ImportError:  # an installed wheel carries its viewer instead
    _SOURCE_VIEWER = ""
