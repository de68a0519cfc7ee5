#!/usr/bin/python3
"""Two binaries side by side on MotionBenchMaker (docs/motionbenchmaker.md).

  scripts/mbm_side_by_side.py --before B1.csv B2.csv ... --after A1.csv A2.csv ...

Each CSV is one `hfts-bench --mbm` run (gzip-compressed files are read
too); before run i is paired with after run i (same round, run one after
the other). Prints, per run, the medians over solved problems (planning
time, without smoothing and final check, smoothing with final check, final
check, path length, waypoints, states checked), then per problem solved
by both runs of a round: the median of after / before planning time and
path length, with a 95 % bootstrap interval of the median (1,000
resamples, seed 1).
"""
import argparse
import csv
import gzip
import random
import statistics as st


def load(path, algorithm):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        return {(r["scenario"], r["problem"]): r for r in csv.DictReader(f)
                if r["algorithm"] == algorithm}


def summary(name, runs):
    solved = [r for r in runs.values() if r["solved"] == "1"]
    if not solved:
        print(f"{name}: solved 0/{len(runs)}")
        return
    ms = lambda key: st.median(float(r[key]) * 1e3 for r in solved)
    print(f"{name}: solved {len(solved)}/{len(runs)}, median {ms('time'):.3f} ms, "
          f"without smoothing {st.median((float(r['time']) - float(r['smoothing_time'])) * 1e3 for r in solved):.3f}, "
          f"smoothing and final check {ms('smoothing_time'):.3f}, final check {ms('final_check_time'):.3f}, "
          f"path length median {st.median(float(r['path_length']) for r in solved):.3f} "
          f"mean {st.mean(float(r['path_length']) for r in solved):.3f}, "
          f"waypoints {st.median(int(r['waypoints']) for r in solved)}, "
          f"states checked {st.median(int(r['collision_checks']) for r in solved)}")


def interval(values, rng):
    medians = sorted(st.median(rng.choices(values, k=len(values))) for _ in range(1000))
    return medians[25], medians[974]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--before", nargs="+", required=True)
    parser.add_argument("--after", nargs="+", required=True)
    parser.add_argument("--algorithm", default="coupled")
    args = parser.parse_args()
    if len(args.before) != len(args.after):
        parser.error("--before and --after need as many runs each")
    before = [load(p, args.algorithm) for p in args.before]
    after = [load(p, args.algorithm) for p in args.after]
    for i, runs in enumerate(before):
        summary(f"before {i + 1}", runs)
    for i, runs in enumerate(after):
        summary(f"after {i + 1}", runs)
    times, lengths = [], []
    for b, a in zip(before, after):
        for key, r in b.items():
            if r["solved"] == "1" and key in a and a[key]["solved"] == "1":
                times.append(float(a[key]["time"]) / float(r["time"]))
                lengths.append(float(a[key]["path_length"]) / float(r["path_length"]))
    if not times:
        raise SystemExit("no problem solved in both runs of a round")
    rng = random.Random(1)
    low, high = interval(times, rng)
    print(f"per problem, after / before planning time: median {st.median(times):.3f} "
          f"[{low:.3f}, {high:.3f}] ({len(times)} pairs)")
    low, high = interval(lengths, rng)
    print(f"per problem, after / before path length: median {st.median(lengths):.3f} "
          f"[{low:.3f}, {high:.3f}], mean {st.mean(lengths):.3f}")


if __name__ == "__main__":
    main()
