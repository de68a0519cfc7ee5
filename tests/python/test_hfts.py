#!/usr/bin/env python3
"""The in-process Python module hfts (docs/python.md), under /usr/bin/python3.

Plans made in process equal the C++ planner's (hfts-server's) for the same
request and seed; bad arguments raise hfts.InvalidArgument (a ValueError)
naming the field; the GIL is released while a plan runs; the batch calls
give what the single calls give; the ROS-shaped results round-trip through
Debian's ROS message classes (python3-trajectory-msgs, genpy).

Arguments: --python-dir (the build's python/ folder), --server, --preprocess,
--source-dir; the rest goes to unittest. The databases of the mug and the
blob and the KR5 + SDH hand map are built once into a temporary folder.
"""
import argparse
import io
import json
import os
import shutil
import signal
import sys
import tempfile
import threading
import time
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "cli"))

import hfts_server_fixture as fixture  # noqa: E402
from cli_support import run_tests_with_databases  # noqa: E402

hfts = None  # imported from --python-dir in main()
ARGS = None
NO_PHYSICS = {"physics_check": 0}
# The mug beyond the KR5's reach but within its fingertips' reach ball
# (tests/cli/hfts_server_fixture.py): the planner searches until stopped.
FAR_AWAY = np.array([[1, 0, 0, 1.3], [0, 1, 0, 0], [0, 0, 1, 0.335], [0, 0, 0, 1.0]])


def setUpModule():
    global WORLD, TABLE, BIN
    WORLD = hfts.World.load(robot_config("kr5_sdh"), ARGS.db_dir)
    TABLE = hfts.Scene.load(scene_file("table"))
    BIN = hfts.Scene.load(scene_file("bin"))


def robot_config(name):
    return os.path.join(ARGS.source_dir, "robots", name, name + ".json")


def scene_file(name):
    return os.path.join(ARGS.source_dir, "objects", "scenes", name + ".json")


