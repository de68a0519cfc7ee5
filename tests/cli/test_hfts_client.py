#!/usr/bin/env python3
"""Tests of hfts-client (the C++ command line) and client/python/hfts_client.py
against a real hfts-server on an ephemeral port. Run by ctest with Debian's
/usr/bin/python3; standard library only."""

import contextlib
import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

from depth_files import CAMERA, HEIGHT, MUG, WIDTH, npy, png
from hfts_server_fixture import (BIN, CONFIG, FAR_AWAY, NO_PHYSICS, NO_PHYSICS_ARGS, QUALITY,
                                 QUALITY_EPSILON, RunningServer, run_tests, wait_until)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "client",
                                "python"))
import hfts_client  # noqa: E402  (the module under test, client/python)


class ClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-client-")
        cls.server = RunningServer(os.path.join(cls.tmp, "log"), "--workers", "2")

    @classmethod
    def tearDownClass(cls):
        code = cls.server.stop()
        shutil.rmtree(cls.tmp, ignore_errors=True)
        assert code == 0, code

    def client(self, *args, port=None, stdin=None):
        return subprocess.run(
            [CONFIG.client, "--port", str(port or self.server.port), *map(str, args)],
            capture_output=True, text=True, timeout=120, input=stdin)

    def ok(self, *args, **kw):
        result = self.client(*args, **kw)
        self.assertEqual(result.returncode, 0, result.stderr)
        return result.stdout


