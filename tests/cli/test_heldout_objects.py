#!/usr/bin/env python3
"""The held-out objects (objects/heldout): the generator reproduces the
committed meshes byte for byte, every mesh has its density sidecar, and
hfts-preprocess builds a database for every one, the scans' centre of mass
from their capped surface. Run by ctest with Debian's /usr/bin/python3."""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

BINARY = None
SOURCE_DIR = None
MESH_EXTENSIONS = (".ply", ".stl", ".obj")


class HeldOutObjects(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-heldout-")
        cls.folder = os.path.join(SOURCE_DIR, "objects", "heldout")
        cls.meshes = os.path.join(cls.folder, "meshes")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def mesh_names(self):
        return sorted(f for f in os.listdir(self.meshes) if f.endswith(MESH_EXTENSIONS))

    def test_the_generator_reproduces_the_committed_meshes(self):
        out = os.path.join(self.tmp, "generated")
        result = subprocess.run(["/usr/bin/python3", os.path.join(self.folder, "generate_heldout.py"),
                                 "--out", out], capture_output=True, text=True, timeout=600)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(sorted(os.listdir(out)), sorted(os.listdir(self.meshes)))
        for name in os.listdir(out):
            with open(os.path.join(out, name), "rb") as a, open(os.path.join(self.meshes, name), "rb") as b:
                self.assertTrue(a.read() == b.read(), f"{name} differs from the committed file")

    def test_every_mesh_has_a_density_sidecar(self):
        names = self.mesh_names()
        self.assertEqual(len(names), 27)
        for name in names:
            with open(os.path.join(self.meshes, os.path.splitext(name)[0] + ".json")) as f:
                sidecar = json.load(f)
            self.assertEqual(list(sidecar), ["density"], name)
            self.assertTrue(200 <= sidecar["density"] <= 8000, name)

    def test_every_object_gets_a_database_and_every_scan_a_repaired_centre_of_mass(self):
        out = os.path.join(self.tmp, "db")
        result = subprocess.run([BINARY, self.meshes, "-o", out, "-j", "2", "-q"], capture_output=True,
                                text=True, timeout=600)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.assertIn("27 built, 0 failed", result.stdout)
        for name in self.mesh_names():
            stem = os.path.splitext(name)[0]
            summary = json.loads(subprocess.run([BINARY, "--inspect", os.path.join(out, stem + ".h5"), "--json"],
                                                capture_output=True, text=True, check=True).stdout)
            scan = stem.endswith("_scan")
            self.assertEqual(summary["closed"], not scan, stem)
            self.assertEqual(summary["center_of_mass_method"], "repaired_mesh" if scan else "closed_mesh", stem)
            self.assertGreater(summary["volume"], 0.0, stem)
            self.assertGreater(summary["num_contacts"], 250, stem)
        for scan in ("lemon", "marker", "clamp", "banana", "padlock", "espresso_cup", "spray_bottle"):
            self.assertIn(f"{scan}_scan.ply' is not a closed manifold (16 boundary, 1 non-manifold, "
                          "0 inconsistently wound edges)", result.stderr)
            self.assertIn(f"{scan}_scan.ply': dropped 2 zero-area triangles", result.stderr)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", required=True)
    parser.add_argument("--source-dir", required=True)
    args, rest = parser.parse_known_args()
    BINARY, SOURCE_DIR = args.binary, args.source_dir
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
