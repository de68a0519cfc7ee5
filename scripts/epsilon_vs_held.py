#!/usr/bin/python3
"""Does a plan's epsilon where the pads touch predict that its grasp holds
in physics? Reads hfts-bench CSVs of runs planned *without* the physics
check (so that plans that did not hold are in them) and prints, per CSV and
pooled: the plans, the area under the ROC curve of epsilon as a predictor of
`held` (0.5: no better than chance), the held rate below and above an
epsilon, and the smallest epsilon of a plan that held
(docs/planning.md#what-a-goal-is).

  scripts/epsilon_vs_held.py RUNS.csv [RUNS.csv ...] [--split 0.02]
"""
import argparse
import csv
import os


def auc(values, held):
    """Area under the ROC curve of `values` as a predictor of `held` (ties
    count a half); nan without both classes."""
    good = [v for v, h in zip(values, held) if h]
    bad = [v for v, h in zip(values, held) if not h]
    if not good or not bad:
        return float("nan")
    wins = sum((a > b) + 0.5 * (a == b) for a in good for b in bad)
    return wins / (len(good) * len(bad))


def plans(path):
    with open(path, newline="") as f:
        return [(float(r["epsilon"]), r["held"] in ("1", "true", "True"))
                for r in csv.DictReader(f) if r["planned"] in ("1", "true", "True")
                and r["epsilon"] and r["held"]]


def row(label, points, split):
    below = [h for e, h in points if e < split]
    above = [h for e, h in points if e >= split]
    held = [e for e, h in points if h]
    smallest = f"{min(held):.4f}" if held else "-"
    area = auc([e for e, _ in points], [h for _, h in points])
    return (f"| {label} | {len(points)} | {area:.2f} | {sum(below)}/{len(below)} | "
            f"{sum(above)}/{len(above)} | {smallest} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", nargs="+")
    parser.add_argument("--split", type=float, default=0.02, help="epsilon of the below/above split")
    args = parser.parse_args()
    print(f"| runs | plans | AUC | held, epsilon < {args.split} | held, epsilon >= {args.split} "
          "| smallest epsilon held |")
    print("| --- | --- | --- | --- | --- | --- |")
    pooled = []
    for path in args.csv:
        points = plans(path)
        pooled += points
        print(row(os.path.splitext(os.path.basename(path))[0], points, args.split))
    if len(args.csv) > 1:
        print(row("pooled", pooled, args.split))


if __name__ == "__main__":
    main()
