#!/usr/bin/python3
"""The reference sample: 25 cases drawn at random (seed 43) from each
robot's failed cases of the physics-check experiment's every-case run
(seed 1, 10 s), interleaved by robot, one line per case:
robot scene object placement failure. Run from this folder:
  ./sample.py > cases.txt
The six lines after the 75 that cases.txt holds are the mask check's
(the KR5's no_stable_grasp_clear_of_support cases), not part of the sample."""
import csv
import random

D = "../2026-11-27-physics-check/"
rng = random.Random(43)
rows = []
for robot in ["panda_gripper", "ur5e_allegro", "kr5_sdh"]:
    with open(D + f"all_cases_{robot}.csv", newline="") as f:
        fails = [x for x in csv.DictReader(f) if x["success"] != "1"]
    for x in rng.sample(fails, 25):
        rows.append((robot, x["scene"], x["object"], x["placement"], x["failure"]))
for i in range(25):
    for k in range(3):
        print(" ".join(rows[k * 25 + i]))
