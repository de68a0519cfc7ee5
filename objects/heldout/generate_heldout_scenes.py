#!/usr/bin/python3
"""Generate held-out placements: the bundled scenes (objects/scenes/) with
their named placements replaced by new ones drawn at random, for
evaluating the planner only (nobody tunes on them; see README.md beside
this script).

Each placement keeps the scene's target support (`rest_on`, so the planner
sets the object down on it) and draws its position uniformly from a small
rectangle around the scene's target position and its yaw uniformly from
[0, 2 pi). The rectangles leave about 10 cm of clearance around the
position to the scene's obstacles, so that most held-out objects (at most
20 cm long) stand free at any yaw; a placement that does put an object
into an obstacle is a case the planner reports as `object_in_collision`,
and it stays in every denominator.

Output is deterministic for a seed and written atomically, one file per
scene with the scene's own name, so that `hfts-bench --scene-dir DIR
--placements all` plans at the new placements and at the scene's target:

    /usr/bin/python3 objects/heldout/generate_heldout_scenes.py --seed 1 --count 1 \\
        --out build/heldout_scenes_s1

Needs only the standard library and numpy.
"""

import argparse
import json
import math
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

SCENES = Path(__file__).resolve().parent.parent / "scenes"

# Per scene: the rectangle (dx, dy half-widths, m) around the target's
# position that the positions are drawn from; see the module's docstring.
HALF_WIDTHS = {"table": (0.03, 0.03), "shelf": (0.03, 0.03), "bin": (0.03, 0.03)}


def yaw_quaternion(yaw):
    """The rotation by `yaw` about world z, as [x, y, z, w]."""
    return [0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)]


def placements(scene, count, rng):
    """`count` new placements of the scene's target (names h1, h2, ...)."""
    target = scene["target"]
    x, y, z = target["pose"]["position"]
    dx, dy = HALF_WIDTHS[scene["name"]]
    drawn = []
    for i in range(count):
        px, py, yaw = rng.uniform(-dx, dx), rng.uniform(-dy, dy), rng.uniform(0.0, 2.0 * math.pi)
        pose = {"position": [round(x + px, 6), round(y + py, 6), z],
                "orientation": [round(v, 12) for v in yaw_quaternion(yaw)]}
        placement = {"name": f"h{i + 1}", "pose": pose}
        if "rest_on" in target:
            placement["rest_on"] = target["rest_on"]
        drawn.append(placement)
    return drawn


def write_atomically(path, text):
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, required=True, help="the generator's seed")
    parser.add_argument("--count", type=int, default=1, help="placements per scene (default 1)")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR")
    args = parser.parse_args(argv)
    if args.count < 1:
        parser.error(f"--count: must be at least 1, got {args.count}")
    rng = np.random.default_rng(args.seed)
    args.out.mkdir(parents=True, exist_ok=True)
    for name in sorted(HALF_WIDTHS):
        with open(SCENES / f"{name}.json") as f:
            scene = json.load(f)
        scene["placements"] = placements(scene, args.count, rng)
        scene["description"] = (f"{scene['description']} Held-out placements "
                                f"(generate_heldout_scenes.py --seed {args.seed}).")
        write_atomically(args.out / f"{name}.json", json.dumps(scene, indent=2) + "\n")
    print(f"wrote {len(HALF_WIDTHS)} scenes with {args.count} placement(s) each to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
