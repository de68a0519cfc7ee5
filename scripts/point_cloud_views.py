#!/usr/bin/env python3
"""Plans from what a depth camera sees, checked against the true scene
(docs/point_clouds.md, issue "Plan from what a camera sees").

  render  DIR       every bundled scene from three camera poses, with the
                    Kinect-like noise (hfts-render-depth): DIR/<scene>_<view>.json;
                    with --ring from four all round the target (objects --ring,
                    plan --fused then use them)
  objects DIR       each view's target built into an object database from its
                    depth image (hfts-preprocess --depth-views) in
                    DIR/databases, beside links to the bundled ones; and each
                    scene's three views fused: a scene with the three depth
                    images (DIR/<scene>_fused.json) and one object from them
                    (<scene>_fused_object). With --clouds, from the target's
                    points alone (--viewpoint) into DIR/databases_clouds.
  containment DIR OUT
                    how far the true object lies outside the solid of each
                    object built from the views, both ways: the bundled
                    scenes' views (render first) or, with --held-out N, N
                    new scenes of other objects among random clutter, three
                    random cameras each, rendered into DIR first
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


def ring(scene):
    """Four cameras around `scene`'s target, 0.8 m from it and 0.95 m
    high, a quarter turn apart (the far side too: a cell with cameras all
    round)."""
    target = json.load(open(os.path.join(ROOT, "objects", "scenes", scene + ".json")))
    x, y, _ = target["target"]["pose"]["position"]
    return {f"ring{k}": (x - 0.8 * math.cos(k * math.pi / 2), y - 0.8 * math.sin(k * math.pi / 2),
                         0.95) for k in range(4)}


def views_of(scene, around):
    return ring(scene) if around else VIEWS


def render(out_dir, db_dir, seed=1, around=False):
    os.makedirs(out_dir, exist_ok=True)
    for scene in SCENES:
        path = os.path.join(ROOT, "objects", "scenes", scene + ".json")
        target = json.load(open(path))["target"]["pose"]["position"]
        look = f"{target[0]},{target[1]},{target[2] + 0.05}"
        for view, eye in views_of(scene, around).items():
            subprocess.run([os.path.join(ROOT, "build", "bin", "hfts-render-depth"), path,
                            "-o", out_dir, "--db", db_dir, "--eye", ",".join(map(str, eye)),
                            "--look-at", look, "--name", f"{scene}_{view}", "--seed", str(seed),
                            "--partial"],
                           check=True)


def link_databases(out, db_dir):
    """`out` with links to the bundled databases of `db_dir`."""
    os.makedirs(out, exist_ok=True)
    for name in os.listdir(db_dir):
        link = os.path.join(out, name)
        if not os.path.lexists(link):
            os.symlink(os.path.abspath(os.path.join(db_dir, name)), link)


def fuse(view_dir, scene, views):
    """DIR/<scene>_fused.json: the views' depth images in one scene, its
    target the object built from them (<scene>_fused_object)."""
    merged = None
    for view in views:
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


def build_views(view_dir, out, scene, views, method):
    """The objects of `scene`'s views, one per view and the views fused,
    into `out`: from the depth images (method "depth", hfts-preprocess
    --depth-views) or from the target's points alone ("clouds",
    --viewpoint). Returns {name: error or None}."""
    preprocess = os.path.join(ROOT, "build", "bin", "hfts-preprocess")
    jobs = {}
    for view, eye in views.items():
        if method == "depth":
            jobs[f"{scene}_{view}_object"] = [os.path.join(view_dir, f"{scene}_{view}_partial.json"),
                                              "--depth-views"]
        else:
            jobs[f"{scene}_{view}_object"] = [os.path.join(view_dir, f"{scene}_{view}_object.ply"),
                                              "--viewpoint", ",".join(map(str, eye))]
    if method == "depth":
        jobs[f"{scene}_fused_object"] = [os.path.join(view_dir, f"{scene}_fused.json"),
                                         "--depth-views"]
    else:
        command = [os.path.join(view_dir, f"{scene}_{v}_object.ply") for v in views]
        for eye in views.values():
            command += ["--viewpoint", ",".join(map(str, eye))]
        jobs[f"{scene}_fused_object"] = command
    errors = {}
    for name, command in jobs.items():
        run = subprocess.run([preprocess] + command + ["--name", name, "-o", out, "-q"],
                             capture_output=True, text=True)
        errors[name] = None if run.returncode == 0 else (run.stderr.strip() or run.stdout.strip())
    return errors


def objects(view_dir, db_dir, method="depth", around=False):
    """The objects seen in the views, and the bundled ones, in one directory
    (DIR/databases; DIR/databases_clouds for the method "clouds")."""
    out = os.path.join(view_dir, "databases" if method == "depth" else "databases_clouds")
    link_databases(out, db_dir)
    for scene in SCENES:
        views = views_of(scene, around)
        fuse(view_dir, scene, views)
        for name, error in build_views(view_dir, out, scene, views, method).items():
            if error:
                print(f"{name}: {error}", file=sys.stderr)


def surface_samples(vertices, faces, count=5000, seed=0):
    """Points uniform on a triangle mesh's surface."""
    import numpy as np
    rng = np.random.default_rng(seed)
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    area = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    pick = rng.choice(len(faces), count, p=area / area.sum())
    u, v = rng.random(count), rng.random(count)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    return a[pick] + u[:, None] * (b[pick] - a[pick]) + v[:, None] * (c[pick] - a[pick])


