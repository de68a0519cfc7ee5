#!/usr/bin/env python3
"""The collision_agreement program (docs/collision.md): the two-tier checker
against FCL alone in every bundled scene, a short run. Standard library only."""

import os
import shutil
import sys
import tempfile
import unittest

from cli_support import bench_options, bundled_meshes, run

BINARY = None
PREPROCESS = None
SOURCE_DIR = None
TARGETS = ["blob", "bottle", "mug"]  # the bundled scenes' targets


class CollisionAgreement(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-agreement-")
        cls.db = os.path.join(cls.tmp, "db")
        meshes = os.path.join(SOURCE_DIR, "objects", "meshes")
        for mesh in bundled_meshes(SOURCE_DIR):
            if os.path.splitext(mesh)[0] in TARGETS:
                run(PREPROCESS, os.path.join(meshes, mesh), "-o", cls.db, "-q", check=0)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def agreement(self, *args, db=None):
        return run(BINARY, "--db", db or self.db,
                   "--robot", os.path.join(SOURCE_DIR, "robots", "kr5_sdh", "kr5_sdh.json"),
                   "--scene-dir", os.path.join(SOURCE_DIR, "objects", "scenes"), *args)

    def test_certified_segments_agree_with_a_dense_sweep(self):
        result = self.agreement("--configurations", 1, "--motions", 0, "--certified", 12)
        self.assertEqual(result.returncode, 0, (result.stdout, result.stderr))
        certified = [line for line in result.stdout.splitlines()
                     if line.startswith("  certifySegment")]
        self.assertEqual(len(certified), 3, result.stdout)
        free = 0
        for line in certified:
            self.assertIn("12 segments", line)
            self.assertIn(" 0 disagreements with a 1001-state sweep", line)
            free += int(line.split(", ")[1].split()[0])
        self.assertGreater(free, 0, result.stdout)  # some are proven, so the sweep ran

    def test_no_disagreement_in_any_scene(self):
        result = self.agreement("--configurations", 3000, "--motions", 30)
        self.assertEqual(result.returncode, 0, (result.stdout, result.stderr))
        lines = result.stdout.splitlines()[1:]
        rows = [line.split() for line in lines if not line.startswith(" ")]
        # isMotionValid of both checkers on the same motions, two resolutions per scene.
        validations = [line for line in lines if line.startswith("  isMotionValid")]
        self.assertEqual(len(validations), 6, result.stdout)
        for line in validations:
            self.assertIn("60 motions (both rules)", line)
            self.assertIn(" 0 disagreements", line)
        self.assertEqual(sorted(r[0] for r in rows), ["bin", "shelf", "table"])
        for scene, configs, colliding, tips, settled, disagree, motions, states, mdisagree, *_ in rows:
            self.assertEqual(int(configs), 3000)
            self.assertTrue(0 < int(colliding) < 3000, scene)
            self.assertEqual(int(disagree), 0, scene)
            self.assertEqual(int(motions), 30)
            self.assertGreater(int(states), 30)
            self.assertEqual(int(mdisagree), 0, scene)
            self.assertGreater(float(settled.rstrip("%")), 0.0, scene)
        # Hands near the targets: some configurations touch only with fingertips.
        self.assertGreater(sum(int(r[3]) for r in rows), 0)

    def test_bad_arguments_are_refused(self):
        result = self.agreement("--configurations", 0)
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("--configurations", result.stderr)
        empty = os.path.join(self.tmp, "empty")
        os.makedirs(empty, exist_ok=True)
        result = self.agreement("--configurations", 10, "--motions", 0, db=empty)
        self.assertEqual(result.returncode, 2)
        self.assertIn(".h5", result.stderr)


if __name__ == "__main__":
    BINARY, PREPROCESS, SOURCE_DIR, rest = bench_options()
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
