#!/usr/bin/env python3
"""Rate 10,000 random three-contact grasps of the mug in one call.

Run from the repository after scripts/build.sh:

    PYTHONPATH=build/python /usr/bin/python3 examples/python/grasp_quality_batch.py \
        --db build/databases [--grasps 10000] [--seed 0]

Draws each grasp's three contacts (distinct) from the mug database's
contacts with numpy, computes every grasp's Ferrari-Canny epsilon with one
hfts.grasp_quality_batch call, prints how many grasps are force closure
(epsilon > 0) and the best, and checks a few against
ObjectDatabase.grasp_quality, which rates contacts of the database by
index. Exits with 1 if the two disagree.
"""

import argparse
import math
import os
import sys
import time

import numpy as np

import hfts


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", required=True, help="folder of the object databases")
    parser.add_argument("--grasps", type=int, default=10000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    db = hfts.ObjectDatabase.load(os.path.join(args.db, "mug.h5"))
    rng = np.random.default_rng(args.seed)
    contacts = np.array([rng.choice(db.num_contacts, size=3, replace=False)
                         for _ in range(args.grasps)])

    # The database's normals point out of the object; torques are taken
    # about its centre of mass and scaled by rho, as the planner rates grasps.
    start = time.perf_counter()
    epsilons = hfts.grasp_quality_batch(db.positions[contacts], db.normals[contacts],
                                        center=db.center_of_mass, torque_scale=db.rho,
                                        normal_direction="outward")
    seconds = time.perf_counter() - start

    best = int(np.argmax(epsilons))
    print(f"{db.name}: {db.num_contacts} contacts, {len(contacts)} random grasps "
          f"rated in {seconds:.3f} s")
    print(f"force closure: {np.count_nonzero(epsilons > 0)} of {len(contacts)}")
    print(f"best: contacts {contacts[best].tolist()}, epsilon {epsilons[best]:.4f}")

    for g in [best, *range(5)]:
        single = db.grasp_quality(contacts[g])
        if not math.isclose(single, epsilons[g], rel_tol=1e-12, abs_tol=1e-15):
            print(f"grasp {g}: batch {epsilons[g]!r}, single {single!r}", file=sys.stderr)
            return 1
    print("the batch agrees with ObjectDatabase.grasp_quality on 6 grasps")
    return 0


if __name__ == "__main__":
    sys.exit(main())
