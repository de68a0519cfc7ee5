#!/usr/bin/python3
"""How close is the planner to issue 43's second target, estimated from a
sample of reference runs?

  scripts/reference_estimate.py ROBOT=RUNS.csv:REFERENCE_DIR [...]

The target: planned-and-held >= 0.90 over the cases where some planner
finds a held grasp within 120 s. RUNS.csv holds the headline runs (one per
case; hfts-bench, success = planned and held). REFERENCE_DIR holds one
hfts-bench CSV per reference run, on a random sample of the cases RUNS.csv
failed. With S successes, F failures and k of n sampled failures solved by
the reference, the cases some planner solves are estimated as
S + F * k / n, and the rate as S / (S + F * k / n), with the Wilson 95 %
interval of k / n carried through (the rate falls as k / n rises). Only
what the reference found counts: another planner might solve more, so the
rate is an upper estimate. Failures the reference could not try at all
(`object_in_collision`: the object intersects an obstacle, no planner can
start) stay in the sample as unsolved.
"""
import argparse
import csv
import glob
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_runs import wilson  # noqa: E402  (same directory)


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("spec", nargs="+", help="ROBOT=RUNS.csv:REFERENCE_DIR")
    args = parser.parse_args()
    print("| robot | planned and held (S / cases) | reference solved (k / n sampled failures) "
          "| estimated rate over solvable cases |")
    print("| --- | --- | --- | --- |")
    for spec in args.spec:
        robot, _, paths = spec.partition("=")
        runs_path, _, ref_dir = paths.partition(":")
        runs = rows(runs_path)
        s = sum(1 for r in runs if r["success"] == "1")
        f = len(runs) - s
        refs = [r for path in sorted(glob.glob(os.path.join(ref_dir, f"{robot}.*.csv")))
                for r in rows(path)]
        n = len(refs)
        if n == 0:
            sys.exit(f"{ref_dir}: no reference runs {robot}.*.csv")
        k = sum(1 for r in refs if r["success"] == "1")
        lo, hi = wilson(k, n)
        rate = lambda p: s / (s + f * p) if s + f * p > 0 else 0.0  # noqa: E731
        print(f"| {robot} | {s}/{len(runs)} | {k}/{n} = {k / n:.2f} [{lo:.2f}, {hi:.2f}] "
              f"| {rate(k / n):.2f} [{rate(hi):.2f}, {rate(lo):.2f}] |")


if __name__ == "__main__":
    main()
