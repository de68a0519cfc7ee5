#!/usr/bin/python3
"""Do the plans hold? A summary of hfts-bench CSVs written with physics
(docs/benchmarks.md, docs/experiments/2026-11-27-physics-check.md).

  scripts/held_summary.py LABEL=RUNS.csv [LABEL=RUNS.csv ...] [--by scene|algorithm]

One row per CSV (or per CSV and scene, or per CSV and algorithm, with
--by; with --by algorithm, also the paired wins: cases that one
algorithm planned and held and the other did not), every run in the
denominator: planned-and-held (hfts-bench's success), planned, held among
the plans, each with a Wilson 95 % interval; the mean held fraction of the
plans' physics trials; the median and largest fingertip penetration of the
plans (mm); and why plans did not hold: the physics trials, or the check of
the grasp as executed (the hand closed again from the pre-grasp) while the
physics held.
"""
import argparse
import csv
import os
import statistics
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_runs import wilson  # noqa: E402  (same directory)


def rate(k, n):
    lo, hi = wilson(k, n)
    return f"{k}/{n} = {k / n:.2f} [{lo:.2f}, {hi:.2f}]" if n else "0/0"


def summarise(label, runs):
    yes = lambda r, column: r[column] in ("1", "true", "True")
    plans = [r for r in runs if yes(r, "planned")]
    held = [r for r in plans if yes(r, "held")]
    fractions = [float(r["held_fraction"]) for r in plans if r["held_fraction"]]
    depth = [1000 * float(r["penetration"]) for r in plans if r["penetration"]]
    not_held = [r for r in plans if not yes(r, "held")]
    physics = sum(1 for r in not_held if r["held_fraction"] and
                  float(r["held_fraction"]) < 6 / 7 - 1e-9)
    fraction = f"{statistics.mean(fractions):.3f}" if fractions else "-"
    median = f"{statistics.median(depth):.2f} / {max(depth):.2f}" if depth else "-"
    return (f"| {label} | {rate(sum(1 for r in runs if yes(r, 'success')), len(runs))} "
            f"| {rate(len(plans), len(runs))} | {rate(len(held), len(plans))} | {fraction} "
            f"| {median} | {physics} / {len(not_held) - physics} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", nargs="+", help="LABEL=FILE")
    parser.add_argument("--by", choices=["scene", "algorithm"],
                        help="one row per scene as well, or one per algorithm instead")
    args = parser.parse_args()
    print("| runs | planned and held | planned | held among plans | mean held fraction "
          "| penetration median / max mm | not held: physics / grasp check |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    wins = []
    for item in args.csv:
        label, _, name = item.rpartition("=")
        if not label:
            label = os.path.basename(name)
        with open(name, newline="") as f:
            runs = list(csv.DictReader(f))
        if not runs:
            sys.exit(f"{name}: no runs")
        if args.by == "algorithm":
            by_algorithm = defaultdict(list)
            for r in runs:
                by_algorithm[r["algorithm"]].append(r)
            for algorithm, rows in by_algorithm.items():
                print(summarise(f"{label} {algorithm}", rows))
            wins.append((label, by_algorithm))
            continue
        print(summarise(label, runs))
        if args.by == "scene":
            scenes = defaultdict(list)
            for r in runs:
                scenes[r["scene"]].append(r)
            for scene, rows in sorted(scenes.items()):
                print(summarise(f"{label}, {scene}", rows))

    for label, by_algorithm in wins:
        print_wins(label, by_algorithm)


def print_wins(label, by_algorithm):
    """Paired: the cases (scene, object, placement, seed) each algorithm
    planned and held where another did not."""
    def case(r):
        return r["scene"], r["object"], r.get("placement", "target"), r["seed"]
    held = {a: {case(r) for r in rows if r["success"] in ("1", "true", "True")}
            for a, rows in by_algorithm.items()}
    names = list(held)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            print(f"{label}: {a} only {len(held[a] - held[b])}, {b} only {len(held[b] - held[a])}")


if __name__ == "__main__":
    main()