class Errors(unittest.TestCase):
    """Bad arguments raise the mapped exception, naming the field."""

    def assertField(self, field, call, *args, **kwargs):
        with self.assertRaises(hfts.InvalidArgument) as raised:
            call(*args, **kwargs)
        self.assertEqual(raised.exception.field, field, str(raised.exception))
        self.assertIsInstance(raised.exception, ValueError)
        self.assertIsInstance(raised.exception, hfts.Error)
        self.assertTrue(str(raised.exception).startswith(field + ": "), str(raised.exception))
        self.assertTrue(raised.exception.problem)

    def test_plan_arguments(self):
        self.assertField("start", WORLD.plan, TABLE, start=np.zeros(3))
        self.assertField("start", WORLD.plan, TABLE, start=np.full(13, np.nan))
        self.assertField("parameters.p_max", WORLD.plan, TABLE, parameters={"p_max": 7})
        self.assertField("parameters.no_such", WORLD.plan, TABLE, parameters={"no_such": 1})
        self.assertField("parameters.threads", WORLD.plan, TABLE, parameters={"threads": [2]})
        self.assertField("object_pose", WORLD.plan, TABLE, object_pose=np.eye(3))
        self.assertField("object_pose", WORLD.plan, TABLE, object_pose=2 * np.eye(4))
        self.assertField("algorithm", WORLD.plan, TABLE, algorithm="astar")
        self.assertField("preset", WORLD.plan, TABLE, preset="fast")
        self.assertField("time_limit", WORLD.plan, TABLE, time_limit=-1.0)
        self.assertField("seed", WORLD.plan, TABLE, seed=-1)
        self.assertField("seed", WORLD.ik_batch, np.stack([np.eye(4)]), seed=2**64)
        settings = WORLD.default_settings()
        settings.paper.i_min = 500
        self.assertField("parameters.i_min", WORLD.plan, TABLE, settings=settings)
        self.assertField("lift.height", WORLD.plan, TABLE, lift=0.0)
        self.assertField("lift", WORLD.plan, TABLE, lift="up")
        self.assertField("lift.held_speed", WORLD.plan, TABLE, lift={"held_speed": 0.0})
        self.assertField("lift.speed", WORLD.plan, TABLE, lift={"speed": 0.5})
        self.assertField("place.on", WORLD.plan, TABLE, place={"on": "floor"})
        self.assertField("place.colour", WORLD.plan, TABLE, place={"on": "table", "colour": 1})
        self.assertField("parameters.p_max", settings.set, "p_max", 2.0)

    def test_other_arguments(self):
        self.assertField("positions", hfts.grasp_quality, np.zeros((3, 2)), np.zeros((3, 3)))
        self.assertField("normals[0]", hfts.grasp_quality, np.eye(3), np.zeros((3, 3)))
        self.assertField("grasps[1].normals[2]", hfts.grasp_quality_batch,
                         np.stack([np.eye(3)] * 2), np.array([-np.eye(3), [[-1, 0, 0], [0, -1, 0],
                                                                        [0, 0, 0.5]]]))
        self.assertField("path[1]", hfts.time_parameterize, WORLD.robot,
                         np.array([np.zeros(13), np.full(13, np.nan)]))
        self.assertField("normals", hfts.grasp_quality_batch, np.zeros((5, 3, 3)),
                         np.zeros((4, 3, 3)))
        self.assertField("normal_direction", hfts.grasp_quality, np.eye(3), -np.eye(3),
                         normal_direction="in")
        self.assertField("poses", WORLD.ik_batch, np.zeros((2, 3, 4)))
        self.assertField("poses[1]", WORLD.ik_batch, np.stack([np.eye(4), 2 * np.eye(4)]))
        self.assertField("link", WORLD.ik, np.eye(4), link="wrist")
        checker = WORLD.checker(TABLE)
        self.assertField("configurations", checker.in_collision_batch, np.zeros((4, 12)))
        self.assertField("configurations[1]", checker.in_collision_batch,
                         np.array([np.zeros(13), np.full(13, np.inf)]))
        self.assertField("configuration", checker.in_collision, np.zeros(2))
        beyond = WORLD.robot.home.copy()
        beyond[6] = 1e20  # finite, far outside the limits
        self.assertField("configuration", checker.in_collision, beyond)
        self.assertField("configuration", checker.clearance, beyond)
        self.assertField("configurations[1]", checker.in_collision_batch,
                         np.stack([WORLD.robot.home, beyond]))
        self.assertField("configuration", WORLD.robot.link_poses, beyond)
        self.assertField("triangles", hfts.ObjectDatabase.from_arrays, np.eye(3),
                         np.array([[0, 1, 2.7]]), "floats")
        self.assertField("rule", checker.in_collision, np.zeros(13), rule="loose")
        self.assertField("object", WORLD.checker, TABLE, object="anvil")
        self.assertField("triangles[0]", hfts.ObjectDatabase.from_arrays, np.eye(3),
                         np.array([[0, 1, 3]]), "tri")
        self.assertField("name", hfts.ObjectDatabase.from_arrays, np.eye(3),
                         np.array([[0, 1, 2]]), "../evil")

    def test_numpy_scalars_are_numbers(self):
        poses = np.stack([np.eye(4)])
        np.testing.assert_array_equal(WORLD.ik_batch(poses, seed=np.int64(3))[0],
                                      WORLD.ik_batch(poses, seed=3)[0])
        a = WORLD.plan(TABLE, seed=np.uint8(2), time_limit=30,
                       parameters={"physics_check": np.bool_(False), "p_max": np.float32(0.75),
                                   "smoothing_steps": np.int64(40)})
        b = WORLD.plan(TABLE, seed=2, time_limit=30,
                       parameters={"physics_check": 0, "p_max": 0.75, "smoothing_steps": 40})
        self.assertTrue(a.success, a.message)
        np.testing.assert_array_equal(a.path, b.path)
        self.assertField("seed", WORLD.plan, TABLE, seed=1.5)

    def test_what_a_plan_cannot_give(self):
        failed = WORLD.plan(TABLE, object_pose=FAR_AWAY, time_limit=0.2, parameters=NO_PHYSICS)
        self.assertField("plan", WORLD.validate, failed)
        self.assertField("plan", failed.glb)
        motion = WORLD.plan(TABLE, goals=[hfts.JointGoal(WORLD.robot.home[:6] + 0.1)],
                            time_limit=30)
        self.assertTrue(motion.success, motion.message)
        self.assertField("plan", WORLD.validate, motion)
        grasp = WORLD.plan(TABLE, seed=1, time_limit=30, parameters=NO_PHYSICS)
        with tempfile.TemporaryDirectory() as folder:
            self.assertField("viewer_dir", grasp.write_viewer_page,
                             os.path.join(folder, "page.html"), folder)

    def test_files_that_do_not_load(self):
        with self.assertRaises(hfts.SceneError):
            hfts.Scene.from_json('{"name": "x", "obstacles": [{"type": "box"}]}')
        with self.assertRaises(hfts.ModelError):
            hfts.Robot.from_strings("<robot name='r'/>", "{}")
        with self.assertRaises(hfts.DatabaseError):
            hfts.World.load(robot_config("kr5_sdh"), "/nonexistent/folder")
        with tempfile.TemporaryDirectory() as empty, self.assertRaises(hfts.DatabaseError):
            hfts.World.load(robot_config("kr5_sdh"), empty)  # no hand map
        with tempfile.NamedTemporaryFile(suffix=".h5") as bad:
            bad.write(b"not hdf5")
            bad.flush()
            with self.assertRaises(hfts.DatabaseError):
                hfts.ObjectDatabase.load(bad.name)