def winding_numbers(points, vertices, faces, chunk=256):
    """The generalized winding number of a closed mesh (closed parts that
    overlap add up) at each point: about 1 inside a part, 0 outside all."""
    import numpy as np
    out = np.zeros(len(points))
    for start in range(0, len(points), chunk):
        p = points[start:start + chunk, None, :]
        a, b, c = (vertices[faces[:, k]][None] - p for k in range(3))
        la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
        det = np.einsum("pij,pij->pi", a, np.cross(b, c))
        div = (la * lb * lc + np.einsum("pij,pij->pi", a, b) * lc +
               np.einsum("pij,pij->pi", b, c) * la + np.einsum("pij,pij->pi", c, a) * lb)
        out[start:start + chunk] = np.arctan2(det, div).sum(1) / (2 * np.pi)
    return out


def triangle_distances(points, vertices, faces, chunk=128):
    """Distance from each point to the nearest triangle (exact)."""
    import numpy as np
    out = np.empty(len(points))
    a0, b0, c0 = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    for start in range(0, len(points), chunk):
        p = points[start:start + chunk, None, :]
        ab, ac, ap = b0 - a0, c0 - a0, p - a0
        n = np.cross(ab, ac)
        n2 = np.maximum((n * n).sum(1), 1e-30)
        # The plane's foot, then the closest point of each edge if outside.
        t = np.einsum("pij,ij->pi", ap, n) / n2
        foot = p - t[..., None] * n
        # Inside when on the inner side of each edge (n x edge points in).
        v = np.einsum("ij,pij->pi", np.cross(n, ab), foot - a0) >= 0
        w = np.einsum("ij,pij->pi", np.cross(n, c0 - b0), foot - b0) >= 0
        x = np.einsum("ij,pij->pi", np.cross(n, a0 - c0), foot - c0) >= 0
        inside = v & w & x & ((n * n).sum(1) > 1e-24)  # not for a sliver without a normal
        best = np.where(inside, np.abs(t) * np.sqrt(n2), np.inf)
        for e0, e1 in ((a0, b0), (b0, c0), (c0, a0)):
            d = e1 - e0
            s = np.clip(np.einsum("pij,ij->pi", p - e0, d) / np.maximum((d * d).sum(1), 1e-30),
                        0, 1)
            q = e0 + s[..., None] * d
            best = np.minimum(best, np.linalg.norm(p - q, axis=2))
        out[start:start + chunk] = best.min(1)
    return out


def outside_distances(solid_db, true_db, pose):
    """How far (m) points uniform on the true object's surface (its
    database's mesh at the 4x4 `pose`) lie outside what the database built
    from views holds: its solid and the boxes of space no camera saw free
    beside it (partial_view/hidden_low, hidden_high). 0 inside."""
    import h5py
    import numpy as np
    with h5py.File(solid_db, "r") as f:
        solid_vertices, solid_faces = f["object/mesh_vertices"][()], f["object/mesh_triangles"][()]
        view = f["partial_view"]
        low = view["hidden_low"][()] if "hidden_low" in view else np.zeros((0, 3))
        high = view["hidden_high"][()] if "hidden_high" in view else np.zeros((0, 3))
    with h5py.File(true_db, "r") as f:
        vertices, faces = f["object/mesh_vertices"][()], f["object/mesh_triangles"][()]
    pose = np.asarray(pose)
    points = surface_samples(vertices @ pose[:3, :3].T + pose[:3, 3], faces)
    out = np.zeros(len(points))
    outside = winding_numbers(points, solid_vertices, solid_faces) < 0.5
    if not outside.any():
        return out
    p = points[outside]
    distance = triangle_distances(p, solid_vertices, solid_faces)
    for start in range(0, len(low), 2048):
        lo, hi = low[None, start:start + 2048], high[None, start:start + 2048]
        gap = np.maximum(np.maximum(lo - p[:, None], p[:, None] - hi), 0.0)
        distance = np.minimum(distance, np.linalg.norm(gap, axis=2).min(1))
    out[outside] = distance
    return out


