#!/usr/bin/python3
"""Two hfts-bench runs of the same cases side by side, per robot (docs/experiments/2026-12-05-switches.md):
planned and held with Wilson intervals, the paired cases only one of them planned and held, the
two-sided sign test on those, the median time ratio over the cases both planned and held, and how many
returned plans held.

  scripts/compare_before_after.py DIR ROBOT [ROBOT ...]

reads DIR/before_ROBOT_s2.csv and DIR/after_ROBOT_s2.csv."""
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_runs import read_runs, sign_test, wilson  # noqa: E402  (same directory)


def rows(path):
    columns = ("scene", "object", "success", "planned", "held", "time")
    return {(r["scene"], r["object"]): r for r in read_runs(path, columns)}


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    directory = sys.argv[1]
    print("| robot | before: planned and held | after: planned and held | only before "
          "| only after | sign test p | time after / before (median, both held) "
          "| returned plans that held, before / after |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for robot in sys.argv[2:]:
        b = rows(os.path.join(directory, f"before_{robot}_s2.csv"))
        a = rows(os.path.join(directory, f"after_{robot}_s2.csv"))
        if set(a) != set(b):
            sys.exit(f"{robot}: the two runs have different cases")
        hb = {c for c, r in b.items() if r["success"] == "1"}
        ha = {c for c, r in a.items() if r["success"] == "1"}
        pb = [r for r in b.values() if r["planned"] == "1"]
        pa = [r for r in a.values() if r["planned"] == "1"]
        ratios = [float(a[c]["time"]) / float(b[c]["time"]) for c in hb & ha]
        n = len(b)

        def rate(k):
            lo, hi = wilson(k, n)
            return f"{k}/{n} = {k / n:.2f} [{lo:.2f}, {hi:.2f}]"

        ratio = f"{statistics.median(ratios):.2f}" if ratios else "-"
        held_b = sum(r["held"] == "1" for r in pb)
        held_a = sum(r["held"] == "1" for r in pa)
        print(f"| {robot} | {rate(len(hb))} | {rate(len(ha))} | {len(hb - ha)} | {len(ha - hb)} "
              f"| {sign_test(len(hb - ha), len(ha - hb)):.2f} | {ratio} "
              f"| {held_b}/{len(pb)}, {held_a}/{len(pa)} |")


if __name__ == "__main__":
    main()
