#!/usr/bin/env python3
"""The plan viewer in a real browser: a plan made through hfts-server and
hfts-client, written as one page by `hfts-client view`, opened in headless
Chromium (Debian's chromium, driven by puppeteer-core from npm; both
installed by scripts/setup.sh): no console errors, the robot moves between
the first and the last frame where the palm is, the contacts are drawn, the
simulated lift plays.
Run by ctest with /usr/bin/python3; standard library only."""

import json
import os
import struct
import subprocess

from depth_files import CAMERA, HEIGHT, MUG, WIDTH, png
from hfts_server_fixture import CONFIG, NO_PHYSICS_ARGS, ServerTest, run_tests


class Viewer(ServerTest):
    OPTIONS = ()

    def page(self, scene):
        plan = os.path.join(self.tmp, scene + ".json")
        result = self.client("--out", plan, "plan", "--scene", scene, "--seed", "1",
                             "--time-limit", "60", "--gltf", os.path.join(self.tmp, scene + ".glb"))
        self.assertEqual(result.returncode, 0, result.stderr)
        html = os.path.join(self.tmp, scene + ".html")
        result = self.client("view", plan, "-o", html)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("wrote " + html, result.stdout)
        return plan, html

    def check(self, html):
        shots = os.path.join(self.tmp, os.path.basename(html) + "_shots")
        result = subprocess.run(
            ["node", os.path.join(CONFIG.source_dir, "viewer", "tools", "check_viewer.js"),
             html, shots], capture_output=True, text=True, timeout=300)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        for png in ("first.png", "last.png"):
            self.assertGreater(os.path.getsize(os.path.join(shots, png)), 10000)
        return json.loads(result.stdout)

    def test_the_page_loads_plays_and_shows_the_contacts(self):
        for scene in ("table", "bin"):
            with self.subTest(scene=scene):
                plan_path, html = self.page(scene)
                with open(plan_path) as f:
                    plan = json.load(f)
                report = self.check(html)
                self.assertEqual(report["consoleErrors"], [])
                self.assertAlmostEqual(report["duration"], plan["trajectory"]["duration"], places=3)
                self.assertEqual(report["contacts"], 3)
                self.assertEqual(report["markers"], 9)  # a sphere, a normal and a cone each
                self.assertGreaterEqual(report["animatedNodes"], 15)
                # The robot moved: many pixels change near the palm's two places.
                self.assertGreater(report["changedNearPalm"], 2000, report)
                self.assertGreater(report["redPixels"], 10, report)
                # The planner simulated the grasp (physics_check): the page
                # also plays the simulated lift, the object rising 10 cm.
                self.assertTrue(plan["physics"]["held"])
                self.assertEqual(report["clips"], ["plan", "simulated"])
                self.assertAlmostEqual(report["simulatedDuration"],
                                       plan["physics"]["motion"][-1]["time"], places=3)
                self.assertGreater(report["objectMoved"], 0.08, report)
                self.assertLess(report["objectMoved"], 0.12, report)
                self.assertIn(report["phaseAtLift"], ("lift", "hold"))

    def test_the_explored_nodes_are_drawn_on_the_object(self):
        plan_path = os.path.join(self.tmp, "explored.json")
        result = self.client("--out", plan_path, "plan", "--scene", "bin", "--seed", "1",
                             "--time-limit", "20", *NO_PHYSICS_ARGS, "--explored", "--gltf",
                             os.path.join(self.tmp, "explored.glb"))
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(plan_path) as f:
            plan = json.load(f)
        self.assertEqual(len(plan["explored"]), plan["stats"]["hfts_nodes_explored"])
        html = os.path.join(self.tmp, "explored.html")
        self.assertEqual(self.client("view", plan_path, "-o", html).returncode, 0)
        report = self.check(html)
        self.assertEqual(report["consoleErrors"], [])
        self.assertEqual(report["explored"], 3 * len(plan["explored"]))

    def test_what_a_depth_camera_saw_is_drawn_as_points(self):
        files = {}
        for name, data in (("depth.png", png(WIDTH, HEIGHT, [1200] * (WIDTH * HEIGHT))),
                           ("mask.png", png(WIDTH, HEIGHT, [255 * m for m in MUG], bits=8)),
                           ("camera.json", json.dumps(CAMERA).encode())):
            files[name] = os.path.join(self.tmp, name)
            with open(files[name], "wb") as f:
                f.write(data)
        plan_path, glb = os.path.join(self.tmp, "seen.json"), os.path.join(self.tmp, "seen.glb")
        result = self.client("--out", plan_path, "plan", "--scene", "table", "--time-limit", "20",
                             *NO_PHYSICS_ARGS, "--depth", files["depth.png"], "--camera",
                             files["camera.json"], "--mask", files["mask.png"], "--gltf", glb)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(glb, "rb") as f:
            data = f.read()
        gltf = json.loads(data[20:20 + struct.unpack("<I", data[12:16])[0]])
        node = next(n for n in gltf["nodes"] if n.get("name") == "camera.points")
        primitive = gltf["meshes"][node["mesh"]]["primitives"][0]
        self.assertEqual(primitive["mode"], 0)
        seen = gltf["accessors"][primitive["attributes"]["POSITION"]]["count"]
        self.assertGreater(seen, WIDTH * HEIGHT // 2)  # all but the mask and the robot's
        html = os.path.join(self.tmp, "seen.html")
        self.assertEqual(self.client("view", plan_path, "-o", html).returncode, 0)
        report = self.check(html)
        self.assertEqual(report["consoleErrors"], [])
        self.assertEqual(report["points"], seen)
        self.assertGreater(report["violetPixels"], 1000, report)

    def test_view_needs_a_successful_plan_with_its_gltf(self):
        failed = os.path.join(self.tmp, "failed.json")
        result = self.client("--out", failed, "plan", "--scene", "table", "--object-pose",
                             "3,0,0,0,0,0,1", "--time-limit", "0.3")
        self.assertEqual(result.returncode, 3)
        result = self.client("view", failed)
        self.assertEqual(result.returncode, 1)
        self.assertIn("not a successful plan result", result.stderr)
        bare = os.path.join(self.tmp, "bare.json")
        self.assertEqual(self.client("--out", bare, "plan", "--scene", "table",
                                     *NO_PHYSICS_ARGS).returncode, 0)
        result = self.client("view", bare)
        self.assertEqual(result.returncode, 1)
        self.assertIn("the plan has no glTF", result.stderr)
        result = self.client("view", bare, "--glb", bare)
        self.assertIn("not a binary glTF", result.stderr)
        result = self.client("view", bare, "--glb", os.path.join(self.tmp, "no.glb"))
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("--glb: File does not exist", result.stderr)
        full = os.path.join(self.tmp, "full.json")
        self.assertEqual(self.client("--out", full, "plan", "--scene", "table", *NO_PHYSICS_ARGS,
                                     "--gltf", os.path.join(self.tmp, "full.glb")).returncode, 0)
        result = self.client("view", full, "--viewer-dir", self.tmp)
        self.assertEqual(result.returncode, 1)
        self.assertIn("scripts/setup.sh", result.stderr)


if __name__ == "__main__":
    run_tests(with_client=True)
