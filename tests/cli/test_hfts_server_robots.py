#!/usr/bin/env python3
"""One hfts-server, three robots (docs/protocol.md "Several robots"):
`--robot A --robot B`, the `robot` field of plan, objects.list and
scenes.list, server.info's robot list, and both clients.
Run by ctest with Debian's /usr/bin/python3; standard library only."""

import base64
import json
import os
import subprocess
import sys

from hfts_server_fixture import CONFIG, NO_PHYSICS, NO_PHYSICS_ARGS, ServerTest, run_tests

BIN_MUG = {"scene": "bin", "object": "mug", "seed": 1, "time_limit": 60, "parameters": NO_PHYSICS}


def config(robot):
    return os.path.join(CONFIG.source_dir, "robots", robot, robot + ".json")


class ThreeRobots(ServerTest):
    """The fixture's KR5 + SDH first (the default), then the Panda and the UR5e."""

    @classmethod
    def setUpClass(cls):
        cls.OPTIONS = ("--workers", "2", "--robot", config("panda_gripper"),
                       "--robot", config("ur5e_allegro"))
        super().setUpClass()

    def test_server_info_lists_both_robots_with_their_own_parameter_defaults(self):
        info = self.server.call("server.info")["result"]
        self.assertEqual(info["robot"]["name"], "kr5_sdh", "the first --robot is the default")
        robots = {r["name"]: r for r in info["robots"]}
        self.assertEqual([r["name"] for r in info["robots"]],
                         ["kr5_sdh", "panda_gripper", "ur5e_allegro"])
        self.assertEqual(len(robots["panda_gripper"]["joint_names"]), 8)
        self.assertEqual(len(robots["panda_gripper"]["fingertips"]), 2)
        self.assertEqual(len(robots["ur5e_allegro"]["joint_names"]), 22)
        self.assertEqual(len(robots["ur5e_allegro"]["fingertips"]), 4)
        defaults = {name: {p["name"]: p["default"] for p in r["planner_parameters"]}
                    for name, r in robots.items()}
        for robot in robots:
            self.assertEqual(defaults[robot]["unstable_by_reach"], "1", robot)
        self.assertEqual(float(defaults["kr5_sdh"]["max_fingertip_error"]), 0.008)
        self.assertEqual(float(defaults["panda_gripper"]["max_fingertip_error"]), 0.005)
        self.assertEqual(float(defaults["ur5e_allegro"]["max_fingertip_error"]), 0.008)

    def test_listings_are_per_robot(self):
        default = self.server.call("scenes.list")["result"]
        panda = self.server.call("scenes.list", {"robot": "panda_gripper"})["result"]
        self.assertEqual((default["robot"], panda["robot"]), ("kr5_sdh", "panda_gripper"))
        shelf = {s["name"]: s for s in panda["scenes"]}["shelf"]
        self.assertEqual(len(shelf["start"]), 8, "the shelf's start for the Panda")
        objects = self.server.call("objects.list", {"robot": "panda_gripper"})["result"]
        kr5_objects = self.server.call("objects.list")["result"]
        self.assertEqual([o["name"] for o in objects["objects"]], ["blob", "mug"])
        self.assertNotEqual(objects["objects"][1]["graspability"],
                            kr5_objects["objects"][1]["graspability"])

    def test_a_plan_for_each_robot_moves_that_robots_joints(self):
        panda = self.server.call("plan", dict(BIN_MUG, robot="panda_gripper"))["result"]
        self.assertTrue(panda["success"], panda["message"])
        self.assertEqual(panda["robot"], "panda_gripper")
        self.assertEqual(panda["joint_names"][-1], "panda_finger_joint1")
        self.assertEqual(len(panda["grasp"]["contacts_world"]), 2)
        self.assertTrue(all(len(q) == 8 for q in panda["path"]))
        kr5 = self.server.call("plan", BIN_MUG)["result"]
        self.assertTrue(kr5["success"], kr5["message"])
        self.assertEqual(kr5["robot"], "kr5_sdh")
        self.assertEqual(len(kr5["grasp"]["contacts_world"]), 3)
        self.assertTrue(all(len(q) == 13 for q in kr5["path"]))
        ur = self.server.call("plan", dict(BIN_MUG, scene="table", robot="ur5e_allegro",
                                           gltf=True))["result"]
        self.assertTrue(ur["success"], ur["message"])
        self.assertEqual(ur["robot"], "ur5e_allegro")
        self.assertEqual(len(ur["grasp"]["contacts_world"]), 4)
        self.assertEqual(len(ur["grasp"]["hand_configuration"]), 16)
        self.assertTrue(all(len(q) == 22 for q in ur["path"]))
        self.assertEqual(base64.b64decode(ur["gltf"])[:4], b"glTF")

    def test_unknown_robots_and_wrong_starts_name_the_field(self):
        self.assertError(self.server.call("plan", dict(BIN_MUG, robot="ur5e")), -32602,
                         field="robot", request_id=1,
                         contains="(this server plans for: kr5_sdh, panda_gripper, ur5e_allegro)")
        self.assertError(self.server.call("scenes.list", {"robot": "ur5e"}), -32602,
                         field="robot", request_id=1)
        kr5_start = [0, -1.5, 1.5, 0, 1.5, 0, 0, -0.2, 0.2, -0.2, 0.2, -0.2, 0.2]
        self.assertError(
            self.server.call("plan", dict(BIN_MUG, robot="panda_gripper", start=kr5_start)),
            -32602, field="start", request_id=1,
            contains="must hold 8 values, one per joint of robot 'panda_gripper', got 13")
        self.assertError(self.server.call("objects.list", {"robots": "kr5_sdh"}), -32602,
                         field="robots", request_id=1)

    def test_the_clients_pass_the_robot(self):
        info = self.client("info")
        self.assertIn("robot: panda_gripper, 8 DoF, 2 fingertips", info.stdout)
        self.assertIn("(the default)", info.stdout)
        plan = self.client("plan", "--robot", "panda_gripper", "--scene", "bin", "--object", "mug",
                           "--time-limit", "20", *NO_PHYSICS_ARGS)
        self.assertEqual(plan.returncode, 0, plan.stderr)
        self.assertIn("plan: success (panda_gripper, bin, mug", plan.stdout)
        objects = self.client("objects", "--robot", "panda_gripper")
        self.assertIn("graspable (panda_gripper)", objects.stdout)
        python = subprocess.run(
            [sys.executable, os.path.join(CONFIG.source_dir, "client", "python", "hfts_client.py"),
             "--port", str(self.server.port), "scenes", "--robot", "panda_gripper"],
            capture_output=True, text=True, timeout=60)
        self.assertEqual(python.returncode, 0, python.stderr)
        self.assertEqual(json.loads(python.stdout)["robot"], "panda_gripper")

    def test_two_configs_of_one_robot_stop_the_server_with_the_reason(self):
        kr5 = os.path.join(CONFIG.source_dir, "robots", "kr5_sdh", "kr5_sdh.json")
        result = subprocess.run(
            [CONFIG.server, "--db", CONFIG.db_dir, "--port", "0", "--robot", kr5, "--robot", kr5,
             "--scenes", os.path.join(CONFIG.source_dir, "objects", "scenes")],
            capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL)
        self.assertEqual(result.returncode, 1)
        self.assertIn("a second robot named 'kr5_sdh'", result.stderr)


if __name__ == "__main__":
    run_tests(with_client=True)
