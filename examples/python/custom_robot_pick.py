#!/usr/bin/env python3
"""Pick the table scene's mug with a robot made in the program: the KR5 +
SDH renamed "my_kr5", its base joint a1 limited to +-1 rad.

Run from the repository after scripts/build.sh:

    PYTHONPATH=build/python /usr/bin/python3 examples/python/custom_robot_pick.py \
        --db build/databases [--a1-limit 1.0] [--seed 1]

Reads robots/kr5_sdh/kr5_sdh.urdf and kr5_sdh.json as text, edits both,
builds the robot with hfts.Robot.from_strings and its hand map in process
with hfts.HandMap.build (a hand map is tied to its robot's name, so the
bundled kr5_sdh map does not fit "my_kr5"; the build takes well under a
second), makes a world of it and the mug's database, plans, and prints
the grasp as ROS's moveit_msgs/Grasp has it (grasp_pose, grasp_quality).
Exits with 1 if the plan fails or leaves the narrowed limit.
"""

import argparse
import json
import os
import sys
import time
import xml.etree.ElementTree as ElementTree

import numpy as np

import hfts

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROBOT_DIR = os.path.join(ROOT, "robots", "kr5_sdh")


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def narrowed_urdf(text, joint, limit):
    """The URDF with `joint` limited to [-limit, limit] rad."""
    robot = ElementTree.fromstring(text)
    element = robot.find(f"joint[@name='{joint}']/limit")
    element.set("lower", repr(-limit))
    element.set("upper", repr(limit))
    return ElementTree.tostring(robot, encoding="unicode")


def renamed_config(text, name):
    """The robot config under another name. Robot.from_strings is given the
    URDF's text, so the config's "urdf" (a file name) is not needed."""
    config = json.loads(text)
    config["name"] = name
    config.pop("urdf")
    return json.dumps(config)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", required=True, help="folder of the object databases")
    parser.add_argument("--a1-limit", type=float, default=1.0, help="rad (default %(default)s)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    urdf = narrowed_urdf(read(os.path.join(ROBOT_DIR, "kr5_sdh.urdf")), "a1", args.a1_limit)
    config = renamed_config(read(os.path.join(ROBOT_DIR, "kr5_sdh.json")), "my_kr5")
    robot = hfts.Robot.from_strings(urdf, config)
    print(f"{robot.name}: a1 in [{robot.lower_limits[0]:.2f}, {robot.upper_limits[0]:.2f}] rad")

    start = time.perf_counter()
    hand_map = hfts.HandMap.build(robot)
    print(f"hand map: {hand_map.num_samples} postures in {time.perf_counter() - start:.2f} s")

    world = hfts.World(robot, hand_map, [hfts.ObjectDatabase.load(os.path.join(args.db, "mug.h5"))])
    # The scene's start is given for "kr5_sdh" only: my_kr5 starts at its home.
    scene = hfts.Scene.load(os.path.join(ROOT, "objects", "scenes", "table.json"))
    plan = world.plan(scene, seed=args.seed, parameters={"physics_check": 0})
    if not plan.success:
        print(f"plan failed: {plan.failure}: {plan.message}")
        return 1

    grasp = plan.to_ros()["grasp"]
    print("grasp_pose:", json.dumps(grasp["grasp_pose"], indent=2))
    print(f"grasp_quality: {grasp['grasp_quality']:.4f}")
    a1 = np.abs(plan.trajectory.positions[:, robot.dof_names.index("a1")]).max()
    print(f"largest |a1| on the trajectory: {a1:.3f} rad")
    return 0 if a1 <= args.a1_limit + 1e-9 else 1


if __name__ == "__main__":
    sys.exit(main())
