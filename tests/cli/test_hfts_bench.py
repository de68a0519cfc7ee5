#!/usr/bin/env python3
"""End-to-end tests of the hfts-bench command line (docs/benchmarks.md).
Run by ctest with Debian's /usr/bin/python3; standard library only."""

import csv
import json
import os
import re
import shutil
import sys
import tempfile
import unittest

from cli_support import bench_options, build_databases, run, sanitizer_slowdown

BENCH = None
PREPROCESS = None
SOURCE_DIR = None
HEADER = ["scene", "object", "algorithm", "seed", "success", "failure", "time", "gs", "vgs",
          "gns", "epsilon", "path_length", "collision_checks", "cpu_time", "placement",
          "rejected_unstable", "rejected_no_arm_ik", "rejected_out_of_hand_reach",
          "rejected_colliding", "rejected_closing_blocked", "fingertip_error",
          "planned_epsilon", "penetration", "rejected_no_pad_contact",
          "rejected_weak_at_contacts", "planned", "held", "held_fraction", "physics_failure",
          "lift", "dropped_goals", "physics_checks", "physics_time", "rejected_paths",
          "final_check_time", "certificate_queries", "clearance"]
TIME_LIMIT = 10
# The default planner without the physics check: for tests of the program,
# not of whether plans hold (the main series has it).
NO_PHYSICS = "coupled:physics_check=0"


class BenchCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="hfts-bench-")
        cls.db = os.path.join(cls.tmp, "db")
        build_databases(PREPROCESS, SOURCE_DIR, cls.db, ["mug"])
        cls.csv = os.path.join(cls.tmp, "results.csv")
        cls.bench = cls.run_bench("--scenes", "table", "--objects", "mug",
                                  "--algorithms", "coupled,decoupled20", "--runs", 2,
                                  "--time-limit", TIME_LIMIT, "--out", cls.csv)
        with open(cls.csv, newline="") as f:
            cls.rows = list(csv.reader(f))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def run_bench(cls, *args, check=None):
        return run(BENCH, "--db", cls.db, *args, check=check)

    def usage_error(self, *args):
        result = self.run_bench("--no-physics", "--out", os.path.join(self.tmp, "bad.csv"), *args)
        self.assertEqual(result.returncode, 2, (result.stdout, result.stderr))
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "bad.csv")))
        return result.stderr

    def test_place_searches_are_checked_before_any_run(self):
        tasks = os.path.join(SOURCE_DIR, "objects", "pick_and_place", "tasks.json")
        for bad, says in [("sideways", "unknown 'sideways'"),
                          ("coupled:fast=1", "unknown setting 'fast=1'"),
                          ("decoupled:held_speed=2", "held_speed must be a number in (0, 1]"),
                          ("coupled:held_speed=0.5x", "held_speed must be a number in (0, 1]")]:
            self.assertIn(says, self.usage_error("--place", tasks, "--searches", bad))

    def test_benchmark_exits_cleanly_and_leaves_no_temporary_file(self):
        self.assertEqual(self.bench.returncode, 0, self.bench.stderr)
        self.assertFalse(os.path.exists(self.csv + ".tmp"))

    def test_csv_has_one_row_per_run_in_order(self):
        self.assertEqual(self.rows[0], HEADER)
        body = self.rows[1:]
        self.assertEqual([(r[0], r[1], r[2], r[3]) for r in body],
                         [("table", "mug", a, s) for a in ("coupled", "decoupled20")
                          for s in ("1", "2")])
        self.assertTrue(all(len(r) == len(HEADER) for r in body))

    def test_csv_values_are_consistent(self):
        for row in self.rows[1:]:
            r = dict(zip(HEADER, row))
            self.assertIn(r["success"], ("0", "1"))
            self.assertIn(r["planned"], ("0", "1"))
            success, planned = r["success"] == "1", r["planned"] == "1"
            self.assertEqual(r["failure"] == "none", success, r)
            # Success is a plan that holds in physics.
            self.assertEqual(r["failure"] == "not_held", planned and not success, r)
            if planned:
                self.assertIn(r["held"], ("0", "1"), r)
                self.assertEqual(r["held"] == "1", success, r)
                self.assertTrue(0.0 <= float(r["held_fraction"]) <= 1.0, r)
                self.assertNotEqual(r["lift"], "", r)
                self.assertEqual(r["physics_failure"] == "", float(r["held_fraction"]) == 1.0, r)
            else:
                self.assertEqual((r["held"], r["held_fraction"], r["lift"]), ("", "", ""), r)
            # The planner stops within 0.1 s of its limit (slower under a sanitizer).
            self.assertLessEqual(float(r["time"]), TIME_LIMIT + 0.1 * sanitizer_slowdown(), r)
            self.assertGreater(float(r["time"]), 0.0)
            gs, vgs, gns = int(r["gs"]), int(r["vgs"]), int(r["gns"])
            self.assertLessEqual(vgs, gs)
            self.assertGreaterEqual(gns, 0)
            self.assertGreater(int(r["collision_checks"]), 0)
            self.assertGreater(float(r["cpu_time"]), 0.0)
            # A goal is dropped only after a simulation of its hand closure
            # failed, and simulations take time.
            dropped, checks = int(r["dropped_goals"]), int(r["physics_checks"])
            self.assertGreaterEqual(dropped, 0, r)
            self.assertGreaterEqual(checks, 1 if dropped > 0 else 0, r)
            self.assertEqual(float(r["physics_time"]) > 0.0, checks > 0, r)
            self.assertLessEqual(float(r["physics_time"]), float(r["time"]) + 0.5, r)
            if planned:
                self.assertGreaterEqual(float(r["epsilon"]), 0.0)
                self.assertGreater(float(r["path_length"]), 0.0)
                self.assertLessEqual(float(r["penetration"]), 0.001 + 1e-12)
                self.assertGreaterEqual(vgs, 1)
            else:
                self.assertEqual((r["epsilon"], r["path_length"]), ("", ""))

    def test_progress_is_one_line_per_run_when_stderr_is_not_a_terminal(self):
        lines = [l for l in self.bench.stderr.splitlines() if l.startswith("[")]
        self.assertEqual(len(lines), 4, self.bench.stderr)
        self.assertRegex(lines[0], r"^\[1/4\] table mug coupled seed 1: "
                                   r"(success|failure \w+) [\d.]+ s"
                                   r"( \(held in [\d.]+ of the trials\))?$")
        self.assertTrue(lines[3].startswith("[4/4] table mug decoupled20 seed 2: "))

    def test_summary_matches_the_csv(self):
        out = self.bench.stdout
        self.assertIn("algorithm", out)
        self.assertIn("VGS/GS", out)
        self.assertIn("4 runs written to", out)
        for algorithm in ("coupled", "decoupled20"):
            rows = [r for r in self.rows[1:] if r[2] == algorithm]
            rate = 100.0 * sum(r[4] == "1" for r in rows) / len(rows)
            mean = sum(float(r[6]) for r in rows) / len(rows)
            planned = 100.0 * sum(dict(zip(HEADER, r))["planned"] == "1" for r in rows) / len(rows)
            match = re.search(rf"^{algorithm}\s+(\d+)\s+([\d.]+)%\s+([\d.]+)%\s+([\d.]+)\s+",
                              out, re.M)
            self.assertIsNotNone(match, out)
            self.assertEqual(int(match.group(1)), 2)
            self.assertAlmostEqual(float(match.group(2)), rate, places=1)
            self.assertAlmostEqual(float(match.group(3)), planned, places=1)
            self.assertAlmostEqual(float(match.group(4)), mean, delta=0.001)

    def test_unknown_scene_is_a_usage_error_naming_the_valid_ones(self):
        scenes = sorted(f[:-5] for f in os.listdir(os.path.join(SOURCE_DIR, "objects", "scenes"))
                        if f.endswith(".json"))
        self.assertIn("table", scenes)
        err = self.usage_error("--scenes", "table,kitchen")
        self.assertIn(f"unknown scene 'kitchen' (valid: {', '.join(scenes)})", err)

    def test_unknown_placement_is_a_usage_error_naming_the_scenes_ones(self):
        err = self.usage_error("--scenes", "table", "--placements", "upside_down")
        self.assertIn("--placements: in scene 'table': unknown placement 'upside_down' "
                      "(valid: target", err)

    def test_algorithms_with_planner_parameters(self):
        err = self.usage_error("--algorithms", "coupled:mask_contacts")
        self.assertIn("'mask_contacts' is not a planner parameter setting name=value", err)
        err = self.usage_error("--algorithms", "coupled:warp=9")
        self.assertIn("algorithm 'coupled:warp=9': unknown planner parameter 'warp'", err)
        err = self.usage_error("--algorithms", "coupled:p_max=1:p_max=0")
        self.assertIn("sets 'p_max' twice", err)
        err = self.usage_error("--algorithms", "decoupled20:preset=fast")
        self.assertIn("algorithm 'decoupled20:preset=fast': the only preset is paper, got 'fast'", err)
        err = self.usage_error("--algorithms", "coupled:lift=up")
        self.assertIn("algorithm 'coupled:lift=up': lift must be a height in [0, 1] m", err)
        err = self.usage_error("--algorithms", "coupled:lift=0:lift=0.1")
        self.assertIn("sets 'lift' twice", err)
        csv_path = os.path.join(self.tmp, "variants.csv")
        result = self.run_bench("--no-physics", "--out", csv_path, "--scenes", "table", "--runs", "1",
                                "--time-limit", "5",
                                "--algorithms",
                                "coupled:smoothing_steps=0:physics_check=0,coupled:physics_check=0")
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(csv_path) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([r["algorithm"] for r in rows],
                         ["coupled:smoothing_steps=0:physics_check=0", "coupled:physics_check=0"])
        unsmoothed = rows[0]
        self.assertEqual(unsmoothed["success"], "1")

    def test_unknown_algorithm_is_a_usage_error(self):
        err = self.usage_error("--algorithms", "coupled,decoupledX")
        self.assertIn("unknown algorithm 'decoupledX'", err)
        self.assertIn("decoupled20", err)
        self.assertIn("rrtconnect", err)
        self.assertIn("unknown algorithm 'decoupled0'", self.usage_error("--algorithms", "decoupled0"))

    def test_bad_runs_and_time_limits_are_usage_errors(self):
        self.assertIn("--runs must be at least 1, got 0", self.usage_error("--runs", "0"))
        self.assertIn("--time-limit must be a positive number", self.usage_error("--time-limit", "-1"))
        self.assertIn("--time-limit", self.usage_error("--time-limit", "soon"))
        result = run(BENCH, "--db", self.db)
        self.assertEqual(result.returncode, 2)
        self.assertIn("--out", result.stderr)

    def test_first_seed_continues_a_series(self):
        # Without the physics check, whose seconds per goal would let a
        # loaded machine's time limit decide.
        def series(name, *args):
            path = os.path.join(self.tmp, name)
            result = self.run_bench("--no-physics", "--out", path, "--scenes", "table", "--objects",
                                    "mug", "--algorithms", NO_PHYSICS, "--time-limit", TIME_LIMIT,
                                    *args)
            self.assertEqual(result.returncode, 0, result.stderr)
            with open(path, newline="") as f:
                return list(csv.DictReader(f))
        [row] = series("seed2.csv", "--runs", "1", "--first-seed", "2")
        [same] = [r for r in series("seeds12.csv", "--runs", "2") if r["seed"] == "2"]
        self.assertEqual(row["seed"], "2")
        for column in ("success", "gs", "vgs", "gns", "path_length", "epsilon"):
            self.assertEqual(row[column], same[column], column)  # the same run as in the series
        self.assertIn("--first-seed", self.usage_error("--first-seed", "-1"))

    def test_unknown_object_is_a_usage_error_naming_the_databases(self):
        err = self.usage_error("--scenes", "table", "--objects", "teapot")
        self.assertIn("unknown object 'teapot' (valid: mug)", err)

    def test_scene_target_without_database_is_a_runtime_error(self):
        with open(os.path.join(SOURCE_DIR, "objects", "scenes", "bin.json")) as f:
            target = json.load(f)["target"]["object"]
        self.assertNotEqual(target, "mug")
        result = self.run_bench("--no-physics", "--scenes", "bin", "--out", os.path.join(self.tmp, "bin.csv"))
        self.assertEqual(result.returncode, 1)
        self.assertIn(f"scene 'bin' targets '{target}', which has no database", result.stderr)

    def test_holdable_only_leaves_out_what_the_robot_cannot_hold(self):
        # The table scene, and a copy with the mug 3 m away (no obstacles):
        # beyond the fingertips' reach, decided before any search.
        scenes = os.path.join(self.tmp, "scenes")
        os.makedirs(scenes, exist_ok=True)
        with open(os.path.join(SOURCE_DIR, "objects", "scenes", "table.json")) as f:
            table = json.load(f)
        far = dict(table, name="far", obstacles=[], placements=[])
        far["target"] = {"object": "mug",
                         "pose": {"position": [3.0, 0, 0.5], "orientation": [0, 0, 0, 1]}}
        for name, scene in (("table", table), ("far", far)):
            with open(os.path.join(scenes, name + ".json"), "w") as f:
                json.dump(scene, f)
        out = os.path.join(self.tmp, "held.csv")
        holdability = os.path.join(self.tmp, "holdability.csv")
        result = self.run_bench("--no-physics", "--scene-dir", scenes, "--scenes", "far,table", "--algorithms",
                                NO_PHYSICS, "--runs", "1", "--time-limit", TIME_LIMIT,
                                "--holdable-only", "--holdability", holdability, "--out", out)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(holdability, newline="") as f:
            decided = {r["scene"]: r for r in csv.DictReader(f)}
        self.assertEqual(decided["table"]["holdable"], "1")
        self.assertGreater(float(decided["table"]["epsilon"]), 0)
        self.assertEqual(decided["table"]["reason"], "")
        self.assertEqual(decided["far"]["holdable"], "0")
        self.assertEqual(decided["far"]["climbs"], "0")
        self.assertIn("the object is out of reach", decided["far"]["reason"])
        self.assertIn("left out far/mug: the object is out of reach", result.stderr)
        self.assertIn("1 of 2 cases left out", result.stderr)
        with open(out, newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([(r["scene"], r["object"]) for r in rows], [("table", "mug")])
        # The file read back gives the same cases without deciding again.
        again = os.path.join(self.tmp, "held-again.csv")
        result = self.run_bench("--no-physics", "--scene-dir", scenes, "--scenes", "far,table", "--algorithms",
                                NO_PHYSICS, "--runs", "1", "--time-limit", TIME_LIMIT,
                                "--holdable-from", holdability, "--out", again)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn(f"left out far/mug: not holdable in {holdability}", result.stderr)
        with open(again, newline="") as f:
            self.assertEqual([(r["scene"], r["object"]) for r in csv.DictReader(f)],
                             [("table", "mug")])

    def test_holdability_alone_plans_every_case(self):
        # Without --holdable-only the answers are written and nothing is
        # left out: the mug 3 m away is planned too (and fails).
        scenes = os.path.join(self.tmp, "far-only")
        os.makedirs(scenes, exist_ok=True)
        with open(os.path.join(SOURCE_DIR, "objects", "scenes", "table.json")) as f:
            far = dict(json.load(f), name="far", obstacles=[], placements=[])
        far["target"] = {"object": "mug",
                         "pose": {"position": [3.0, 0, 0.5], "orientation": [0, 0, 0, 1]}}
        with open(os.path.join(scenes, "far.json"), "w") as f:
            json.dump(far, f)
        out = os.path.join(self.tmp, "all.csv")
        holdability = os.path.join(self.tmp, "holdability-alone.csv")
        result = self.run_bench("--no-physics", "--scene-dir", scenes, "--scenes", "far", "--algorithms",
                                "coupled", "--runs", "1", "--time-limit", "1",
                                "--holdability", holdability, "--out", out)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(holdability, newline="") as f:
            decided = list(csv.DictReader(f))
        self.assertEqual([(r["scene"], r["holdable"]) for r in decided], [("far", "0")])
        self.assertNotIn("left out", result.stderr)
        with open(out, newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([(r["scene"], r["object"], r["success"]) for r in rows],
                         [("far", "mug", "0")])

    def write_holdability(self, name, text):
        path = os.path.join(self.tmp, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_holdable_from_plans_only_what_the_file_holds(self):
        answers = self.write_holdability(
            "answers.csv",
            "scene,object,placement,holdable,climbs,leaves,stable,reached,hand_clear,epsilon,"
            "seconds,reason\n"
            "table,mug,target,1,3,100,20,5,2,0.05,1.0,\n"
            'shelf,mug,target,0,9,900,80,9,0,0,9.0,"no grasp, ""really"", in 9 climbs"\n'
            .replace("\n", "\r\n"))
        out = os.path.join(self.tmp, "from-file.csv")
        result = self.run_bench("--no-physics", "--scenes", "table,shelf", "--objects", "mug", "--algorithms",
                                NO_PHYSICS, "--runs", "1", "--time-limit", TIME_LIMIT,
                                "--holdable-from", answers, "--out", out)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn(f"left out shelf/mug: not holdable in {answers}", result.stderr)
        self.assertIn("1 of 2 cases left out", result.stderr)
        with open(out, newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([(r["scene"], r["object"]) for r in rows], [("table", "mug")])

    def test_a_bad_holdability_file_is_named_before_any_run(self):
        header = "scene,object,placement,holdable\n"
        cases = {
            "no answer for shelf/mug at target": header + "table,mug,target,1\n",
            "line 3: holdable is 'yes', not 0 or 1": header + "table,mug,target,1\n"
                                                      "shelf,mug,target,yes\n",
            "line 2: 3 fields, the columns need at least 4": header + "table,mug,target\n",
            "line 2: text follows a closing quote in field 2": header + 'table,"mug"x,target,1\n',
            "line 1: a quote is not closed": 'scene,"object,placement,holdable\n',
            "line 3: table/mug at target is answered twice": header + "table,mug,target,1\n"
                                                              "table,mug,target,0\n",
            "line 2: a quote is not closed": header + 'table,"mug,target,1\n',
            "no 'holdable' column": "scene,object,placement\ntable,mug,target\n",
        }
        for i, (message, text) in enumerate(cases.items()):
            path = self.write_holdability(f"bad{i}.csv", text)
            out = os.path.join(self.tmp, f"bad{i}-runs.csv")
            result = self.run_bench("--no-physics", "--scenes", "table,shelf", "--objects", "mug",
                                    "--holdable-from", path, "--out", out)
            self.assertEqual(result.returncode, 1, (message, result.stderr))
            self.assertIn(f"holdability file '{path}'", result.stderr)
            self.assertIn(message, result.stderr)
            self.assertNotIn("[1/", result.stderr)
            self.assertFalse(os.path.exists(out), message)
        missing = os.path.join(self.tmp, "no-such-answers.csv")
        result = self.run_bench("--no-physics", "--scenes", "table", "--objects", "mug",
                                "--holdable-from", missing, "--out", out)
        self.assertEqual(result.returncode, 1, result.stderr)
        self.assertIn(f"holdability file '{missing}': cannot be read", result.stderr)
        self.assertIn("--holdability", self.usage_error("--holdable-from", missing,
                                                        "--holdability", missing))

    def test_unwritable_output_fails_before_planning(self):
        out = os.path.join(self.tmp, "no-such-dir", "results.csv")
        result = self.run_bench("--no-physics", "--scenes", "table", "--out", out)
        self.assertEqual(result.returncode, 1)
        self.assertIn("cannot write", result.stderr)
        self.assertNotIn("[1/", result.stderr)


if __name__ == "__main__":
    BENCH, PREPROCESS, SOURCE_DIR, rest = bench_options()
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)
