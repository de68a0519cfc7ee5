#!/usr/bin/env python3
"""The Python examples (examples/python/, docs/python.md) run and do what
they say, under /usr/bin/python3 with the build's module.

Arguments: --python-dir (the build's python/ folder), --preprocess,
--source-dir; the rest goes to unittest. The mug's database and the KR5 +
SDH hand map are built once into a temporary folder.
"""
import argparse
import os
import subprocess
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cli"))
from cli_support import run_tests_with_databases  # noqa: E402

ARGS = None


def run_example(name, *args):
    env = dict(os.environ, PYTHONPATH=ARGS.python_dir)
    return subprocess.run(["/usr/bin/python3",
                           os.path.join(ARGS.source_dir, "examples", "python", name),
                           "--db", ARGS.db_dir, *args],
                          capture_output=True, text=True, env=env, timeout=600)


class Examples(unittest.TestCase):
    def test_plan_and_watch_writes_the_page(self):
        page = os.path.join(ARGS.db_dir, "plan.html")
        done = run_example("plan_and_watch.py", "--out", page)
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
        with open(page, encoding="utf-8") as f:
            text = f.read()
        self.assertIn("window.HFTS_PLAN", text)
        self.assertIn("window.HFTS_GLB_BASE64", text)

    def test_grasp_quality_batch(self):
        done = run_example("grasp_quality_batch.py", "--grasps", "2000")
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
        self.assertIn("force closure", done.stdout)

    def test_custom_robot_pick(self):
        done = run_example("custom_robot_pick.py")
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
        self.assertIn("grasp_quality", done.stdout)


def main():
    global ARGS
    parser = argparse.ArgumentParser()
    for option in ("--python-dir", "--preprocess", "--source-dir"):
        parser.add_argument(option, required=True)
    ARGS, rest = parser.parse_known_args()
    ARGS.python_dir = os.path.abspath(ARGS.python_dir)
    ARGS.source_dir = os.path.abspath(ARGS.source_dir)
    run_tests_with_databases(ARGS.preprocess, ARGS.source_dir, ["mug"], rest,
                             lambda folder: setattr(ARGS, "db_dir", folder))


if __name__ == "__main__":
    main()