class CommandLine(ClientTest):
    def test_info_is_readable_and_json_is_the_raw_result(self):
        text = self.ok("info")
        self.assertRegex(text, r"^hfts-server \d+\.\d+\.\d+ ")
        self.assertIn("robot: kr5_sdh, 13 DoF, 3 fingertips: a1 a2 a3 a4 a5 a6 knuckle", text)
        self.assertIn("objects: 2, scenes: 3", text)
        self.assertIn("workers: 2 (0 planning, 0 queued, queue capacity 64)", text)
        info = json.loads(self.ok("--json", "info"))
        self.assertEqual(info["robot"]["name"], "kr5_sdh")

    def test_objects_and_scenes(self):
        objects = self.ok("objects").splitlines()
        self.assertEqual(objects[0].split()[:2], ["object", "contacts"])
        self.assertEqual([l.split()[0] for l in objects[1:]], ["blob", "mug"])
        self.assertIn("20/80/320", objects[2])
        scenes = self.ok("scenes").splitlines()
        self.assertEqual([l.split()[0] for l in scenes], ["bin", "shelf", "table"])
        self.assertRegex(scenes[2], r"^table +target mug +at \(0\.550, 0\.000, 0\.000\), "
                                    r"7 obstacles: ")
        self.assertEqual(len(json.loads(self.ok("--json", "scenes"))["scenes"]), 3)

    def test_plan_prints_grasp_path_timing_and_stats(self):
        text = self.ok("plan", "--scene", "bin", "--seed", "1", "--time-limit", "20",
                       *NO_PHYSICS_ARGS)
        lines = text.splitlines()
        self.assertRegex(lines[0],
                         r"^plan: success \(kr5_sdh, bin, blob, coupled, seed 1\) in [\d.]+ s$")
        self.assertRegex(lines[1], r"^grasp \(the hand closed until its pads touch\): "
                                   r"epsilon [\d.e-]+ at the contacts touched \(planned "
                                   r"[\d.e-]+\), penetration [\d.e-]+ mm, reachability "
                                   r"[\d.e-]+ m, planned fingertip error [\d.e-]+ m, "
                                   r"HFTS node on level 3$")
        self.assertEqual(sum(l.startswith("  contact ") for l in lines), 3)
        self.assertTrue(any(l.startswith("  hand (knuckle ") for l in lines))
        self.assertRegex(text, r"\npath: \d+ waypoints \(start \.\.\. pre-grasp, grasp\), length ")
        self.assertRegex(text, r"\nstats: \d+ iterations, \d+ goal sampling calls \(\d+ valid\)")
        self.assertNotIn("proven free", text)
        proven = self.ok("plan", "--scene", "bin", "--seed", "1", "--time-limit", "20",
                         "--param", "certify_path=1", *NO_PHYSICS_ARGS)
        self.assertRegex(proven, r"\npath proven free \(certify_path\); the nearest distance its "
                                 r"proofs measured: [\d.e-]+ mm\n")

    def test_json_and_out_give_the_same_result_as_the_protocol(self):
        out = os.path.join(self.tmp, "plan.json")
        printed = json.loads(self.ok("--json", "--out", out, "plan", "--scene", "bin",
                                     "--seed", "1", "--time-limit", "20", *NO_PHYSICS_ARGS))
        with open(out) as f:
            saved = json.load(f)
        self.assertEqual(saved, printed)
        self.assertEqual([f for f in os.listdir(self.tmp) if ".tmp" in f], [])
        raw = self.server.call("plan", BIN)["result"]
        self.assertEqual(saved["path"], raw["path"])
        self.assertEqual(saved["grasp"], raw["grasp"])

    def test_plan_options_reach_the_server(self):
        start = "0,-1.5,1.5,0,1.5,0,0,-0.2,0.2,-0.2,0.2,-0.2,0.2"
        plan = json.loads(self.ok(
            "--json", "plan", "--scene", "bin", "--object", "mug",
            "--object-pose", "0.55,0.05,0.02,0,0,0,1", "--start", start, "--algorithm",
            "decoupled", "--iterations", "40", "--seed", "3", "--time-limit", "20",
            "--param", "step_size=0.12", "--param", "kappa=4", "--param", "physics_check=0"))
        self.assertEqual((plan["object"], plan["algorithm"], plan["seed"], plan["time_limit"]),
                         ("mug", "decoupled", 3, 20))
        self.assertEqual(plan["object_pose"]["position"], [0.55, 0.05, 0.02])
        self.assertTrue(plan["success"], plan["message"])
        self.assertEqual(plan["path"][0], [float(v) for v in start.split(",")])

    def test_the_trajectory_is_printed_and_written_as_csv(self):
        csv_path = os.path.join(self.tmp, "trajectory.csv")
        text = self.ok("plan", "--scene", "bin", "--seed", "1", "--time-limit", "20",
                       "--trajectory-rate", "50", "--trajectory-csv", csv_path, *NO_PHYSICS_ARGS)
        self.assertRegex(text, r"\ntrajectory: [\d.]+ s, \d+ points, the hand closes from [\d.]+ s")
        with open(csv_path) as f:
            rows = [line.rstrip("\n").split(",") for line in f]
        header, values = rows[0], [[float(v) for v in row] for row in rows[1:]]
        joints = json.loads(self.ok("--json", "info"))["robot"]["joint_names"]
        self.assertEqual(header, ["time_from_start"] + joints + [j + "_velocity" for j in joints]
                         + [j + "_acceleration" for j in joints])
        self.assertGreater(len(values), 10)
        times = [row[0] for row in values]
        self.assertEqual(times[0], 0.0)
        self.assertTrue(all(b > a and b - a <= 1 / 50 + 1e-9 for a, b in zip(times, times[1:])))
        n = len(joints)
        for row in (values[0], values[-1]):  # at rest at both ends
            self.assertEqual(row[1 + n:1 + 2 * n], [0.0] * n)
        # Same plan, same trajectory: the Python client gets the points the CSV holds.
        with hfts_client.HftsClient(self.server.host, self.server.port, timeout=120) as c:
            plan = c.plan("bin", seed=1, time_limit=20, trajectory_rate=50,
                          parameters=NO_PHYSICS)
        points = plan["trajectory"]["points"]
        self.assertEqual(len(points), len(values))
        self.assertEqual(points[-1]["positions"], values[-1][1:1 + n])
        self.assertEqual(points[-1]["time_from_start"], plan["trajectory"]["duration"])

    def test_ros_messages_are_written(self):
        ros_path = os.path.join(self.tmp, "plan_ros.json")
        self.ok("plan", "--scene", "table", "--seed", "1", "--time-limit", "20", "--ros", ros_path,
                *NO_PHYSICS_ARGS)
        with open(ros_path) as f:
            ros = json.load(f)
        self.assertEqual(ros["grasp"]["id"], "mug")
        self.assertEqual(ros["grasp"]["grasp_pose"]["header"]["frame_id"], "world")
        points = ros["trajectory"]["points"]
        self.assertEqual(points[0]["time_from_start"], {"secs": 0, "nsecs": 0})
        # The same plan through the Python client, asked for the ROS format.
        with hfts_client.HftsClient(self.server.host, self.server.port, timeout=120) as c:
            plan = c.plan("table", seed=1, time_limit=20, parameters=NO_PHYSICS, format="ros")
        self.assertEqual(plan["ros"], ros)
        last = plan["trajectory"]["points"][-1]
        self.assertEqual(points[-1]["positions"], last["positions"])
        self.assertAlmostEqual(points[-1]["time_from_start"]["secs"]
                               + 1e-9 * points[-1]["time_from_start"]["nsecs"],
                               last["time_from_start"], delta=1e-9)

    def test_a_motion_plan_to_joint_and_pose_goals(self):
        # No grasp: a path to the configuration, then to the palm pose.
        arm = [0.6, -1.2, 1.3, 0.0, 1.4, 0.0]
        text = self.ok("plan", "--scene", "table", "--time-limit", "20",
                       "--goal-joints", ",".join(map(str, arm)))
        self.assertRegex(text.splitlines()[0],
                         r"^plan: success \(kr5_sdh, table, mug, coupled, seed 1\) in [\d.]+ s$")
        self.assertEqual(text.splitlines()[1], "motion: reached goal 0 of the request's")
        self.assertRegex(text, r"\npath: \d+ waypoints \(start \.\.\. goal\), length ")
        self.assertRegex(text, r"\ntrajectory: [\d.]+ s, \d+ points\n")
        plan = json.loads(self.ok("--json", "plan", "--scene", "table", "--time-limit", "20",
                                  "--goal-pose", "0.52,-0.35,0.6,0.295,0.955,-0.01,0.034",
                                  "--goal-tolerance", "0.005,0.05"))
        self.assertTrue(plan["success"], plan["message"])
        self.assertEqual((plan["reached_goal"], plan["grasp"]), (0, None))
        # A palm in the table top: no free IK solution within the time limit.
        blocked = self.client("plan", "--scene", "table", "--time-limit", "1",
                              "--goal-pose", "0.6,0.0,0.0,0,1,0,0")
        self.assertEqual(blocked.returncode, 3, blocked.stderr)
        self.assertRegex(blocked.stdout, r"^plan: no plan, no_valid_goal: ")
        bad = self.client("plan", "--scene", "table", "--goal-joints", "0.1,x")
        self.assertEqual(bad.returncode, 1)
        self.assertIn("--goal-joints: 'x' is not a number", bad.stderr)
        wrong = self.client("plan", "--scene", "table", "--goal-joints", "0.1,0.2")
        self.assertEqual(wrong.returncode, 1)
        self.assertIn("goals[0].joints: needs 13 values (every DoF) or 6 (the arm's), got 2",
                      wrong.stderr)

    def test_an_inline_scene_file(self):
        scene = os.path.join(self.tmp, "my_bin.json")
        with open(os.path.join(CONFIG.source_dir, "objects", "scenes", "bin.json")) as f:
            data = json.load(f)
        data["name"] = "my_bin"
        with open(scene, "w") as f:
            json.dump(data, f)
        text = self.ok("plan", "--scene-file", scene, "--time-limit", "20", *NO_PHYSICS_ARGS)
        self.assertIn("plan: success (kr5_sdh, my_bin, blob, coupled, seed 1)", text)

    def test_a_plan_without_solution_exits_with_3(self):
        result = self.client("plan", "--scene", "table", "--object-pose",
                             "3,0,0,0,0,0,1", "--time-limit", "0.3")
        self.assertEqual(result.returncode, 3, result.stderr)
        self.assertRegex(result.stdout, r"^plan: no plan, (object_unreachable|no_valid_goal): ")

    def test_quality_from_a_file_and_from_stdin(self):
        request = os.path.join(self.tmp, "quality.json")
        with open(request, "w") as f:
            json.dump(QUALITY, f)
        self.assertEqual(self.ok("quality", request), f"epsilon {QUALITY_EPSILON:.10g}\n")
        result = json.loads(self.ok("--json", "quality", "-", stdin=json.dumps(QUALITY)))
        self.assertAlmostEqual(result["epsilon"], QUALITY_EPSILON, places=12)
        by_object = json.loads(self.ok("--json", "quality", request, "--object", "mug"))
        self.assertGreaterEqual(by_object["epsilon"], 0.0)

    def test_server_errors_exit_with_1_and_the_servers_message(self):
        result = self.client("plan", "--scene", "table", "--object", "teapot")
        self.assertEqual(result.returncode, 1)
        self.assertEqual(result.stdout, "")
        self.assertIn("plan failed: object: unknown object 'teapot'", result.stderr)
        self.assertIn("(error -32602)", result.stderr)
        bad = self.client("plan", "--scene", "table", "--start", "1,2,3")
        self.assertIn("start: must hold 13 values, one per joint of robot 'kr5_sdh', got 3",
                      bad.stderr)
        quality = self.client("quality", "-", stdin='{"contacts": []}')
        self.assertEqual(quality.returncode, 1)
        self.assertIn("contacts: must be a non-empty array", quality.stderr)

    def test_usage_and_connection_errors(self):
        refused = self.client("info", port=1)
        self.assertEqual(refused.returncode, 1)
        self.assertIn("cannot connect to 127.0.0.1:1", refused.stderr)
        no_scene = self.client("plan")
        self.assertEqual(no_scene.returncode, 1)
        self.assertIn("plan needs --scene NAME or --scene-file FILE", no_scene.stderr)
        self.assertNotEqual(self.client("teleport").returncode, 0)
        unreadable = self.client("quality", os.path.join(self.tmp, "missing.json"))
        self.assertEqual(unreadable.returncode, 1)
        self.assertIn("cannot read", unreadable.stderr)