def resting_pose(scene, db_dir):
    """The 4x4 pose of `scene`'s target (a scene file's JSON) standing on
    its `rest_on` box (its lowest vertex on the box's top), else as given."""
    import h5py
    import numpy as np
    target = scene["target"]
    q = np.asarray(target["pose"]["orientation"], dtype=float)
    x, y, z, w = q / np.linalg.norm(q)
    rotation = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    pose = np.eye(4)
    pose[:3, :3] = rotation
    pose[:3, 3] = target["pose"]["position"]
    if target.get("rest_on"):
        support = next(o for o in scene["obstacles"] if o["name"] == target["rest_on"])
        top = support["pose"]["position"][2] + support["size"][2] / 2
        with h5py.File(os.path.join(db_dir, target["object"] + ".h5"), "r") as f:
            lowest = (f["object/mesh_vertices"][()] @ rotation.T)[:, 2].min()
        pose[2, 3] = top - lowest
    return pose


# Held-out objects for the containment check: none is a bundled scene's
# target (mug, bottle, blob), on which the carving was developed.
HELD_OUT_OBJECTS = ["jug", "bowl", "kettlebell", "vase", "tin_can", "carton", "egg",
                    "saucepan", "crayon_box", "torus", "peg", "box"]


def box_pose(position, yaw=0.0):
    return {"position": list(position), "orientation": [0.0, 0.0, math.sin(yaw / 2),
                                                        math.cos(yaw / 2)]}


def held_out(out_dir, cases, seed, db_dir):
    """`cases` scenes of a held-out object on a table among 2-3 random boxes
    and cylinders (every third in a bin instead), each rendered from three
    random camera poses with noise. Returns {case: views}."""
    import random
    import h5py
    import numpy as np
    rng = random.Random(seed)
    os.makedirs(out_dir, exist_ok=True)
    table = {"name": "table", "type": "box", "size": [1.0, 1.4, 0.04],
             "pose": box_pose([0.55, 0.0, -0.021])}
    out = {}
    for i in range(cases):
        name = HELD_OUT_OBJECTS[i % len(HELD_OUT_OBJECTS)]
        with h5py.File(os.path.join(db_dir, name + ".h5"), "r") as f:
            vertices = f["object/mesh_vertices"][()]
        radius = float(np.linalg.norm(vertices[:, :2], axis=1).max())
        centre = [0.5 + rng.uniform(-0.05, 0.1), rng.uniform(-0.1, 0.1)]
        yaw = rng.uniform(0, 2 * math.pi)
        obstacles = [table]
        support = "table"
        if i % 3 == 2:  # in a bin
            support = "bin_bottom"
            half = radius + 0.12
            obstacles.append({"name": "bin_bottom", "type": "box", "size": [2 * half, 2 * half, 0.02],
                              "pose": box_pose([centre[0], centre[1], 0.0095])})
            for k, (dx, dy) in enumerate([(1, 0), (-1, 0), (0, 1), (0, -1)]):
                size = [0.02, 2 * half, 0.18] if dx else [2 * half, 0.02, 0.18]
                obstacles.append({"name": f"bin_wall_{k}", "type": "box", "size": size,
                                  "pose": box_pose([centre[0] + dx * half, centre[1] + dy * half,
                                                    0.09])})
        for k in range(rng.choice([2, 3]) if support == "table" else 1):
            height = rng.uniform(0.05, 0.25)
            size = rng.uniform(0.02, 0.05)
            angle = rng.uniform(0, 2 * math.pi)
            gap = radius + size * 1.5 + rng.uniform(0.01, 0.06)
            position = [centre[0] + gap * math.cos(angle), centre[1] + gap * math.sin(angle),
                        height / 2 + (0.0195 if support != "table" else -0.001)]
            if rng.random() < 0.5:
                obstacles.append({"name": f"clutter_{k}", "type": "box",
                                  "size": [2 * size, 2 * size, height],
                                  "pose": box_pose(position, rng.uniform(0, math.pi))})
            else:
                obstacles.append({"name": f"clutter_{k}", "type": "cylinder", "radius": size,
                                  "length": height, "pose": box_pose(position)})
        scene = {"name": f"heldout_{i}", "description": f"held-out case {i}: {name}",
                 "robot_base": box_pose([0, 0, 0]), "obstacles": obstacles,
                 "target": {"object": name, "pose": box_pose([centre[0], centre[1], 0.0], yaw),
                            "rest_on": support}}
        path = os.path.join(out_dir, f"heldout_{i}.json")
        with open(path, "w") as f:
            json.dump(scene, f, indent=2)
        look = resting_pose(scene, db_dir)[:3, 3] + [0, 0, 0.05]
        azimuths = sorted(rng.uniform(-80, 80) for _ in range(3))
        views = {}
        for k, azimuth in enumerate(azimuths):
            distance, height = rng.uniform(0.5, 0.9), rng.uniform(0.45, 0.95)
            a = math.radians(azimuth)
            eye = (look[0] - distance * math.cos(a), look[1] + distance * math.sin(a), height)
            views[f"v{k}"] = eye
            subprocess.run([os.path.join(ROOT, "build", "bin", "hfts-render-depth"), path,
                            "-o", out_dir, "--db", db_dir, "--eye", ",".join(map(str, eye)),
                            "--look-at", ",".join(map(str, look)), "--name", f"heldout_{i}_v{k}",
                            "--seed", str(seed + i), "--partial"],
                           check=True, capture_output=True)
        out[f"heldout_{i}"] = views
    return out


