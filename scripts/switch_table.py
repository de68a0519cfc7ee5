#!/usr/bin/python3
"""What each beyond-paper switch buys: hfts-bench CSVs in which every case
ran the default planner (`coupled`) and the default with one setting
changed (`coupled:NAME=VALUE`), side by side (docs/planning.md, issue 44).

  scripts/switch_table.py LABEL=RUNS.csv [LABEL=RUNS.csv ...]

One row per CSV and changed setting: planned-and-held (hfts-bench's
success) of the default and of the change over the same cases, with
Wilson 95 % intervals; the paired cases only one of them planned and
held; the two-sided exact sign test's p-value on those; and, over the
cases both planned and held, the median of the change's planning time
over the default's. Every case is in every denominator.

Then one row per addition, summed over the CSVs: the cases the planner
with the addition planned and held and without it did not (its wins) and
the reverse (its losses). A change to the paper's value (PAPER, as
planner::paperSettings() has it) turns the addition off, any other turns
it on. The addition stays when its wins exceed its losses (the decision
rule of docs/experiments/2026-12-05-switches.md).
"""
import argparse
import os
import statistics
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_runs import read_runs, sign_test, wilson  # noqa: E402  (same directory)

DEFAULT = "coupled"
# Each addition's value that turns it off, as planner::paperSettings() had
# them for the runs analysed (before 2026-12-05, when four were deleted).
PAPER = {"retreat": "0", "p_local": "0", "stable_nodes": "0", "other_postures": "0",
         "hand_clearance": "0", "palm_turns": "1", "mask_contacts": "0",
         "unstable_by_reach": "0", "fit_check": "0", "fit_clearance": "0"}


def rate(k, n):
    lo, hi = wilson(k, n)
    return f"{k}/{n} = {k / n:.2f} [{lo:.2f}, {hi:.2f}]" if n else "0/0"


def case(r):
    return r["scene"], r["object"], r.get("placement", "target"), r["seed"]


def held(r):
    return r["success"] in ("1", "true", "True")


def rows_of(label, runs, tally):
    by_algorithm = defaultdict(dict)
    for r in runs:
        by_algorithm[r["algorithm"]][case(r)] = r
    if DEFAULT not in by_algorithm:
        sys.exit(f"{label}: no '{DEFAULT}' runs to compare with")
    base = by_algorithm[DEFAULT]
    out = []
    for algorithm, changed in by_algorithm.items():
        if algorithm == DEFAULT:
            continue
        cases = sorted(set(base) & set(changed))
        if len(cases) != len(base):
            print(f"{label} {algorithm}: {len(cases)} of the default's {len(base)} cases",
                  file=sys.stderr)
        a = [c for c in cases if held(base[c])]
        b = [c for c in cases if held(changed[c])]
        only_default = len(set(a) - set(b))
        only_changed = len(set(b) - set(a))
        both = set(a) & set(b)
        ratios = [float(changed[c]["time"]) / float(base[c]["time"]) for c in both
                  if float(base[c]["time"]) > 0]
        ratio = f"{statistics.median(ratios):.2f}" if ratios else "-"
        setting = algorithm.partition(":")[2]
        name, _, value = setting.partition("=")
        if name in PAPER:
            off = float(value) == float(PAPER[name])
            wins, losses = (only_default, only_changed) if off else (only_changed, only_default)
            tally[name][0] += wins
            tally[name][1] += losses
            tally[name][2].append(f"{label} {wins}/{losses}")
        out.append(f"| {label} | `{setting}` | {rate(len(a), len(cases))} "
                   f"| {rate(len(b), len(cases))} | {only_default} | {only_changed} "
                   f"| {sign_test(only_default, only_changed):.2f} | {ratio} |")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", nargs="+", help="LABEL=FILE")
    args = parser.parse_args()
    print("| runs | changed setting | default: planned and held | changed: planned and held "
          "| only the default | only the change | sign test p | time, changed / default "
          "(median, both held) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    tally = defaultdict(lambda: [0, 0, []])
    for item in args.csv:
        label, _, name = item.rpartition("=")
        runs = read_runs(name)
        if not runs:
            sys.exit(f"{name}: no runs")
        for row in rows_of(label or os.path.basename(name), runs, tally):
            print(row)
    print()
    print("| addition | per robot (wins/losses) | its wins | its losses | sign test p | decision |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, (wins, losses, labels) in tally.items():
        decision = "stays" if wins > losses else "deleted"
        print(f"| `{name}` | {', '.join(labels)} | {wins} | {losses} "
              f"| {sign_test(wins, losses):.2f} | {decision} |")


if __name__ == "__main__":
    main()
