#!/usr/bin/env python3
"""End-to-end test of hfts-bench's experiment mode (docs/benchmarks.md):
`--experiment paper --quick` runs, then its CSV, its OMPL benchmark logs
(read the way OMPL's ompl_benchmark_statistics.py reads them) and its
plots. Run by ctest with Debian's /usr/bin/python3; standard library only."""

import csv
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest
import zlib

from cli_support import bench_options, build_databases, run

BENCH = None
PREPROCESS = None
SOURCE_DIR = None
# The paper's planner (every addition beyond the paper off), and its decoupled baseline.
PAPER = "paper"
ALGORITHMS = [PAPER, "decoupled20:preset=paper", "decoupled60:preset=paper",
              "decoupled100:preset=paper",
              "rrtconnect"]
CASES = [("table", "mug"), ("bin", "blob")]
RUNS = 2
TIME_LIMIT = 2.0
FIGURES = ["fig7_success_vs_time.png", "fig7_success_by_case.png", "fig8_nodes_explored.png",
           "fig9_valid_goal_ratio.png", "grasp_quality.png"]
RUN_PROPERTIES = ["collision checks INTEGER", "cpu time REAL", "goal sampling calls INTEGER",
                  "grasp epsilon REAL", "hfts nodes explored INTEGER", "seed INTEGER",
                  "solution length REAL", "solved BOOLEAN", "status ENUM", "time REAL",
                  "valid goal samples INTEGER"]


class LogReader:
    """Line reader that fails with the line number and what was expected."""

    def __init__(self, path):
        with open(path) as f:
            self.lines = f.read().split("\n")
        self.at = 0

    def next(self):
        self.at += 1
        return self.lines[self.at - 1]

    def expect(self, test, pattern_words, index=0):
        """Next line's tokens; `pattern_words` maps token positions to required words."""
        line = self.next()
        tokens = line.split()
        for position, word in pattern_words.items():
            test.assertTrue(-len(tokens) <= position < len(tokens) and tokens[position] == word,
                            f"line {self.at}: expected {word!r} at {position} in {line!r}")
        return tokens

    def block(self, test):
        test.assertEqual(self.next(), "<<<|", f"line {self.at}")
        text = []
        while not self.lines[self.at].startswith("|>>>"):
            text.append(self.next())
        self.next()
        return "\n".join(text)