class SameAsCpp(unittest.TestCase):
    """A plan made in process equals hfts-server's for the same request."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-python-")
        cls.server = fixture.RunningServer(os.path.join(cls.tmp, "server.log"), "--workers", "1")

    @classmethod
    def tearDownClass(cls):
        code = cls.server.stop()
        shutil.rmtree(cls.tmp, ignore_errors=True)
        assert code == 0, f"hfts-server exited with {code}"

    def served(self, params):
        response = self.server.call("plan", params)
        self.assertIn("result", response, response)
        return response["result"]

    def test_plans_equal_the_servers_for_the_same_seed(self):
        for scene, name, seed in ((TABLE, "table", 1), (TABLE, "table", 7), (BIN, "bin", 3)):
            with self.subTest(scene=name, seed=seed):
                mine = WORLD.plan(scene, seed=seed, time_limit=30, parameters=NO_PHYSICS)
                theirs = self.served({"scene": name, "seed": seed, "time_limit": 30,
                                      "parameters": NO_PHYSICS})
                self.assertTrue(mine.success, mine.message)
                self.assertTrue(theirs["success"], theirs["message"])
                self.assertEqual(mine.joint_names, theirs["joint_names"])
                np.testing.assert_array_equal(mine.path, np.array(theirs["path"]))
                self.assertEqual(mine.lift["direction"], theirs["lift"]["direction"])
                np.testing.assert_array_equal(mine.lift["path"], np.array(theirs["lift"]["path"]))
                self.assertEqual(mine.grasp["epsilon"], theirs["grasp"]["epsilon"])
                self.assertEqual(mine.stats["collision_checks"],
                                 theirs["stats"]["collision_checks"])
                # The whole result, as the service writes it (timings aside).
                as_dict = mine.to_dict()
                for key in ("path", "grasp", "trajectory", "object_pose", "plan_seed", "lift"):
                    self.assertEqual(as_dict[key], theirs[key], key)

    def test_typed_settings_equal_the_same_parameters_by_name(self):
        settings = WORLD.default_settings()
        settings.paper.p_max = 0.6
        settings.execution.smoothing_steps = 50
        settings.goal.physics_check = False
        typed = WORLD.plan(TABLE, seed=2, time_limit=30, settings=settings)
        by_name = self.served({"scene": "table", "seed": 2, "time_limit": 30, "parameters": {
            "p_max": 0.6, "smoothing_steps": 50, "physics_check": 0}})
        np.testing.assert_array_equal(typed.path, np.array(by_name["path"]))

    def test_the_services_ros_format_is_the_modules(self):
        mine = WORLD.plan(TABLE, seed=1, time_limit=30, parameters=NO_PHYSICS)
        theirs = self.served({"scene": "table", "seed": 1, "time_limit": 30,
                              "parameters": NO_PHYSICS, "format": "ros"})
        self.assertEqual(theirs["ros"], mine.to_ros())
        plain = self.served({"scene": "table", "seed": 1, "time_limit": 30,
                             "parameters": NO_PHYSICS})
        self.assertNotIn("ros", plain)
        response = self.server.call("plan", {"scene": "table", "format": "xml"})
        self.assertEqual(response["error"]["code"], -32602, response)
        self.assertEqual(response["error"]["data"]["field"], "format", response)

    def test_a_world_built_from_parts_plans_the_same(self):
        robot = hfts.Robot.load(robot_config("kr5_sdh"))
        hand_map = hfts.HandMap.load(os.path.join(ARGS.db_dir, "kr5_sdh_hand_map.h5"))
        mug = hfts.ObjectDatabase.load(os.path.join(ARGS.db_dir, "mug.h5"))
        world = hfts.World(robot, hand_map, [mug])
        self.assertEqual(world.object_names, ["mug"])
        a = world.plan(TABLE, seed=5, time_limit=30, parameters=NO_PHYSICS)
        b = WORLD.plan(TABLE, seed=5, time_limit=30, parameters=NO_PHYSICS)
        self.assertTrue(a.success, a.message)
        np.testing.assert_array_equal(a.path, b.path)


class Threads(unittest.TestCase):
    def test_the_gil_is_released_while_planning(self):
        """A second Python thread runs while a plan that cannot succeed
        searches; a Cancel from it stops the plan."""
        cancel = hfts.Cancel()
        outcome = {}

        def plan():
            started = time.monotonic()
            outcome["plan"] = WORLD.plan(TABLE, object_pose=FAR_AWAY, time_limit=30,
                                         parameters=NO_PHYSICS, cancel=cancel)
            outcome["seconds"] = time.monotonic() - started

        worker = threading.Thread(target=plan)
        worker.start()
        counted, deadline = 0, time.monotonic() + 1.5
        while time.monotonic() < deadline:
            counted += 1  # pure Python: runs only while the plan lets go of the GIL
        still_planning = worker.is_alive()
        cancel.cancel()
        worker.join(timeout=30)
        self.assertTrue(still_planning, "the plan ended before the other thread was done")
        self.assertGreater(counted, 100000)
        self.assertFalse(worker.is_alive())
        self.assertEqual(outcome["plan"].failure, "cancelled")
        self.assertLess(outcome["seconds"], 10)
        self.assertTrue(cancel.cancelled)

    def test_ctrl_c_stops_a_plan(self):
        """SIGINT (Ctrl-C) during a plan that cannot succeed raises
        KeyboardInterrupt soon, not at the end of its time limit."""
        timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        started = time.monotonic()
        with self.assertRaises(KeyboardInterrupt):
            WORLD.plan(TABLE, object_pose=FAR_AWAY, time_limit=30, parameters=NO_PHYSICS)
        timer.join()
        self.assertLess(time.monotonic() - started, 5)
        # The world plans again afterwards.
        self.assertTrue(WORLD.plan(TABLE, seed=1, time_limit=30, parameters=NO_PHYSICS).success)

    def test_a_checker_shared_by_threads(self):
        checker = WORLD.checker(TABLE)
        rng = np.random.default_rng(3)
        robot = WORLD.robot
        q = rng.uniform(robot.lower_limits, robot.upper_limits, size=(400, robot.num_dofs))
        alone = checker.in_collision_batch(q)
        results = [None] * 4

        def check(i):
            results[i] = checker.in_collision_batch(q)

        threads = [threading.Thread(target=check, args=(i,)) for i in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for r in results:
            np.testing.assert_array_equal(r, alone)


class Batches(unittest.TestCase):
    """Each batch call gives what the single call gives, item by item."""

    def test_grasp_quality_batch(self):
        mug = WORLD.object("mug")
        rng = np.random.default_rng(11)
        picks = rng.integers(0, mug.num_contacts, size=(300, 3))
        positions, normals = mug.positions[picks], mug.normals[picks]
        common = dict(center=mug.center_of_mass, torque_scale=mug.rho,
                      normal_direction="outward")
        batch = hfts.grasp_quality_batch(positions, normals, **common)
        self.assertEqual(batch.shape, (300,))
        single = [hfts.grasp_quality(p, n, **common) for p, n in zip(positions, normals)]
        np.testing.assert_array_equal(batch, single)
        np.testing.assert_array_equal(batch[:20],
                                      [mug.grasp_quality(list(i)) for i in picks[:20]])
        self.assertGreater(np.count_nonzero(batch), 0)
        self.assertGreater(np.count_nonzero(batch == 0), 0)

    def test_ik_batch(self):
        robot = WORLD.robot
        rng = np.random.default_rng(5)
        q = rng.uniform(robot.lower_limits, robot.upper_limits, size=(50, robot.num_dofs))
        palm = robot.link_names.index(robot.palm_link)
        poses = np.stack([robot.link_poses(c)[palm] for c in q])
        solutions, index = WORLD.ik_batch(poses)
        self.assertEqual(solutions.shape[1], robot.num_arm_dofs)
        self.assertEqual(sorted(set(index.tolist())), list(range(50)))  # each pose solved
        for i in range(50):
            single = WORLD.ik(poses[i], seed=1 + i)
            np.testing.assert_array_equal(solutions[index == i], single)
            # Some solution is the configuration the pose came from.
            self.assertLess(np.min(np.abs(single - q[i, :robot.num_arm_dofs]).max(axis=1)), 1e-6)

    def test_collision_batch(self):
        checker = WORLD.checker(TABLE)
        robot = WORLD.robot
        rng = np.random.default_rng(8)
        q = rng.uniform(robot.lower_limits, robot.upper_limits, size=(500, robot.num_dofs))
        batch = checker.in_collision_batch(q)
        single = np.array([checker.in_collision(c) for c in q])
        np.testing.assert_array_equal(batch, single)
        self.assertTrue(batch.any() and not batch.all())
        grasp_rule = checker.in_collision_batch(q, rule="grasp", self_collision=False)
        np.testing.assert_array_equal(
            grasp_rule, [checker.in_collision(c, rule="grasp", self_collision=False) for c in q])


class Results(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.plan = WORLD.plan(TABLE, seed=1, time_limit=30, parameters=NO_PHYSICS)
        assert cls.plan.success, cls.plan.message

    def test_arrays(self):
        plan = self.plan
        self.assertEqual(plan.path.shape, (len(plan.to_dict()["path"]), 13))
        np.testing.assert_array_equal(plan.path[-1, 6:], plan.grasp["hand_configuration"])
        t = plan.trajectory
        self.assertEqual(t.positions.shape, (len(t), 13))
        self.assertEqual(t.times[-1], t.duration)
        np.testing.assert_allclose(t.positions[0], plan.path[0], atol=1e-12)
        # The trajectory ends with the lift, which starts at the grasp.
        np.testing.assert_allclose(plan.lift["path"][0], plan.path[-1], atol=1e-12)
        np.testing.assert_allclose(t.positions[-1], plan.lift["path"][-1], atol=1e-12)
        closed = t.positions[np.searchsorted(t.times, t.lift_start)]
        np.testing.assert_allclose(closed, plan.path[-1], atol=1e-12)
        self.assertLess(t.closing_start, t.lift_start)
        limit = WORLD.robot.max_velocities * (1 + 1e-6)
        self.assertTrue((np.abs(t.velocities) <= limit).all())

    def test_held_speed(self):
        # The same plan with the arm at half speed while it holds the mug:
        # the lift takes twice as long, within half the velocity limits.
        plans = [WORLD.plan(TABLE, seed=1, time_limit=30, parameters=NO_PHYSICS,
                            lift={"height": 0.1, "held_speed": speed}) for speed in (1.0, 0.5)]
        for plan in plans:
            self.assertTrue(plan.success, plan.message)
        np.testing.assert_array_equal(plans[0].path, plans[1].path)
        fast, t = plans[0].trajectory, plans[1].trajectory
        self.assertAlmostEqual(t.lift_start, fast.lift_start, places=9)
        self.assertAlmostEqual((t.duration - t.lift_start) / (fast.duration - fast.lift_start), 2.0,
                               places=3)
        lifting = t.times > t.lift_start
        limit = 0.5 * WORLD.robot.max_velocities * (1 + 1e-6)
        self.assertTrue((np.abs(t.velocities[lifting]) <= limit).all())

    def test_pick_and_place(self):
        area = ((0.30, -0.42), (0.42, -0.30))
        plan = WORLD.plan(TABLE, seed=1, time_limit=30, parameters=NO_PHYSICS,
                          place={"on": "table", "area": area})
        self.assertTrue(plan.success, plan.message)
        place = plan.place
        # The mug's origin is within 8 cm of its centre of mass, which is in the area.
        x, y = place["object_pose"]["position"][:2]
        self.assertTrue(area[0][0] - 0.08 <= x <= area[1][0] + 0.08, x)
        self.assertTrue(area[0][1] - 0.08 <= y <= area[1][1] + 0.08, y)
        np.testing.assert_allclose(place["carry"][0], plan.lift["path"][-1], atol=1e-12)
        np.testing.assert_allclose(place["carry"][-1], place["descent"][0], atol=1e-12)
        self.assertTrue(place["rest"]["stable"])
        t = plan.trajectory
        self.assertLess(t.lift_start, t.carry_start)
        self.assertLess(t.carry_start, t.place_start)
        self.assertLess(t.place_start, t.release_start)
        self.assertLess(t.release_start, t.retreat_start)
        np.testing.assert_allclose(t.positions[-1], place["retreat"][-1], atol=1e-9)
        self.assertEqual(set(plan.place_rejected), {"unsupported", "no_arm_ik", "colliding",
                                                    "descent_blocked", "release_blocked",
                                                    "retreat_blocked", "unstable"})
        self.assertIsNone(self.plan.place)

    def test_time_parameterize(self):
        robot = WORLD.robot
        path = self.plan.path[:-1]
        t = hfts.time_parameterize(robot, path, rate=50)
        self.assertEqual(t.positions.shape[1], 13)
        np.testing.assert_allclose(t.positions[-1], path[-1], atol=1e-12)
        self.assertTrue((np.abs(t.velocities) <= robot.max_velocities * (1 + 1e-6)).all())
        self.assertTrue((np.abs(t.accelerations) <= robot.max_accelerations * (1 + 1e-6)).all())

    def test_database_arrays_are_views(self):
        mug = WORLD.object("mug")
        positions = mug.positions
        self.assertFalse(positions.flags.writeable)
        self.assertIsNotNone(positions.base)  # a view of the database, not a copy
        self.assertTrue(np.shares_memory(positions, mug.positions))
        self.assertEqual(positions.shape, (mug.num_contacts, 3))

    def test_database_from_arrays(self):
        # A 6 x 4 x 3 cm box, its triangles wound outwards.
        corners = np.array([[x, y, z] for x in (0, 0.06) for y in (0, 0.04) for z in (0, 0.03)])
        faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                          [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
        box = hfts.ObjectDatabase.from_arrays(corners, faces, "py_box")
        self.assertGreater(box.num_contacts, 50)
        np.testing.assert_allclose(box.center_of_mass, [0.03, 0.02, 0.015], atol=1e-9)
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "py_box.h5")
            box.save(path)
            again = hfts.ObjectDatabase.load(path)
        np.testing.assert_array_equal(again.positions, box.positions)
        self.assertEqual(again.name, "py_box")

    def test_ros_messages_round_trip(self):
        """The trajectory and the grasp's postures as trajectory_msgs/
        JointTrajectory, its pose as geometry_msgs/PoseStamped, through
        genpy's serialisation and back."""
        from geometry_msgs.msg import PoseStamped
        from trajectory_msgs.msg import JointTrajectory

        ros = self.plan.to_ros()
        for name, shaped in (("trajectory", ros["trajectory"]),
                             ("pre_grasp_posture", ros["grasp"]["pre_grasp_posture"]),
                             ("grasp_posture", ros["grasp"]["grasp_posture"])):
            with self.subTest(message=name):
                again = round_trip(JointTrajectory, shaped)
                self.assertEqual(list(again.joint_names), shaped["joint_names"])
                self.assertEqual(len(again.points), len(shaped["points"]))
                for point, expected in zip(again.points, shaped["points"]):
                    self.assertEqual(list(point.positions), expected["positions"])
                    self.assertEqual(list(point.velocities), expected["velocities"])
                    self.assertEqual(point.time_from_start.secs,
                                     expected["time_from_start"]["secs"])
                    self.assertEqual(point.time_from_start.nsecs,
                                     expected["time_from_start"]["nsecs"])
        trajectory = round_trip(JointTrajectory, ros["trajectory"])
        self.assertAlmostEqual(trajectory.points[-1].time_from_start.to_sec(),
                               self.plan.trajectory.duration, delta=1e-9)
        pose = round_trip(PoseStamped, ros["grasp"]["grasp_pose"])
        self.assertEqual(pose.header.frame_id, "world")
        self.assertEqual(set(ros["grasp"]), {
            "id", "pre_grasp_posture", "grasp_posture", "grasp_pose", "grasp_quality",
            "pre_grasp_approach", "post_grasp_retreat", "post_place_retreat",
            "max_contact_force", "allowed_touch_objects"})  # moveit_msgs/Grasp's fields
        self.assertEqual(ros["grasp"]["grasp_quality"], self.plan.grasp["epsilon"])
        # The palm link's pose at the grasp, from the robot's kinematics.
        robot = WORLD.robot
        palm = robot.link_poses(self.plan.path[-1], TABLE.robot_base)[
            robot.link_names.index(robot.palm_link)]
        p = ros["grasp"]["grasp_pose"]["pose"]["position"]
        np.testing.assert_allclose([p["x"], p["y"], p["z"]], palm[:3, 3], atol=1e-12)

    def test_failed_plan_has_no_ros_grasp(self):
        failed = WORLD.plan(TABLE, object_pose=FAR_AWAY, time_limit=0.5, parameters=NO_PHYSICS)
        self.assertFalse(failed.success)
        self.assertEqual(failed.to_ros(), {"grasp": None, "trajectory": None})
        self.assertIsNone(failed.grasp)
        self.assertIsNone(failed.trajectory)

    def test_validation_in_physics(self):
        """World.validate gives what a plan asked to validate carries."""
        verdict = WORLD.validate(self.plan)
        self.assertEqual(verdict["holds"], verdict["check"]["valid"] and verdict["physics"]["held"])
        self.assertGreaterEqual(verdict["physics"]["held_fraction"], 0.0)
        validated = WORLD.plan(TABLE, seed=1, time_limit=30, parameters=NO_PHYSICS, validate=True)
        np.testing.assert_array_equal(validated.path, self.plan.path)
        self.assertEqual(validated.validation["check"], verdict["check"])
        self.assertEqual(validated.validation["holds"], verdict["holds"])
        self.assertEqual(validated.validation["physics"]["held_fraction"],
                         verdict["physics"]["held_fraction"])
        light = hfts.SimulationOptions()
        light.perturb = False
        self.assertEqual(len(WORLD.validate(self.plan, light)["physics"]["trials"]), 1)

    def test_validation_in_another_scene_puts_its_object_where_that_scene_has_it(self):
        """A true scene whose target is another object (the true one of an
        object built from views): that object where that scene has it, here
        45 cm beside the mug the plan grasps, so the hand closes on nothing."""
        with open(scene_file("table")) as f:
            truth = json.load(f)
        truth["target"] = {"object": "blob", "rest_on": "table",
                           "pose": {"position": [0.55, 0.45, 0], "orientation": [0, 0, 0, 1]}}
        verdict = WORLD.validate(self.plan, scene=hfts.Scene.from_json(json.dumps(truth)))
        self.assertFalse(verdict["check"]["pads_touch"])
        self.assertFalse(verdict["holds"])
        # Where the mug was, the hand closes on the blob.
        truth["target"]["pose"]["position"] = [0.55, 0, 0]
        verdict = WORLD.validate(self.plan, scene=hfts.Scene.from_json(json.dumps(truth)))
        self.assertTrue(verdict["check"]["pads_touch"])


