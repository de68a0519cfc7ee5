#!/usr/bin/env python3
"""hfts-bench --mbm (docs/motionbenchmaker.md) on the committed sample of
MotionBenchMaker problems (tests/data/mbm: two of each Panda scenario): every
problem solved by the multi-tree planner, OMPL's RRTConnect with FCL alone
beside it, the CSV and the table. Standard library only."""

import csv
import os
import shutil
import sys
import tempfile
import unittest

from cli_support import bench_options, run, sanitizer_slowdown

BINARY = None
SOURCE_DIR = None
SCENARIOS = ["bookshelf_small_panda", "bookshelf_tall_panda", "bookshelf_thin_panda",
             "box_panda", "cage_panda", "table_pick_panda", "table_under_pick_panda"]


class MotionBenchMaker(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-mbm-")
        cls.sample = os.path.join(SOURCE_DIR, "tests", "data", "mbm")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def bench(self, *args):
        return run(BINARY, "--mbm", self.sample, *args, timeout=560)

    def test_every_sample_problem_is_solved_by_both_planners(self):
        out = os.path.join(self.tmp, "mbm.csv")
        limit = 10 * sanitizer_slowdown()
        result = self.bench("--time-limit", limit, "--out", out)
        self.assertEqual(result.returncode, 0, (result.stdout, result.stderr))
        with open(out) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 28)
        self.assertEqual(sorted({r["scenario"] for r in rows}), SCENARIOS)
        self.assertEqual(sorted({r["algorithm"] for r in rows}), ["coupled", "rrtconnect"])
        for r in rows:
            self.assertGreater(float(r["time"]), 0.0)
            self.assertLess(float(r["time"]), limit + 1.0)
            self.assertGreater(int(r["collision_checks"]), 0)
            if r["algorithm"] == "coupled":  # the multi-tree planner solves every one
                self.assertEqual((r["solved"], r["reason"]), ("1", "none"), r)
            if r["solved"] == "1":
                self.assertGreaterEqual(int(r["waypoints"]), 2)
        solved = sum(r["solved"] == "1" for r in rows if r["algorithm"] == "rrtconnect")
        self.assertGreaterEqual(solved, 12, "RRTConnect solves most within the limit")
        table = result.stdout.splitlines()
        self.assertTrue(table[0].startswith("scenario"), result.stdout)
        totals = [line.split() for line in table if line.startswith("all ")]
        self.assertEqual([t[1] for t in totals], ["coupled", "rrtconnect"])
        self.assertEqual([t[2] for t in totals], ["14/14", f"{solved}/14"])

    def test_one_scenario_and_its_first_problem(self):
        out = os.path.join(self.tmp, "one.csv")
        result = self.bench("--scenarios", "cage_panda", "--problems", "1", "--algorithms",
                            "coupled:certify_path=1", "--out", out)
        self.assertEqual(result.returncode, 0, (result.stdout, result.stderr))
        with open(out) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([(r["scenario"], r["problem"], r["algorithm"], r["solved"]) for r in rows],
                         [("cage_panda", "0001", "coupled:certify_path=1", "1")])

    def test_bad_arguments_are_refused(self):
        result = self.bench("--scenarios", "kitchen")
        self.assertEqual(result.returncode, 2)
        self.assertIn("unknown scenario 'kitchen'", result.stderr)
        result = run(BINARY, "--mbm", os.path.join(self.tmp, "missing"))
        self.assertEqual(result.returncode, 2)
        self.assertIn("is not a folder", result.stderr)
        result = self.bench("--algorithms", "decoupled20")
        self.assertEqual(result.returncode, 2)
        self.assertIn("motion goals take coupled, paper or rrtconnect", result.stderr)


if __name__ == "__main__":
    BINARY, _, SOURCE_DIR, rest = bench_options()
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