class DepthView(ClientTest):
    """plan --depth FILE --camera JSON [--mask FILE]: the view goes inline in the
    request's obstacles."""

    def write(self, name, data):
        path = os.path.join(self.tmp, name)
        with open(path, "wb" if isinstance(data, bytes) else "w") as f:
            f.write(data if isinstance(data, bytes) else json.dumps(data))
        return path

    def plan(self, *args):
        return self.client("--json", "plan", "--scene", "table", "--time-limit", "5",
                           *NO_PHYSICS_ARGS, *args)

    def test_a_depth_png_or_npy_with_its_camera_is_planned_with(self):
        depth = self.write("d.png", png(WIDTH, HEIGHT, [1200] * (WIDTH * HEIGHT)))
        mask = self.write("m.png", png(WIDTH, HEIGHT, [255 * m for m in MUG], bits=8))
        camera = self.write("cam.json", CAMERA)
        glb = os.path.join(self.tmp, "seen.glb")
        result = self.plan("--depth", depth, "--camera", camera, "--mask", mask, "--gltf", glb)
        self.assertIn(result.returncode, (0, 3), result.stderr)  # 3: no plan in 5 s
        self.assertIn("success", json.loads(result.stdout))
        # The same view as a float32 .npy in metres, named, with an inline scene.
        metres = self.write("d.npy", npy(WIDTH, HEIGHT, [1.2] * (WIDTH * HEIGHT)))
        named = self.write("named.json", {**CAMERA, "name": "top", "voxel": 0.02})
        scene = os.path.join(CONFIG.source_dir, "objects", "scenes", "table.json")
        result = self.client("--json", "plan", "--scene-file", scene, "--time-limit", "5",
                             *NO_PHYSICS_ARGS, "--depth", metres, "--camera", named)
        self.assertIn(result.returncode, (0, 3), result.stderr)
        self.assertIn("success", json.loads(result.stdout))
        # The server reads the view: a camera without a focal length is its error.
        blind = self.write("blind.json", {**CAMERA, "intrinsics": {"fx": 0, "fy": 40,
                                                                  "cx": 15.5, "cy": 11.5}})
        refused = self.plan("--depth", depth, "--camera", blind)
        self.assertEqual(refused.returncode, 1)
        self.assertIn("plan failed: obstacles[0].intrinsics.fx: must be a positive number",
                      refused.stderr)
        clash = self.write("clash.json", {**CAMERA, "name": "table"})
        self.assertIn("obstacles[0].name: 'table' is an obstacle of scene 'table' already",
                      self.plan("--depth", depth, "--camera", clash).stderr)

    def test_usage_errors(self):
        depth = self.write("u.png", png(2, 2, [1000] * 4))
        camera = self.write("u.json", CAMERA)
        cases = [
            (["--depth", os.path.join(self.tmp, "missing.png"), "--camera", camera],
             "--depth '%s': cannot read the file" % os.path.join(self.tmp, "missing.png")),
            (["--depth", camera, "--camera", camera], "neither a PNG nor a NumPy .npy file"),
            (["--depth", depth, "--camera", depth], "--camera '%s': not valid JSON" % depth),
            (["--depth", depth, "--camera", self.write("list.json", [1, 2])],
             "must be a JSON object with the camera's intrinsics and pose"),
            (["--depth", depth, "--camera", self.write("no_pose.json",
                                                       {"intrinsics": CAMERA["intrinsics"]})],
             "has no 'pose'"),
            (["--depth", depth, "--camera", self.write("no_k.json", {"pose": CAMERA["pose"]})],
             "has no 'intrinsics'"),
            (["--depth", depth, "--camera", self.write("file.json", {**CAMERA, "file": "x.png"})],
             "'file' is the image's: --depth and --mask give the image"),
            (["--depth", depth, "--camera", camera, "--mask", camera], "--mask '%s': not a PNG"
             % camera),
            (["--mask", depth], "--mask needs --depth and --camera"),
            (["--camera", camera], "--camera needs --depth"),
            (["--depth", depth], "--depth needs --camera"),
        ]
        for args, message in cases:
            with self.subTest(args=args):
                result = self.client("plan", "--scene", "table", *args)
                self.assertEqual(result.returncode, 1, result.stderr)
                self.assertIn(message, result.stderr)
                self.assertEqual(result.stdout, "")


