#!/usr/bin/env python3
"""hfts-render-depth (docs/point_clouds.md): a bundled scene rendered from a
camera, read back as a scene whose obstacle is the depth image, and the
collision checker's two tiers agreeing with FCL alone on it. Standard
library only."""

import argparse
import json
import os
import shutil
import sys
import tempfile
import unittest

from cli_support import run

ARGS = None


class RenderDepth(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-render-depth-")
        cls.db = os.path.join(cls.tmp, "db")
        cls.views = os.path.join(cls.tmp, "views")
        cls.scene = os.path.join(ARGS.source_dir, "objects", "scenes", "table.json")
        cls.target = json.load(open(cls.scene))["target"]["object"]
        meshes = os.path.join(ARGS.source_dir, "objects", "meshes")
        for mesh in os.listdir(meshes):
            if os.path.splitext(mesh)[0] == cls.target and not mesh.endswith(".json"):
                run(ARGS.preprocess, os.path.join(meshes, mesh), "-o", cls.db, "-q", check=0)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def render(self, *args):
        return run(ARGS.render, self.scene, "-o", self.views, "--db", self.db, *args)

    def test_a_view_is_an_image_a_mask_and_a_scene_the_checker_agrees_on(self):
        result = self.render("--eye", "-0.35,0,0.95", "--look-at", "0.55,0,0.1",
                             "--width", 160, "--height", 120, "--fov", 50, "--name", "behind")
        self.assertEqual(result.returncode, 0, result.stderr)
        seen, total, on_target = (int(result.stdout.split(": ")[1].split()[i]) for i in (0, 2, 7))
        self.assertEqual(total, 160 * 120)
        self.assertGreater(seen, total // 2)  # the table fills most of the view
        self.assertGreater(on_target, 20)  # and the target some of it
        for name in ("behind.png", "behind_mask.png"):
            with open(os.path.join(self.views, name), "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        scene = json.load(open(os.path.join(self.views, "behind.json")))
        self.assertEqual([o["type"] for o in scene["obstacles"]], ["depth_image"])
        self.assertEqual(scene["obstacles"][0]["mask"], "behind_mask.png")
        self.assertNotIn("rest_on", scene["target"])
        # The two tiers against FCL alone, in the scene seen by the camera.
        agreement = run(ARGS.agreement, "--db", self.db, "--robot",
                        os.path.join(ARGS.source_dir, "robots", "kr5_sdh", "kr5_sdh.json"),
                        "--scene-dir", self.views, "--configurations", 3000, "--motions", 20)
        self.assertEqual(agreement.returncode, 0, (agreement.stdout, agreement.stderr))
        rows = [line.split() for line in agreement.stdout.splitlines()[1:]
                if line and not line.startswith(" ")]
        self.assertEqual([r[0] for r in rows], ["behind"])
        configs, colliding, disagree, mdisagree = (int(rows[0][i]) for i in (1, 2, 5, 8))
        self.assertEqual(configs, 3000)
        self.assertTrue(0 < colliding < 3000, agreement.stdout)
        self.assertEqual(disagree, 0)
        self.assertEqual(mdisagree, 0)

    def test_partial_writes_the_targets_points_and_a_scene_to_grasp_them(self):
        out = os.path.join(self.tmp, "partial")
        result = run(ARGS.render, self.scene, "-o", out, "--db", self.db, "--eye", "0.15,0.75,0.95",
                     "--look-at", "0.55,0,0.1", "--width", 160, "--height", 120, "--name", "left",
                     "--partial")
        self.assertEqual(result.returncode, 0, result.stderr)
        on_target = int(result.stdout.split(": ")[1].split()[7])
        with open(os.path.join(out, "left_object.ply")) as f:
            header = f.read().split("end_header\n")
        count = int(header[0].split("element vertex ")[1].split()[0])
        self.assertEqual(count, len(header[1].splitlines()))
        self.assertGreater(count, 0.8 * on_target)  # the target's pixels, but dropouts
        # The points lie where the target stands (the table's mug at x 0.55).
        xs = [float(line.split()[0]) for line in header[1].splitlines()]
        self.assertTrue(all(0.45 < x < 0.7 for x in xs), (min(xs), max(xs)))
        with open(os.path.join(out, "left_partial.json")) as f:
            scene = json.load(f)
        self.assertEqual(scene["target"]["object"], "left_object")
        self.assertEqual(scene["target"]["pose"]["position"], [0.0, 0.0, 0.0])
        self.assertNotIn("rest_on", scene["target"])
        # Without --partial, neither.
        self.assertFalse(os.path.exists(os.path.join(self.views, "behind_object.ply")))

    def test_bad_arguments_are_refused(self):
        result = self.render("--eye", "0,0", "--look-at", "1,0,0")
        self.assertEqual(result.returncode, 2)
        self.assertIn("--eye", result.stderr)
        result = self.render("--eye", "0,0,1", "--look-at", "1,0,0", "--noise", "loud")
        self.assertEqual(result.returncode, 2)
        result = run(ARGS.render, self.scene, "-o", self.views, "--db",
                     os.path.join(self.tmp, "nothing"), "--eye", "0,0,1", "--look-at", "1,0,0")
        self.assertEqual(result.returncode, 1)
        self.assertIn("no database", result.stderr)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    for option in ("--render", "--agreement", "--preprocess", "--source-dir"):
        parser.add_argument(option, required=True)
    ARGS, rest = parser.parse_known_args()
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
