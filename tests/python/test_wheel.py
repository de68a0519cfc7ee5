#!/usr/bin/env python3
"""The wheel of the Python module (scripts/build_wheel.sh) builds offline
from the checkout and installs into a fresh virtual environment, where
`import hfts` works (docs/python.md).

Arguments: --source-dir (the checkout), --build-dir (a configured CMake
build folder the extension is built in, HFTS_CMAKE_BUILD_DIR).
"""
import argparse
import glob
import os
import subprocess
import sys
import tempfile
import unittest
import zipfile

ARGS = None


class Wheel(unittest.TestCase):
    def test_builds_offline_and_imports_in_a_fresh_venv(self):
        with tempfile.TemporaryDirectory() as work:
            out = os.path.join(work, "dist")
            env = dict(os.environ, HFTS_CMAKE_BUILD_DIR=ARGS.build_dir,
                       PIP_NO_INDEX="1")  # no package index: offline
            built = subprocess.run([os.path.join(ARGS.source_dir, "scripts", "build_wheel.sh"),
                                    out], capture_output=True, text=True, env=env, timeout=1200)
            self.assertEqual(built.returncode, 0, built.stdout + built.stderr)
            wheels = glob.glob(os.path.join(out, "hfts-*.whl"))
            self.assertEqual(len(wheels), 1, os.listdir(out))
            names = set(zipfile.ZipFile(wheels[0]).namelist())
            for name in ("hfts/__init__.py", "hfts/_hfts.pyi", "hfts/py.typed",
                         "hfts/viewer/dist/viewer.js", "hfts/viewer/src/page.html"):
                self.assertIn(name, names)
            self.assertTrue(any(n.startswith("hfts/_hfts.") and n.endswith(".so") for n in names))
            self.assertNotIn("hfts/_build_info.py", names)  # the build's paths stay out

            venv = os.path.join(work, "venv")
            # Debian's numpy comes from the system's site packages.
            subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv],
                           check=True, timeout=300)
            python = os.path.join(venv, "bin", "python")
            installed = subprocess.run([python, "-m", "pip", "install", "--no-index", wheels[0]],
                                       capture_output=True, text=True, timeout=300)
            self.assertEqual(installed.returncode, 0, installed.stdout + installed.stderr)
            clean = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
            probe = subprocess.run(
                [python, "-c",
                 "import hfts, numpy as np\n"
                 "print(hfts.__file__)\n"
                 "print(hfts.viewer_dir())\n"
                 "c = np.array([[1, 0, 0], [-0.5, 0.8660254037844386, 0],"
                 " [-0.5, -0.8660254037844386, 0]])\n"
                 "print(hfts.grasp_quality(c, -c))\n"],
                capture_output=True, text=True, cwd=work, env=clean, timeout=120)
            self.assertEqual(probe.returncode, 0, probe.stderr)
            module, viewer, epsilon = probe.stdout.split("\n")[:3]
            self.assertTrue(module.startswith(venv), module)
            self.assertTrue(viewer.startswith(venv), viewer)
            self.assertAlmostEqual(float(epsilon), 0.275925155686099, places=12)


def main():
    global ARGS
    parser = argparse.ArgumentParser()
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--build-dir", required=True)
    ARGS, rest = parser.parse_known_args()
    ARGS.source_dir = os.path.abspath(ARGS.source_dir)
    ARGS.build_dir = os.path.abspath(ARGS.build_dir)
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)


if __name__ == "__main__":
    main()
