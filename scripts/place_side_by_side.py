#!/usr/bin/python3
"""The placement searches side by side on hfts-bench --place CSVs
(docs/placement.md#measured).

  scripts/place_side_by_side.py PLACE.csv [PLACE.csv ...] [--against OTHER.csv ...]

Per file (one robot's run): per search, success (held and placed) and
"held, standing after the retreat" with Wilson 95 % intervals, plans found,
what the simulated plans failed on; then the coupled search's place stage
against the decoupled one's on the same task and seed (the same grasp: the
seed decides it before the place stage), runs where both reached a
placement: the median of the paired time ratios with its quartiles and how
many the coupled search was faster in. With --against (files of the same
tasks, robots and seeds from another build), each search's place stage
against its own in those files, paired the same way.
"""
import argparse
import csv
import statistics
import sys
from collections import Counter, defaultdict

from compare_runs import wilson  # same directory


def read(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"place_side_by_side: cannot read {path}: {e}")
    needed = {"task", "robot", "search", "seed", "success", "planned", "stood", "physics_failure",
              "place_time"}
    if not rows or not needed <= set(rows[0]):
        sys.exit(f"place_side_by_side: {path} is not an hfts-bench --place CSV")
    return rows


def rate(k, n):
    lo, hi = wilson(k, n)
    return f"{k}/{n} ({100 * lo:.0f}-{100 * hi:.0f} %)"


def failure_kind(row):
    text = row["physics_failure"]
    if row["planned"] != "1":
        return "not planned: " + row.get("reason", "")
    if not text:
        return "placed"
    phase = text.split(":")[0]
    return phase + (" (in the palm)" if "palm" in text else " (from where released)")


def paired(rows_a, rows_b, key_a, key_b):
    """(time a, time b) of the runs both reached a placement in."""
    b = {key_b(r): r for r in rows_b}
    pairs = []
    for r in rows_a:
        other = b.get(key_a(r))
        if other is None:
            continue
        ta, tb = float(r["place_time"]), float(other["place_time"])
        if r["planned"] == "1" and other["planned"] == "1" and ta > 0 and tb > 0:
            pairs.append((ta, tb))
    return pairs


def describe(pairs, faster_name):
    if not pairs:
        return "no run both reached a placement in"
    ratios = sorted(a / b for a, b in pairs)
    q = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else [ratios[0]] * 3
    faster = sum(1 for a, b in pairs if a < b)
    return (f"{len(pairs)} pairs, median ratio {statistics.median(ratios):.2f} "
            f"(quartiles {q[0]:.2f}-{q[2]:.2f}), {faster_name} faster in {faster}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+")
    parser.add_argument("--against", nargs="*", default=[])
    args = parser.parse_args()
    for path in args.files:
        rows = read(path)
        robot = rows[0]["robot"]
        print(f"## {path} ({robot}, {len(rows)} runs)")
        by_search = defaultdict(list)
        for r in rows:
            by_search[r["search"]].append(r)
        for search, runs in by_search.items():
            n = len(runs)
            ok = sum(r["success"] == "1" for r in runs)
            stood = sum(r["stood"] == "1" and r["planned"] == "1" for r in runs)
            planned = sum(r["planned"] == "1" for r in runs)
            kinds = Counter(failure_kind(r) for r in runs)
            print(f"{search}: success {rate(ok, n)}, standing {rate(stood, n)}, planned {planned}/{n}; "
                  + ", ".join(f"{k} {v}" for k, v in sorted(kinds.items())))
        coupled = by_search.get("coupled", [])
        decoupled = by_search.get("decoupled", [])
        key = lambda r: (r["task"], r["seed"])  # noqa: E731
        print("place stage, coupled / decoupled: " +
              describe(paired(coupled, decoupled, key, key), "coupled"))
    if args.against:
        new = [r for p in args.files for r in read(p)]
        old = [r for p in args.against for r in read(p)]
        key = lambda r: (r["robot"], r["task"], r["search"], r["seed"])  # noqa: E731
        for search in ("coupled", "decoupled"):
            mine = [r for r in new if r["search"] == search]
            print(f"place stage, {search}, these / --against: " +
                  describe(paired(mine, old, key, key), "these"))


if __name__ == "__main__":
    main()