class PythonClient(ClientTest):
    def connect(self):
        return hfts_client.HftsClient(self.server.host, self.server.port, timeout=120)

    def test_every_call(self):
        with self.connect() as client:
            self.assertEqual(client.info()["robot"]["name"], "kr5_sdh")
            self.assertEqual([o["name"] for o in client.objects()["objects"]], ["blob", "mug"])
            self.assertEqual(len(client.scenes()["scenes"]), 3)
            plan = client.plan("bin", seed=1, time_limit=20, parameters=NO_PHYSICS)
            self.assertTrue(plan["success"], plan["message"])
            self.assertEqual(len(plan["path"][0]), len(plan["joint_names"]))
            self.assertAlmostEqual(client.quality(QUALITY["contacts"]), QUALITY_EPSILON,
                                   places=12)
            self.assertEqual(client.reload()["objects"], ["blob", "mug"])

    def test_motion_goals(self):
        goal = hfts_client.joint_goal([0.6, -1.2, 1.3, 0.0, 1.4, 0.0])
        with self.connect() as client:
            plan = client.plan("table", goal=goal, time_limit=20)
            self.assertTrue(plan["success"], plan["message"])
            self.assertEqual(plan["reached_goal"], 0)
            self.assertEqual(plan["path"][-1][:6], goal["joints"])
            self.assertEqual(plan["path"][-1][6:], plan["path"][0][6:], "the start's hand")
            pose = hfts_client.pose_goal([0.52, -0.35, 0.6], [0.295, 0.955, -0.01, 0.034],
                                         position_tolerance=0.005,
                                         orientation_tolerance=0.05)
            both = client.plan("table", goals=[pose, goal], time_limit=20)
            self.assertTrue(both["success"], both["message"])
            self.assertIn(both["reached_goal"], (0, 1))
            with self.assertRaises(hfts_client.RpcError) as caught:
                client.plan("table", goal=hfts_client.pose_goal([0, 0, 1], [0, 0, 0, 1],
                                                                link="finger_1_distal"))
            self.assertEqual(caught.exception.field, "goal.link")

    def test_a_depth_image_goes_in_the_obstacles(self):
        image = png(WIDTH, HEIGHT, [1200] * (WIDTH * HEIGHT))
        mask = png(WIDTH, HEIGHT, [255 * m for m in MUG], bits=8)
        view = hfts_client.depth_image(image, CAMERA, mask=mask)
        self.assertEqual((view["type"], view["name"], view["units"]),
                         ("depth_image", "camera", "mm"))
        metres = hfts_client.depth_image(npy(2, 1, [1.0, 2.0]), {**CAMERA, "name": "top"})
        self.assertEqual((metres["name"], metres["units"]), ("top", "m"))
        self.assertIn("npy_base64", metres)
        with self.connect() as client:
            plan = client.plan("table", obstacles=[view], time_limit=5, parameters=NO_PHYSICS)
            self.assertIn("success", plan)
            with self.assertRaises(hfts_client.RpcError) as caught:
                client.plan("table", obstacles=[{**view, "name": "jar"}])
            self.assertEqual(caught.exception.field, "obstacles[0].name")
        for image, camera in ((b"GIF89a", CAMERA), (image, {"pose": CAMERA["pose"]}),
                              (image, {**CAMERA, "file": "x.png"})):
            with self.assertRaises(ValueError):
                hfts_client.depth_image(image, camera)

    def test_errors_raise_with_code_and_field(self):
        with self.connect() as client:
            with self.assertRaises(hfts_client.RpcError) as caught:
                client.plan("table", object_pose={"position": [0, 0, 0],
                                                  "orientation": [0, 0, 0, 0]})
            self.assertEqual(caught.exception.code, -32602)
            self.assertEqual(caught.exception.field, "object_pose.orientation")
            self.assertIn("zero norm", caught.exception.message)
            with self.assertRaises(hfts_client.RpcError) as unknown:
                client.call("teleport")
            self.assertEqual(unknown.exception.code, -32601)
            self.assertEqual(client.info()["name"], "hfts-server")

    def test_a_plan_can_be_cancelled_while_it_runs(self):
        with self.connect() as client:
            request = client.plan_async("table", object_pose=FAR_AWAY, time_limit=30)
            self.assertTrue(wait_until(lambda: self.server.call("server.info")["result"]
                                       ["load"]["running"] >= 1))
            began = time.monotonic()
            self.assertTrue(client.cancel(request))
            plan = client.receive(request)
            self.assertEqual(plan["reason"], "cancelled")
            self.assertLess(time.monotonic() - began, 2.0)
            self.assertFalse(client.cancel(request), "it is no longer running")

    def test_the_module_runs_as_a_program(self):
        buffer = io.StringIO()
        with contextlib.redirect_stdout(buffer):
            code = hfts_client.main(["--port", str(self.server.port), "plan", "bin",
                                     "--time-limit", "20", *NO_PHYSICS_ARGS])
        self.assertEqual(code, 0)
        plan = json.loads(buffer.getvalue())
        self.assertTrue(plan["success"])
        self.assertEqual(plan["stats"]["physics_checks"], 0, "--param reached the server")
        with contextlib.redirect_stderr(io.StringIO()) as usage:
            with self.assertRaises(SystemExit) as bad:
                hfts_client.main(["--port", str(self.server.port), "plan", "bin",
                                  "--param", "physics_check"])
        self.assertEqual(bad.exception.code, 2)
        self.assertIn("--param: expected NAME=VALUE, got 'physics_check'", usage.getvalue())


class Shutdown(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="hfts-client-shutdown-")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_shutdown_stops_the_server_with_exit_code_0(self):
        server = RunningServer(os.path.join(self.tmp, "log"))
        result = subprocess.run([CONFIG.client, "--port", str(server.port), "shutdown"],
                                capture_output=True, text=True, timeout=60)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stdout, "the server is shutting down\n")
        self.assertEqual(server.process.wait(timeout=30), 0)
        server.stop()

    def test_the_python_client_stops_the_server_too(self):
        server = RunningServer(os.path.join(self.tmp, "log"))
        with hfts_client.HftsClient(server.host, server.port) as client:
            self.assertEqual(client.shutdown(), {"shutting_down": True})
        self.assertEqual(server.process.wait(timeout=30), 0)
        server.stop()


if __name__ == "__main__":
    run_tests(with_client=True)