def containment(view_dir, cases, db_dir, out_path):
    """For each case ({scene name: views}, their renders in `view_dir`),
    the objects built both ways (one per view and the views fused) and how
    far the true object's surface lies outside each one's solid."""
    import numpy as np
    rows = []
    for scene_name, views in cases.items():
        path = os.path.join(view_dir, scene_name + ".json")
        if not os.path.exists(path):
            path = os.path.join(ROOT, "objects", "scenes", scene_name + ".json")
        scene = json.load(open(path))
        pose = resting_pose(scene, db_dir)
        true_db = os.path.join(db_dir, scene["target"]["object"] + ".h5")
        fuse(view_dir, scene_name, views)
        for method in ("clouds", "depth"):
            out = os.path.join(view_dir, "containment_" + method)
            os.makedirs(out, exist_ok=True)
            for name, error in build_views(view_dir, out, scene_name, views, method).items():
                row = {"scene": scene_name, "object": scene["target"]["object"], "built": name,
                       "fused": name.endswith("_fused_object"), "method": method,
                       "error": error}
                if not error:
                    d = outside_distances(os.path.join(out, name + ".h5"), true_db, pose)
                    row.update(max_outside=float(d.max()), p99_outside=float(np.quantile(d, 0.99)),
                               share_outside_2mm=float((d > 0.002).mean()))
                rows.append(row)
                print(json.dumps(row), flush=True)
    with open(out_path, "w") as f:
        for row in rows:
            f.write(json.dumps(row) + "\n")
    containment_summary(rows)
    return rows


def containment_summary(rows, limit=0.003):
    """Per method and kind: built, and contained (every surface sample
    within `limit` of the solid)."""
    print(f"| method | objects | built | contained (max outside <= {1000 * limit:.0f} mm) | "
          "median of max outside (mm) | largest (mm) |")
    print("| --- | --- | --- | --- | --- | --- |")
    for method in ("clouds", "depth"):
        for fused in (False, True):
            mine = [r for r in rows if r["method"] == method and r["fused"] == fused]
            built = [r for r in mine if not r["error"]]
            ok = [r for r in built if r["max_outside"] <= limit]
            worst = sorted(1000 * r["max_outside"] for r in built)
            median = worst[len(worst) // 2] if worst else float("nan")
            lo, hi = wilson(len(ok), len(built))
            print(f"| {method}, {'three views fused' if fused else 'one view'} | {len(mine)} | "
                  f"{len(built)} | {len(ok)}/{len(built)} [{lo:.2f}, {hi:.2f}] | {median:.1f} | "
                  f"{worst[-1] if worst else float('nan'):.1f} |")


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
    r.add_argument("--ring", action="store_true",
                   help="four cameras all round each target instead of the three")
    o = sub.add_parser("objects")
    o.add_argument("dir")
    o.add_argument("--db", default=os.path.join(ROOT, "build", "databases"))
    o.add_argument("--clouds", action="store_true",
                   help="build from the target's points alone (--viewpoint)")
    o.add_argument("--ring", action="store_true", help="the views render --ring made")
    c = sub.add_parser("containment")
    c.add_argument("dir")
    c.add_argument("out")
    c.add_argument("--db", default=os.path.join(ROOT, "build", "databases"))
    c.add_argument("--held-out", type=int, default=0,
                   help="render this many held-out cases into DIR first (else: the bundled "
                        "scenes' views, render first)")
    c.add_argument("--seed", type=int, default=11)
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
        render(args.dir, args.db, args.seed, args.ring)
    elif args.command == "objects":
        objects(args.dir, args.db, "clouds" if args.clouds else "depth", args.ring)
    elif args.command == "containment":
        if args.held_out:
            cases = held_out(args.dir, args.held_out, args.seed, args.db)
        else:
            cases = {scene: VIEWS for scene in SCENES}
        containment(args.dir, cases, args.db, args.out)
    elif args.command == "summary":
        summary(args.out)
    else:
        plan_all(args.dir, args.out, args.seeds, args.time_limit, args.partial, args.fused)
    return 0


if __name__ == "__main__":
    sys.exit(main())
