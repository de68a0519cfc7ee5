#!/usr/bin/python3
"""Plans grasps of objects under a board just above them (scenes generated
here, none bundled): how often a plan is found, which kind of lift it
takes (docs/placement.md "The lift"), and whether its grasp held in
physics (the plan's physics check follows the plan's lift).

    PYTHONPATH=build/python scripts/lift_under_board.py --robots kr5_sdh \
        --objects box,mug,bottle --scenes 3 --seeds 1,2 --out lift.csv
"""
import argparse
import csv
import json
import math
import random
import sys
import time

import hfts


def object_height(world, name):
    """The object's top above its frame (its database's mesh)."""
    return world.object(name).mesh_vertices[:, 2].max()


def board_scene(rng, name, top):
    """A table, the object somewhere on it, a board `headroom` above it."""
    x, y = rng.uniform(0.45, 0.65), rng.uniform(-0.15, 0.15)
    yaw = rng.uniform(-math.pi, math.pi)
    headroom, size = rng.uniform(0.03, 0.06), rng.uniform(0.25, 0.4)
    pose = lambda p, yaw=0.0: {"position": p, "orientation": [0, 0, math.sin(yaw / 2), math.cos(yaw / 2)]}
    scene = {
        "name": "under_board",
        "robot_base": pose([0, 0, 0]),
        "obstacles": [
            {"name": "table", "type": "box", "size": [1.0, 1.4, 0.04], "pose": pose([0.55, 0, -0.021])},
            {"name": "board", "type": "box", "size": [size, size, 0.01],
             "pose": pose([x + rng.uniform(-0.05, 0.05), y + rng.uniform(-0.05, 0.05), top + headroom + 0.005])},
        ],
        "target": {"object": name, "pose": pose([x, y, 0.0], yaw), "rest_on": "table"},
    }
    return scene, headroom, size


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--robots", default="kr5_sdh,panda_gripper,ur5e_allegro")
    p.add_argument("--objects", default="box,mug,bottle")
    p.add_argument("--scenes", type=int, default=3, help="scenes per robot and object")
    p.add_argument("--seeds", default="1,2")
    p.add_argument("--time-limit", type=float, default=10.0)
    p.add_argument("--scene-seed", type=int, default=4801, help="seed of the generated scenes")
    p.add_argument("--db", default="build/databases")
    p.add_argument("--out", required=True)
    a = p.parse_args()
    fields = ["robot", "object", "scene", "headroom", "board", "seed", "success", "failure",
              "lift", "held_fraction", "time", "lift_blocked", "dropped_goals", "message"]
    with open(a.out + ".tmp", "w", newline="") as f:
        out = csv.DictWriter(f, fieldnames=fields)
        out.writeheader()
        for robot in a.robots.split(","):
            world = hfts.World.load(f"robots/{robot}/{robot}.json", a.db)
            for name in a.objects.split(","):
                rng = random.Random(f"{a.scene_seed}-{name}")
                top = object_height(world, name)
                for k in range(a.scenes):
                    scene, headroom, size = board_scene(rng, name, top)
                    for seed in (int(s) for s in a.seeds.split(",")):
                        began = time.monotonic()
                        plan = world.plan(hfts.Scene.from_json(json.dumps(scene)), seed=seed,
                                          time_limit=a.time_limit, validate=True)
                        v = plan.validation
                        row = {"robot": robot, "object": name, "scene": k, "headroom": round(headroom, 4),
                               "board": round(size, 3), "seed": seed, "success": int(plan.success),
                               "failure": plan.failure, "lift": plan.lift["direction"] if plan.lift else "",
                               "held_fraction": v["physics"]["held_fraction"] if v and v.get("physics") else "",
                               "time": round(time.monotonic() - began, 3),
                               "lift_blocked": plan.stats["rejected_lift_blocked"],
                               "dropped_goals": plan.stats["dropped_goals"],
                               "message": "" if plan.success else plan.message[:160]}
                        out.writerow(row)
                        f.flush()
                        print(row, file=sys.stderr)
    import os
    os.replace(a.out + ".tmp", a.out)


if __name__ == "__main__":
    main()
