#!/usr/bin/env python3
"""What the Python module's batch calls cost over the same C++ calls, side
by side on one machine (docs/performance.md, "Python batch calls").

Writes one set of inputs (fixed seed): N grasps of 3 contacts on an
object's database contacts, N palm poses (forward kinematics of random
configurations), N random configurations in a scene. Then, for each round,
runs python_batch_benchmark (Google Benchmark: the batch functions of
python/src/batch.h without Python) and times the module's calls on the same
arrays (hfts.grasp_quality_batch, World.ik_batch,
CollisionChecker.in_collision_batch), one after the other (odd rounds
Python first). Reports the time
per item of each side and the ratio Python / C++ per round, with its median
and range; writes rounds.csv and summary.json into --out.

  PYTHONPATH=build/python /usr/bin/python3 python/bench/batch_overhead.py \\
      --benchmark build/bin/python_batch_benchmark --db build/databases \\
      --out docs/experiments/data/DATE-python-batch
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import hfts

CALLS = ("grasp_quality_batch", "ik_batch", "in_collision_batch")
CPP_NAMES = {"BM_GraspQualityBatch": "grasp_quality_batch", "BM_ArmIkBatch": "ik_batch",
             "BM_CollisionBatch": "in_collision_batch"}


def write_inputs(folder, args):
    world = hfts.World.load(args.robot, args.db)
    scene = hfts.Scene.load(args.scene)
    rng = np.random.default_rng(args.seed)
    target = world.object(scene.target_object)
    picks = rng.integers(0, target.num_contacts, size=(args.items, 3))
    positions = np.ascontiguousarray(target.positions[picks])
    normals = np.ascontiguousarray(target.normals[picks])
    robot = world.robot
    palm = robot.link_names.index(robot.palm_link)
    q = rng.uniform(robot.lower_limits, robot.upper_limits, size=(args.items, robot.num_dofs))
    poses = np.ascontiguousarray(np.stack([robot.link_poses(c)[palm] for c in q]))
    configurations = rng.uniform(robot.lower_limits, robot.upper_limits,
                                 size=(args.items, robot.num_dofs))
    for name, array in (("quality_positions", positions), ("quality_normals", normals),
                        ("ik_poses", poses), ("configurations", configurations)):
        array.astype("<f8").tofile(os.path.join(folder, name + ".f64"))
    meta = {"robot": os.path.abspath(args.robot), "db": os.path.abspath(args.db),
            "scene": os.path.abspath(args.scene), "grasps": args.items, "poses": args.items,
            "configurations": args.items, "center": target.center_of_mass.tolist(),
            "torque_scale": target.rho}
    with open(os.path.join(folder, "inputs.json"), "w") as f:
        json.dump(meta, f)
    checker = world.checker(scene)
    calls = {
        "grasp_quality_batch": lambda: hfts.grasp_quality_batch(
            positions, normals, center=target.center_of_mass, torque_scale=target.rho,
            normal_direction="outward"),
        "ik_batch": lambda: world.ik_batch(poses, seed=1),
        "in_collision_batch": lambda: checker.in_collision_batch(configurations),
    }
    return calls


def time_python(call, min_time):
    """Seconds per call: the median of calls repeated for at least min_time."""
    times, spent = [], 0.0
    while spent < min_time or len(times) < 3:
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
        spent += times[-1]
    return statistics.median(times)


def time_cpp(benchmark, folder, min_time):
    """Seconds per batch of each C++ benchmark (its reported real time)."""
    run = subprocess.run([benchmark, f"--inputs={folder}", "--benchmark_format=json",
                          f"--benchmark_min_time={min_time}"],
                         capture_output=True, text=True, check=True)
    out = {}
    for b in json.loads(run.stdout)["benchmarks"]:
        scale = {"ms": 1e-3, "us": 1e-6, "ns": 1e-9, "s": 1.0}[b["time_unit"]]
        out[CPP_NAMES[b["name"]]] = b["real_time"] * scale
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--benchmark", required=True, help="build/bin/python_batch_benchmark")
    parser.add_argument("--db", required=True, help="databases and the robot's hand map")
    parser.add_argument("--robot", default="robots/kr5_sdh/kr5_sdh.json")
    parser.add_argument("--scene", default="objects/scenes/table.json")
    parser.add_argument("--items", type=int, default=10000)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--min-time", type=float, default=2.0, help="s per measurement")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        calls = write_inputs(folder, args)
        for call in calls.values():
            call()  # warm up
        for r in range(args.rounds):
            # Odd rounds time Python first: neither side always runs after
            # the other.
            python = {} if r % 2 == 0 else {n: time_python(calls[n], args.min_time) for n in CALLS}
            cpp = time_cpp(args.benchmark, folder, args.min_time)
            for name in CALLS:
                if name not in python:
                    python[name] = time_python(calls[name], args.min_time)
                rows.append({"round": r, "call": name, "items": args.items,
                             "cpp_us_per_item": 1e6 * cpp[name] / args.items,
                             "python_us_per_item": 1e6 * python[name] / args.items,
                             "ratio": python[name] / cpp[name]})
                print(f"round {r} {name}: C++ {rows[-1]['cpp_us_per_item']:.3f} us, Python "
                      f"{rows[-1]['python_us_per_item']:.3f} us per item, ratio "
                      f"{rows[-1]['ratio']:.4f}", flush=True)
    with open(os.path.join(args.out, "rounds.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    summary = {"command": " ".join(sys.argv), "items": args.items, "rounds": args.rounds}
    for name in CALLS:
        ratios = [row["ratio"] for row in rows if row["call"] == name]
        cpp = [row["cpp_us_per_item"] for row in rows if row["call"] == name]
        summary[name] = {"median_ratio": statistics.median(ratios), "min_ratio": min(ratios),
                         "max_ratio": max(ratios),
                         "cpp_us_per_item_median": statistics.median(cpp)}
        print(f"{name}: Python / C++ median {summary[name]['median_ratio']:.4f} "
              f"(range {min(ratios):.4f}-{max(ratios):.4f}) over {len(ratios)} rounds; C++ "
              f"{summary[name]['cpp_us_per_item_median']:.3f} us per item")
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)


if __name__ == "__main__":
    main()
