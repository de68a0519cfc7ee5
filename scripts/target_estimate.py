#!/usr/bin/python3
"""Issue 43's second target over several seeds: planned-and-held on the
cases where some planner finds a held grasp, per robot and per scene.

  scripts/target_estimate.py [--evidence ROBOT=OLD.csv[,...]] ROBOT=RUN.csv[,RUN.csv...][:REFERENCE_DIR] [...]

Each RUN.csv is one hfts-bench run over the same cases (one seed each;
success = planned and held). A case is solvable when some run held in it,
or the reference run on it did (REFERENCE_DIR: hfts-bench CSVs named
ROBOT.SCENE.OBJECT.PLACEMENT.csv, one reference run each, on a random
sample of the cases every run failed). With S cases solved by some run,
F cases failed by all and k of the n sampled ones solved by the reference,
the solvable cases are estimated as S + F k / n and the rate over them as
H / (R (S + F k / n)), H the held runs and R the runs per case; the Wilson
95 % interval of k / n is carried through (without references: the rate
over the cases some run solved, an upper bound). Only what the runs and
the reference found counts, so the solvable cases are counted from below
and the rate from above. --evidence adds runs of other planners (older
binaries, other settings) that count only as evidence that a case is
solvable: a case one of them held in is solvable, and the references
sample the cases that every run and every evidence run failed; H and R
stay those of the measured runs.
"""
import argparse
import csv
import glob
import os
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_runs import wilson  # noqa: E402  (same directory)


def case_of(r):
    return (r["scene"], r["object"], r.get("placement", "target"))


def read_runs(paths):
    """{case: [held, ...]} over the runs, each case in every run."""
    held = defaultdict(list)
    for path in paths:
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                held[case_of(r)].append(r["success"] == "1")
    counts = {len(v) for v in held.values()}
    if len(counts) != 1:
        sys.exit(f"{paths}: the runs do not cover the same cases")
    return held


def read_references(directory, robot):
    refs = {}
    for path in sorted(glob.glob(os.path.join(directory, f"{robot}.*.csv"))):
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                refs[case_of(r)] = r["success"] == "1"
    return refs


def estimate(held, refs, evidence):
    runs = len(next(iter(held.values())))
    solved = [c for c, v in held.items() if any(v) or any(evidence.get(c, []))]
    failed = [c for c, v in held.items() if not (any(v) or any(evidence.get(c, [])))]
    hits = sum(sum(v) for v in held.values())
    sampled = [c for c in failed if c in refs]
    n, k = len(sampled), sum(refs[c] for c in sampled)
    if n == 0:
        cases = len(solved)
        rate = hits / (runs * cases) if cases else float("nan")
        return f"{len(solved)} | {len(failed)} | - | {rate:.2f} (upper bound)"
    lo, hi = wilson(k, n)
    def rate(p):
        cases = len(solved) + len(failed) * p
        return hits / (runs * cases) if cases else float("nan")
    return (f"{len(solved)} | {len(failed)} | {k}/{n} = {k / n:.2f} [{lo:.2f}, {hi:.2f}] | "
            f"{rate(k / n):.2f} [{rate(hi):.2f}, {rate(lo):.2f}]")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("spec", nargs="+", help="ROBOT=RUN.csv[,RUN.csv...][:REFERENCE_DIR]")
    parser.add_argument("--evidence", action="append", default=[],
                        help="ROBOT=RUN.csv[,...]: runs that only show which cases are solvable")
    args = parser.parse_args()
    evidence = {}
    for spec in args.evidence:
        robot, _, paths = spec.partition("=")
        for case, v in read_runs(paths.split(",")).items():
            evidence.setdefault(robot, {}).setdefault(case, []).extend(v)
    print("| robot | scene | runs planned and held | cases held in some run | cases failed "
          "in every run | reference solved (sampled) | estimated rate over solvable cases |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for spec in args.spec:
        robot, _, rest = spec.partition("=")
        paths, _, ref_dir = rest.partition(":")
        held = read_runs(paths.split(","))
        refs = read_references(ref_dir, robot) if ref_dir else {}
        for scene in [None] + sorted({c[0] for c in held}):
            mine = {c: v for c, v in held.items() if scene is None or c[0] == scene}
            hits = sum(sum(v) for v in mine.values())
            total = sum(len(v) for v in mine.values())
            lo, hi = wilson(hits, total)
            print(f"| {robot} | {scene or 'all'} | {hits}/{total} = {hits / total:.2f} "
                  f"[{lo:.2f}, {hi:.2f}] | {estimate(mine, refs, evidence.get(robot, {}))} |")


if __name__ == "__main__":
    main()
