#!/usr/bin/env python3
"""Plans from what a depth camera sees, checked against the true scene
(docs/point_clouds.md, issue "Plan from what a camera sees").

  render  DIR       every bundled scene from three camera poses, with the
                    Kinect-like noise (hfts-render-depth): DIR/<scene>_<view>.json
  objects DIR       each view's target points (DIR/<scene>_<view>_object.ply)
                    built into an object database (hfts-preprocess --viewpoint)
                    in DIR/databases, beside links to the bundled ones; and
                    each scene's three views fused: one object from the
                    three clouds (<scene>_fused_object) and a scene with the
                    three depth images (DIR/<scene>_fused.json)
  summary OUT       the table of OUT, per robot, with Wilson intervals
  plan    DIR OUT   for each robot, rendered scene and seed: a plan from the
                    rendered view and one from the true meshes (one thread,
                    10 s, physics check on); the rendered view's plan checked
                    against the true scene: its path densely (every 0.005 rad
                    of the largest joint step; strict up to the pre-grasp, the
                    grasp rule from there) and its grasp in physics on the true
                    object. Writes OUT (JSON lines) and prints the table.
                    With --partial, the view's plan grasps the object built
                    from the view (objects), checked on the true object;
                    with --fused, the three views' object and scene.

Runs under /usr/bin/python3 with PYTHONPATH=build/python.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = ["table", "shelf", "bin"]
# Camera eyes (world, m): behind the robot, to its left, to its right, all
# above the work area and looking at the target. The robot's side of each
# scene is the open one.
VIEWS = {"behind": (-0.35, 0.0, 0.95), "left": (0.15, 0.75, 0.95), "right": (0.15, -0.75, 0.95)}
ROBOTS = ["kr5_sdh", "panda_gripper", "ur5e_allegro"]


def render(out_dir, db_dir, seed=1):
    os.makedirs(out_dir, exist_ok=True)
    for scene in SCENES:
        path = os.path.join(ROOT, "objects", "scenes", scene + ".json")
        target = json.load(open(path))["target"]["pose"]["position"]
        look = f"{target[0]},{target[1]},{target[2] + 0.05}"
        for view, eye in VIEWS.items():
            subprocess.run([os.path.join(ROOT, "build", "bin", "hfts-render-depth"), path,
                            "-o", out_dir, "--db", db_dir, "--eye", ",".join(map(str, eye)),
                            "--look-at", look, "--name", f"{scene}_{view}", "--seed", str(seed),
                            "--partial"],
                           check=True)


def objects(view_dir, db_dir):
    """The objects seen in the views, and the bundled ones, in one directory."""
    out = os.path.join(view_dir, "databases")
    os.makedirs(out, exist_ok=True)
    for name in os.listdir(db_dir):
        link = os.path.join(out, name)
        if not os.path.lexists(link):
            os.symlink(os.path.abspath(os.path.join(db_dir, name)), link)
    preprocess = os.path.join(ROOT, "build", "bin", "hfts-preprocess")
    for scene in SCENES:
        for view, eye in VIEWS.items():
            subprocess.run([preprocess, os.path.join(view_dir, f"{scene}_{view}_object.ply"),
                            "--viewpoint", ",".join(map(str, eye)), "-o", out, "-q"], check=True)
        # The three views fused: one object from the three clouds, a scene
        # with the three depth images.
        clouds = [os.path.join(view_dir, f"{scene}_{v}_object.ply") for v in VIEWS]
        command = [preprocess] + clouds + ["--name", f"{scene}_fused_object", "-o", out, "-q"]
        for eye in VIEWS.values():
            command += ["--viewpoint", ",".join(map(str, eye))]
        subprocess.run(command, check=True)
        merged = None
        for view in VIEWS:
            one = json.load(open(os.path.join(view_dir, f"{scene}_{view}_partial.json")))
            for o in one["obstacles"]:
                o["name"] = f"{o['name']}_{view}"
            if merged is None:
                merged = one
            else:
                merged["obstacles"] += one["obstacles"]
        merged["name"] = f"{scene}_fused"
        merged["target"]["object"] = f"{scene}_fused_object"
        with open(os.path.join(view_dir, f"{scene}_fused.json"), "w") as f:
            json.dump(merged, f, indent=2)


def dense(path, step=0.005):
    """The path's configurations every `step` rad of the largest joint step."""
    out = [path[0]]
    for a, b in zip(path[:-1], path[1:]):
        n = max(1, int(math.ceil(max(abs(x - y) for x, y in zip(a, b)) / step)))
        out += [[x + (y - x) * k / n for x, y in zip(a, b)] for k in range(1, n + 1)]
    return out


