#!/usr/bin/python3
"""Side-by-side summary of hfts-bench CSVs (docs/performance.md).

  scripts/compare_runs.py RUNS.csv [--baseline ALGORITHM] [--limit SECONDS]

Per algorithm: success with a Wilson 95 % interval, mean time (failed runs
counted at the time limit), mean per scene, mean CPU time per wall second,
and the geometric mean of the paired time ratios against the baseline
(same scene, object, placement and seed; runs both solved) with a 95 %
interval (t on the log ratios).
"""
import argparse
import csv
import math
import sys
from collections import defaultdict

T95 = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26,
       10: 2.23, 15: 2.13, 20: 2.09, 30: 2.04, 60: 2.00}


def t95(df):
    keys = sorted(k for k in T95 if k <= df)
    return T95[keys[-1]] if keys else T95[1]


def wilson(k, n, z=1.959964):
    if n == 0:
        return 0.0, 0.0
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return max(0.0, c - h), min(1.0, c + h)


def read_runs(path, columns=("scene", "object", "algorithm", "seed", "success", "time")):
    """The rows of an hfts-bench CSV; exits naming the file when it cannot be
    read or lacks one of `columns`."""
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in columns if c not in (reader.fieldnames or [])]
            if missing:
                sys.exit(f"{path}: not an hfts-bench CSV (no column {', '.join(missing)})")
            return list(reader)
    except OSError as e:
        sys.exit(f"{path}: {e.strerror}")


def sign_test(a, b):
    """Two-sided exact binomial test of paired outcomes a against b at p = 1/2."""
    n = a + b
    if n == 0:
        return 1.0
    k = min(a, b)
    return min(1.0, 2.0 * sum(math.comb(n, i) for i in range(k + 1)) / 2.0**n)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", nargs="+")
    parser.add_argument("--baseline", default="coupled")
    parser.add_argument("--limit", type=float, default=None,
                        help="time charged to a failed run (default: its own time)")
    args = parser.parse_args()
    rows = []
    for name in args.csv:
        rows += read_runs(name)
    if not rows:
        sys.exit("no runs")
    case = lambda r: (r["scene"], r["object"], r.get("placement", ""), r["seed"])
    by_alg = defaultdict(list)
    for r in rows:
        by_alg[r["algorithm"]].append(r)
    base = {case(r): r for r in by_alg.get(args.baseline, [])}
    print("| algorithm | success | mean time s | " +
          " / ".join(sorted({r["scene"] for r in rows})) +
          " mean s | CPU / wall | time vs " + args.baseline + " |")
    print("| --- | --- | --- | --- | --- | --- |")
    for alg, runs in by_alg.items():
        ok = [r for r in runs if r["success"] in ("1", "true", "True")]
        def charged(r):
            t = float(r["time"])
            return t if r in ok or args.limit is None else max(t, args.limit)
        lo, hi = wilson(len(ok), len(runs))
        mean = sum(charged(r) for r in runs) / len(runs)
        scenes = defaultdict(list)
        for r in runs:
            scenes[r["scene"]].append(charged(r))
        per_scene = " / ".join(f"{sum(v) / len(v):.2f}" for _, v in sorted(scenes.items()))
        cpu = [float(r["cpu_time"]) / float(r["time"]) for r in runs
               if r.get("cpu_time") and float(r["time"]) > 0]
        cpu_text = f"{min(cpu):.2f}-{max(cpu):.2f}" if cpu else "-"
        logs = [math.log(float(r["time"]) / float(base[case(r)]["time"])) for r in ok
                if case(r) in base and base[case(r)]["success"] in ("1", "true", "True")
                and float(base[case(r)]["time"]) > 0 and float(r["time"]) > 0]
        if alg == args.baseline or len(logs) < 2:
            ratio = "1" if alg == args.baseline else "-"
        else:
            m = sum(logs) / len(logs)
            sd = math.sqrt(sum((x - m) ** 2 for x in logs) / (len(logs) - 1))
            h = t95(len(logs) - 1) * sd / math.sqrt(len(logs))
            ratio = f"{math.exp(m):.2f} [{math.exp(m - h):.2f}, {math.exp(m + h):.2f}] (n={len(logs)})"
        print(f"| {alg} | {len(ok)}/{len(runs)} = {len(ok) / len(runs):.2f} [{lo:.2f}, {hi:.2f}] "
              f"| {mean:.2f} | {per_scene} | {cpu_text} | {ratio} |")


if __name__ == "__main__":
    main()