def png_facts(path):
    """Width, height and how many distinct byte values the decompressed image data holds."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    width, height = struct.unpack(">II", data[16:24])
    idat, at = b"", 8
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        if kind == b"IDAT":
            idat += data[at + 8:at + 8 + length]
        at += 12 + length
    return width, height, len(set(zlib.decompress(idat)))


class BenchExperiment(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-bench-experiment-")
        cls.db = os.path.join(cls.tmp, "db")
        build_databases(PREPROCESS, SOURCE_DIR, cls.db, ["mug", "blob"])
        cls.out = os.path.join(cls.tmp, "quick")
        cls.result = run(BENCH, "--db", cls.db, "--experiment", "paper", "--quick",
                         "--out-dir", cls.out)
        with open(os.path.join(cls.out, "results.csv"), newline="") as f:
            cls.rows = list(csv.DictReader(f))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_runs_the_quick_design_and_says_where_the_results_are(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        self.assertIn("20 runs, at most 0.7 minutes if every run hits the time limit",
                      self.result.stderr)
        self.assertIn(f"20 runs written to {os.path.join(self.out, 'results.csv')}",
                      self.result.stdout)
        self.assertIn(f"plots and summary.md written to {self.out}", self.result.stdout)

    def test_csv_holds_every_case_algorithm_and_seed_in_order(self):
        self.assertEqual([(r["scene"], r["object"], r["algorithm"], r["seed"]) for r in self.rows],
                         [(s, o, a, str(seed)) for s, o in CASES for a in ALGORITHMS
                          for seed in range(1, RUNS + 1)])
        for r in self.rows:
            self.assertEqual(r["failure"] == "none", r["success"] == "1", r)
            self.assertLess(float(r["time"]), TIME_LIMIT + 1.0, r)
            self.assertGreater(float(r["cpu_time"]), 0.0, r)
            self.assertLessEqual(int(r["vgs"]), int(r["gs"]), r)

    def test_each_case_has_an_ompl_benchmark_log_that_the_statistics_script_can_read(self):
        for scene, obj in CASES:
            with self.subTest(case=(scene, obj)):
                self.check_log(os.path.join(self.out, "ompl", f"{scene}_{obj}.log"), scene, obj)

    def check_log(self, path, scene, obj):
        # The order and wording ompl_benchmark_statistics.py (OMPL 1.5) expects.
        log = LogReader(path)
        self.assertRegex(log.expect(self, {0: "OMPL", 1: "version"})[-1], r"^\d+\.\d+\.\d+$")
        self.assertEqual(log.expect(self, {0: "Experiment"})[-1], f"{scene}_{obj}")
        self.assertEqual(log.expect(self, {-2: "experiment", -1: "properties"})[0], "2")
        self.assertEqual({log.next(), log.next()}, {f"object TEXT = {obj}", f"scene TEXT = {scene}"})
        log.expect(self, {0: "Running", 1: "on"})
        log.expect(self, {0: "Starting", 1: "at"})
        self.assertIn(f"scene {scene}, object {obj}", log.block(self))
        self.assertIn("CPU", log.block(self))
        int(log.expect(self, {-2: "random", -1: "seed"})[0])
        self.assertEqual(float(log.expect(self, {-3: "seconds", -2: "per", -1: "run"})[0]),
                         TIME_LIMIT)
        float(log.expect(self, {-3: "MB", -2: "per", -1: "run"})[0])
        self.assertEqual(log.expect(self, {-3: "runs", -2: "per", -1: "planner"})[0], str(RUNS))
        float(log.expect(self, {-3: "collect", -2: "the", -1: "data"})[0])
        self.assertEqual(log.expect(self, {-2: "enum", -1: "type"})[0], "1")
        self.assertTrue(log.next().startswith("status|"))
        self.assertEqual(log.expect(self, {-1: "planners"})[0], str(len(ALGORITHMS)))
        for algorithm in ALGORITHMS:
            self.check_planner(log, algorithm, scene, obj)
        self.assertEqual(log.lines[log.at:], [""])

    def check_planner(self, log, algorithm, scene, obj):
        self.assertEqual(log.next(), algorithm)
        for _ in range(int(log.expect(self, {-2: "common", -1: "properties"})[0])):
            log.next()
        count = int(log.expect(self, {1: "properties", 2: "for", 3: "each", 4: "run"})[0])
        names = [log.next() for _ in range(count)]
        self.assertEqual(names, RUN_PROPERTIES)
        self.assertEqual(log.expect(self, {-1: "runs"})[0], str(RUNS))
        rows = [r for r in self.rows
                if (r["scene"], r["object"], r["algorithm"]) == (scene, obj, algorithm)]
        for row in rows:
            line = log.next()
            self.assertTrue(line.endswith("; "), line)
            values = dict(zip(names, line.split("; ")[:-1]))
            self.assertEqual(len(values), count, line)
            for name, value in values.items():
                if value:
                    float(value)
                else:
                    self.assertIn(name, ("grasp epsilon REAL", "solution length REAL"))
            self.assertEqual(values["solved BOOLEAN"], row["success"])
            self.assertEqual(values["seed INTEGER"], row["seed"])
            self.assertAlmostEqual(float(values["time REAL"]), float(row["time"]), places=5)
            self.assertEqual(values["goal sampling calls INTEGER"], row["gs"])
            # OMPL's PlannerStatus: EXACT_SOLUTION 6, APPROXIMATE_SOLUTION 5,
            # TIMEOUT 4, INVALID_GOAL 2.
            status = {"none": "6", "not_held": "5", "time_limit": "4", "no_valid_goal": "4",
                      "no_stable_grasp_clear_of_support": "2"}
            self.assertEqual(values["status ENUM"], status[row["failure"]], row)
        self.assertEqual(log.next(), ".")

    def test_plots_are_real_pictures(self):
        for name in FIGURES:
            with self.subTest(figure=name):
                path = os.path.join(self.out, name)
                self.assertGreater(os.path.getsize(path), 20000)
                width, height, values = png_facts(path)
                self.assertGreaterEqual(width, 800)
                self.assertGreaterEqual(height, 400)
                self.assertGreater(values, 100)  # drawn, not a blank canvas

    def test_summary_has_a_row_per_algorithm(self):
        with open(os.path.join(self.out, "summary.md")) as f:
            summary = f.read()
        for algorithm in ALGORITHMS:
            self.assertRegex(summary, rf"\n\| {algorithm} \| {RUNS * len(CASES)} \| \d+/")
        self.assertIn("| table / mug |", summary)

    def test_given_options_override_the_design_and_a_failed_plot_keeps_the_results(self):
        out = os.path.join(self.tmp, "override")
        result = run(BENCH, "--db", self.db, "--experiment", "paper", "--quick", "--out-dir", out,
                     "--scenes", "bin", "--algorithms", "coupled", "--runs", 1,
                     "--python", os.path.join(self.tmp, "no-such-python"))
        self.assertEqual(result.returncode, 1, result.stderr)
        self.assertIn("the plots failed", result.stderr)
        with open(os.path.join(out, "results.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([(r["scene"], r["object"], r["algorithm"]) for r in rows],
                         [("bin", "blob", "coupled")])
        self.assertTrue(os.path.exists(os.path.join(out, "ompl", "bin_blob.log")))

    def test_plot_script_draws_failures_single_runs_and_no_goal_calls(self):
        rows = [["scene", "object", "algorithm", "seed", "success", "failure", "time", "gs",
                 "vgs", "gns", "epsilon", "path_length", "collision_checks", "cpu_time"],
                ["table", "mug", "coupled", "1", "1", "none", "0.5", "3", "1", "9", "0.05", "2.0",
                 "100", "0.5"],
                ["table", "mug", "decoupled20", "1", "0", "time_limit", "2.0", "0", "0", "0", "",
                 "", "50", "2.0"],
                ["table", "mug", "decoupled20", "2", "0", "time_limit", "2.1", "4", "0", "12", "",
                 "", "60", "2.1"]]
        out = os.path.join(self.tmp, "edge")
        os.makedirs(out)
        with open(os.path.join(out, "results.csv"), "w", newline="") as f:
            csv.writer(f).writerows(rows)
        result = subprocess.run([sys.executable, os.path.join(SOURCE_DIR, "bench", "plot_results.py"),
                                 os.path.join(out, "results.csv"), "--out-dir", out],
                                capture_output=True, text=True, timeout=120)
        self.assertEqual(result.returncode, 0, result.stderr)
        for name in FIGURES + ["summary.md"]:
            self.assertTrue(os.path.exists(os.path.join(out, name)), name)
        with open(os.path.join(out, "summary.md")) as f:
            summary = f.read()
        self.assertIn("| decoupled20 | 2 | 0/2 = 0.00 [0.00, 0.66] |", summary)
        self.assertIn("| algorithm | time_limit |\n| --- | --- |\n| coupled | 0 |\n"
                      "| decoupled20 | 2 |", summary)

    def test_zoo_plans_every_object_of_the_databases_at_every_placement(self):
        out = os.path.join(self.tmp, "zoo")
        result = run(BENCH, "--db", self.db, "--experiment", "zoo", "--out-dir", out,
                     "--scenes", "table", "--time-limit", "0.2", "--no-plots")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(os.path.join(out, "results.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        # Every database (blob, mug) at the table's three placements, coupled
        # (as in the paper and as it plans by default) against decoupled20,
        # one run each.
        algorithms = [PAPER, "coupled", "decoupled20:preset=paper"]
        self.assertEqual([(r["placement"], r["object"], r["algorithm"]) for r in rows],
                         [(p, o, a) for p in ["target", "lying", "turned_near_box"]
                          for o in ["blob", "mug"] for a in algorithms])
        self.assertTrue(os.path.exists(os.path.join(out, "ompl", "table_mug_lying.log")))

    def test_experiment_usage_errors(self):
        def usage_error(*args):
            result = run(BENCH, "--db", self.db, *args)
            self.assertEqual(result.returncode, 2, (result.stdout, result.stderr))
            return result.stderr

        out = os.path.join(self.tmp, "bad")
        self.assertIn("unknown experiment 'icra' (valid: paper, zoo)",
                      usage_error("--experiment", "icra", "--out-dir", out))
        self.assertIn("--out-dir", usage_error("--experiment", "paper"))
        self.assertIn("--out", usage_error("--experiment", "paper", "--out-dir", out,
                                           "--out", os.path.join(out, "x.csv")))
        self.assertIn("--quick", usage_error("--quick", "--out", os.path.join(out, "x.csv")))
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    BENCH, PREPROCESS, SOURCE_DIR, rest = bench_options()
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