def free_in(world, scene, plan, object_pose):
    """Whether the plan's path misses the true scene (its object at
    `object_pose`, None: the scene's): strict up to the pre-grasp, the
    grasp rule on the closing (pre-grasp to grasp)."""
    import numpy as np
    checker = world.checker(scene, object_pose=object_pose)
    path = [list(map(float, row)) for row in plan.path]
    strict = np.array(dense(path[:-1]))
    closing = np.array(dense(path[-2:]))
    hits = checker.in_collision_batch(strict, rule="strict")
    grasp_hits = checker.in_collision_batch(closing, rule="grasp")
    return not hits.any() and not grasp_hits.any()


def plan_all(view_dir, out_path, seeds, time_limit, partial, fused):
    import hfts
    rows = []
    partial = partial or fused
    db_dir = os.path.join(view_dir, "databases") if partial else os.path.join(ROOT, "build",
                                                                               "databases")
    suffix = "_partial" if partial else ""
    views = ["fused"] if fused else list(VIEWS)
    with open(out_path, "w") as out:
        for robot in ROBOTS:
            world = hfts.World.load(os.path.join(ROOT, "robots", robot, robot + ".json"), db_dir)
            for scene_name in SCENES:
                truth = hfts.Scene.load(os.path.join(ROOT, "objects", "scenes", scene_name + ".json"))
                for view in views:
                    t0 = time.time()
                    name = f"{scene_name}_fused" if fused else f"{scene_name}_{view}{suffix}"
                    seen = hfts.Scene.load(os.path.join(view_dir, name + ".json"))
                    load_s = time.time() - t0
                    for seed in seeds:
                        row = {"robot": robot, "scene": scene_name, "view": view, "seed": seed,
                               "scene_load_s": load_s, "partial_object": partial,
                               "fused": fused}
                        p = world.plan(seen, seed=seed, time_limit=time_limit)
                        row["seen_planned"] = bool(p.success)
                        row["seen_failure"] = p.failure
                        if p.success:
                            # An object built from the view is where the true one is
                            # (the world's frame); a true one where the plan had it.
                            row["free_in_truth"] = free_in(world, truth, p,
                                                           None if partial else p.object_pose)
                            v = world.validate(p, scene=truth)
                            row["held_in_truth"] = bool(v["holds"])
                        q = world.plan(truth, seed=seed, time_limit=time_limit)
                        row["truth_planned"] = bool(q.success)
                        rows.append(row)
                        out.write(json.dumps(row) + "\n")
                        out.flush()
                        print(json.dumps(row), flush=True)
    return rows


def wilson(k, n, z=1.96):
    if n == 0:
        return (0.0, 1.0)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


def summary(out_path):
    rows = [json.loads(line) for line in open(out_path) if line.strip()]
    print("| robot | runs | planned from the view | of those, free in the true scene | "
          "of those, held in the true scene | planned, free and held (of all runs) | "
          "planned from the true meshes |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for robot in ROBOTS + ["all"]:
        mine = [r for r in rows if robot in ("all", r["robot"])]
        if not mine:
            continue
        n = len(mine)
        planned = [r for r in mine if r["seen_planned"]]
        free = [r for r in planned if r.get("free_in_truth")]
        held = [r for r in planned if r.get("held_in_truth")]
        both = [r for r in planned if r.get("free_in_truth") and r.get("held_in_truth")]
        truth = [r for r in mine if r["truth_planned"]]

        def cell(k, m):
            lo, hi = wilson(k, m)
            return f"{k}/{m} [{lo:.2f}, {hi:.2f}]"
        print(f"| {robot} | {n} | {cell(len(planned), n)} | {cell(len(free), len(planned))} | "
              f"{cell(len(held), len(planned))} | {cell(len(both), n)} | {cell(len(truth), n)} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("render")
    r.add_argument("dir")
    r.add_argument("--db", default=os.path.join(ROOT, "build", "databases"))
    r.add_argument("--seed", type=int, default=1)
    o = sub.add_parser("objects")
    o.add_argument("dir")
    o.add_argument("--db", default=os.path.join(ROOT, "build", "databases"))
    s = sub.add_parser("summary")
    s.add_argument("out")
    p = sub.add_parser("plan")
    p.add_argument("dir")
    p.add_argument("out")
    p.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    p.add_argument("--time-limit", type=float, default=10.0)
    p.add_argument("--partial", action="store_true",
                   help="grasp the object built from the view (run objects first)")
    p.add_argument("--fused", action="store_true",
                   help="plan in the three views' scene for the object built from them")
    args = parser.parse_args()
    if args.command == "render":
        render(args.dir, args.db, args.seed)
    elif args.command == "objects":
        objects(args.dir, args.db)
    elif args.command == "summary":
        summary(args.out)
    else:
        plan_all(args.dir, args.out, args.seeds, args.time_limit, args.partial, args.fused)
    return 0


if __name__ == "__main__":
    sys.exit(main())