def round_trip(message_class, shaped):
    """A message from its dict, serialised with genpy and read back."""
    message = fill(message_class(), shaped)
    buffer = io.BytesIO()
    message.serialize(buffer)
    again = message_class()
    again.deserialize(buffer.getvalue())
    return again


def fill(message, shaped):
    import genpy
    for name, value in shaped.items():
        current = getattr(message, name)
        if isinstance(current, (genpy.Time, genpy.Duration)):
            setattr(message, name, type(current)(value["secs"], value["nsecs"]))
        elif hasattr(current, "__slots__"):
            fill(current, value)
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            item_class = type(message)._slot_types[type(message).__slots__.index(name)]
            module = __import__(item_class.split("/")[0] + ".msg", fromlist=["x"])
            cls = getattr(module, item_class.split("/")[1].rstrip("[]"))
            setattr(message, name, [fill(cls(), v) for v in value])
        else:
            setattr(message, name, value)
    return message


def main():
    global hfts, ARGS
    parser = argparse.ArgumentParser()
    for option in ("--python-dir", "--server", "--preprocess", "--source-dir"):
        parser.add_argument(option, required=True)
    ARGS, rest = parser.parse_known_args()
    sys.path.insert(0, os.path.abspath(ARGS.python_dir))
    import hfts as module
    hfts = module
    for key in ("server", "preprocess", "source_dir"):
        setattr(fixture.CONFIG, key, os.path.abspath(getattr(ARGS, key)))
    ARGS.source_dir = os.path.abspath(ARGS.source_dir)

    def use(folder):
        ARGS.db_dir = fixture.CONFIG.db_dir = folder

    run_tests_with_databases(ARGS.preprocess, ARGS.source_dir, ["mug", "blob"], rest, use)


if __name__ == "__main__":
    main()
