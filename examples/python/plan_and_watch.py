#!/usr/bin/env python3
"""Plan a grasp of the table scene's mug with the KR5 + SDH and write a page
that shows the plan moving in a web browser (docs/viewer.md).

Run from the repository after scripts/build.sh:

    PYTHONPATH=build/python /usr/bin/python3 examples/python/plan_and_watch.py \
        --db build/databases [--seed 1] [--physics] [--out plan.html]

Prints whether the plan succeeded, the grasp's epsilon and the trajectory's
duration; exits with 1 if the plan failed. Without --physics the planner
skips its physics check of the grasp (parameter physics_check 0), which
takes most of a plan's time here.
"""

import argparse
import os
import sys
import tempfile

import hfts

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", required=True, help="folder of the databases and hand maps")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--physics", action="store_true", help="keep the planner's physics check")
    parser.add_argument("--out", help="the page to write (default: hfts_table_plan.html in the "
                                      "temporary folder)",
                        default=os.path.join(tempfile.gettempdir(), "hfts_table_plan.html"))
    args = parser.parse_args()

    world = hfts.World.load(os.path.join(ROOT, "robots", "kr5_sdh", "kr5_sdh.json"), args.db)
    scene = hfts.Scene.load(os.path.join(ROOT, "objects", "scenes", "table.json"))
    parameters = {} if args.physics else {"physics_check": 0}
    plan = world.plan(scene, seed=args.seed, parameters=parameters)

    print(f"success: {plan.success}")
    if not plan.success:
        print(f"failure: {plan.failure}: {plan.message}")
        return 1
    print(f"grasp epsilon: {plan.grasp['epsilon']:.4f}")
    trajectory = plan.trajectory
    print(f"trajectory duration: {trajectory.duration:.2f} s ({len(trajectory)} points; "
          f"the hand closes from {trajectory.closing_start:.2f} s)")
    hfts.write_viewer_page(plan, args.out)
    print(f"viewer page: {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
