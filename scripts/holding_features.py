#!/usr/bin/python3
"""Which features of a grasp predict that it holds in physics? An
exploration on plans made without the physics check
(docs/experiments/2026-11-28-holding-features.md).

  scripts/holding_features.py PLANS.csv

PLANS.csv: one row per plan (robot, case, held, epsilon, the contacts in
the object frame as "x y z nx ny nz" with outward normals, ';'-separated,
the centre of mass, the object's orientation). Per robot and pooled, the
area under the ROC curve of each feature as a predictor of `held` (1: it
orders every held plan before every dropped one; 0.5: chance), oriented so
that higher means "predicts held":
  epsilon        Ferrari-Canny epsilon where the pads touch
  -push_balance  |sum of the unit inward normals| / contacts: how far equal
                 pushes of the fingers are from cancelling
  -push_torque   |sum of (contact - COM) x unit inward normal| / contacts (mm)
  -com_offset    horizontal distance (world) of the COM from the contacts' centroid (mm)
  -friction_need the friction coefficient the contacts need (times mu 0.5)
                 for equal pushes of all fingers to balance, force and
                 torque about the COM, with no weight: a linear program
                 (friction cones as 8-sided pyramids, scipy's HiGHS); 99
                 when no friction balances them
Needs Debian's python3-numpy and python3-scipy.
"""
import argparse
import csv
import math
import os
import sys
from collections import defaultdict

import numpy as np
from scipy.optimize import linprog

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from epsilon_vs_held import auc  # noqa: E402  (same directory)

MU = 0.5
EDGES = 8


def rotation(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def tangents(n):
    a = np.cross(n, [1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.cross(n, [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    return [math.cos(2 * math.pi * k / EDGES) * a + math.sin(2 * math.pi * k / EDGES) * b
            for k in range(EDGES)]


def friction_need(points, inward, com):
    """Smallest s: unit pushes along `inward` plus tangential forces within
    s * MU * (unit push) balance in force and torque about `com`."""
    n = len(points)
    a_eq = np.zeros((6, n * EDGES + 1))
    b_eq = np.zeros(6)
    for i in range(n):
        r = points[i] - com
        b_eq[:3] -= inward[i]
        b_eq[3:] -= np.cross(r, inward[i])
        for k, t in enumerate(tangents(inward[i])):
            a_eq[:3, i * EDGES + k] = t
            a_eq[3:, i * EDGES + k] = np.cross(r, t)
    a_ub = np.zeros((n, n * EDGES + 1))
    for i in range(n):
        a_ub[i, i * EDGES:(i + 1) * EDGES] = 1.0
        a_ub[i, -1] = -MU
    # Balance within a tolerance (1e-6 of a unit push, 1e-6 m of its
    # torque): two contacts on a line through the COM balance exactly only
    # in exact arithmetic, and the CSV keeps six decimals.
    tolerance = np.full(6, 1e-6)
    a_ub = np.vstack([a_ub, a_eq, -a_eq])
    b_ub = np.concatenate([np.zeros(n), b_eq + tolerance, tolerance - b_eq])
    cost = np.zeros(n * EDGES + 1)
    cost[-1] = 1.0
    found = linprog(cost, a_ub, b_ub, bounds=[(0, None)] * (n * EDGES + 1), method="highs")
    # More than any friction: none balances them (99, as when infeasible).
    return min(found.x[-1], 99.0) if found.success else 99.0


def features(row):
    contacts = np.array([[float(v) for v in c.split()] for c in row["contacts"].split(";")])
    points, inward = contacts[:, :3], -contacts[:, 3:]
    com = np.array([float(v) for v in row["com_object"].split()])
    offset = rotation([float(v) for v in row["object_orientation"].split()]) @ (
        com - points.mean(axis=0))
    torque = sum(np.cross(p - com, n) for p, n in zip(points, inward))
    # Rounded, so that values equal but for the CSV's six decimals tie (an
    # antipodal pair needs no friction, whatever its last digits say).
    return {
        "epsilon": float(row["epsilon"]),
        "-push_balance": -round(np.linalg.norm(inward.sum(axis=0)) / len(points), 3),
        "-push_torque": -round(1000 * np.linalg.norm(torque) / len(points), 1),
        "-com_offset": -round(1000 * math.hypot(offset[0], offset[1]), 1),
        "-friction_need": -round(min(friction_need(points, inward, com), 99.0), 3),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv")
    args = parser.parse_args()
    with open(args.csv, newline="") as f:
        plans = [r for r in csv.DictReader(f) if r["success"] == "1" and r["held"] != ""]
    by_robot = defaultdict(list)
    for r in plans:
        x = features(r)
        by_robot[r["robot"]].append((x, r["held"] == "1"))
        by_robot["pooled"].append((x, r["held"] == "1"))
    names = list(by_robot["pooled"][0][0])
    print("| robot | plans | held | " + " | ".join(f"AUC {n}" for n in names) + " |")
    print("| --- | --- | --- | " + " | ".join("---" for _ in names) + " |")
    for robot in sorted(by_robot, key=lambda k: (k == "pooled", k)):
        rows = by_robot[robot]
        held = [h for _, h in rows]
        aucs = " | ".join(f"{auc([x[n] for x, _ in rows], held):.2f}" for n in names)
        print(f"| {robot} | {len(rows)} | {sum(held)} | {aucs} |")
    print()
    print("| robot | smallest epsilon held | held with epsilon < 0.02 | dropped: first failure in "
          "the lift / hold / a disturbance |")
    print("| --- | --- | --- | --- |")
    for robot in sorted({r["robot"] for r in plans}):
        mine = [r for r in plans if r["robot"] == robot]
        held = [float(r["epsilon"]) for r in mine if r["held"] == "1"]
        low = [r for r in mine if float(r["epsilon"]) < 0.02]
        dropped = [r["physics_failure"].split(":")[0] for r in mine if r["held"] == "0"]
        phases = [sum(1 for d in dropped if d == "lift"), sum(1 for d in dropped if d == "hold"),
                  sum(1 for d in dropped if d.startswith("disturbance"))]
        print(f"| {robot} | {min(held):.4f} | {sum(1 for r in low if r['held'] == '1')}/{len(low)} | "
              f"{phases[0]} / {phases[1]} / {phases[2]} of {len(dropped)} |")


if __name__ == "__main__":
    main()
