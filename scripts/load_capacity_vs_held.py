#!/usr/bin/python3
"""Does a grasp's load capacity (docs/grasp_quality.md#load-capacity)
predict that it holds in physics? Reads a CSV of validated plans (columns
robot, epsilon, load_capacity, held; one row per plan made without the
physics check, then simulated) and prints per robot: the plans, how many
held, the area under the ROC curve of the load capacity and of epsilon as
predictors of `held` (0.5: chance), the plans that held with a capacity
below 1 and those that did not hold with one below 1.

  scripts/load_capacity_vs_held.py PLANS.csv
"""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epsilon_vs_held import auc  # noqa: E402  (same directory)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plans", help="CSV with robot, epsilon, load_capacity, held")
    args = parser.parse_args()
    with open(args.plans, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["load_capacity"] and r["held"]]
    print("| robot | plans | held | AUC load capacity | AUC epsilon "
          "| held with capacity < 1 | not held with capacity < 1 |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for robot in sorted({r["robot"] for r in rows}):
        mine = [r for r in rows if r["robot"] == robot]
        held = [r["held"] == "1" for r in mine]
        load = [float(r["load_capacity"]) for r in mine]
        eps = [float(r["epsilon"]) for r in mine]
        weak_held = sum(1 for c, h in zip(load, held) if h and c < 1.0)
        weak_dropped = sum(1 for c, h in zip(load, held) if not h and c < 1.0)
        print(f"| {robot} | {len(mine)} | {sum(held)} | {auc(load, held):.2f} | "
              f"{auc(eps, held):.2f} | {weak_held} of {sum(held)} | "
              f"{weak_dropped} of {len(mine) - sum(held)} |")


if __name__ == "__main__":
    main()
