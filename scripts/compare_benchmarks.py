#!/usr/bin/python3
"""Two Google Benchmark binaries side by side, run in alternation (docs/performance.md).

  scripts/compare_benchmarks.py BEFORE AFTER [--filter REGEX] [--rounds N]
                                [--counter NAME] [--min-time SECONDS]

Runs BEFORE, then AFTER, N times over (the machine is shared and noisy:
alternating spreads its moods over both), each with --benchmark_filter and
--benchmark_min_time, and prints a Markdown table: per benchmark, the
median and the minimum over the rounds of the chosen counter (default
`median_us`, the median of single timed checks of planner_benchmark;
`real_time` for the benchmark's own time per iteration) for both binaries,
and the ratio of the medians (AFTER / BEFORE).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
from collections import defaultdict


def run(binary, args):
    """The benchmarks of one run: {name: entry} (aggregates excluded)."""
    command = [binary, f"--benchmark_filter={args.filter}",
               f"--benchmark_min_time={args.min_time}", "--benchmark_format=json"]
    try:
        out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    except FileNotFoundError:
        sys.exit(f"compare_benchmarks: no such binary: {binary}")
    except subprocess.CalledProcessError as e:
        sys.exit(f"compare_benchmarks: {binary} failed (exit {e.returncode}): {e.stderr.strip()}")
    if not out.strip():
        return {}  # no benchmark matched the filter
    try:
        report = json.loads(out)
    except json.JSONDecodeError as e:
        sys.exit(f"compare_benchmarks: {binary} did not print Google Benchmark JSON: {e}")
    return {b["name"]: b for b in report.get("benchmarks", [])
            if b.get("run_type", "iteration") == "iteration"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--filter", default=".", help="--benchmark_filter (default: all)")
    parser.add_argument("--rounds", type=int, default=5, help="runs of each binary (default 5)")
    parser.add_argument("--counter", default="median_us",
                        help="counter or field to compare (default median_us)")
    parser.add_argument("--min-time", type=float, default=0.5,
                        help="--benchmark_min_time in seconds (default 0.5)")
    args = parser.parse_args()
    if args.rounds < 1:
        parser.error("--rounds must be >= 1")
    if not args.min_time > 0:
        parser.error("--min-time must be > 0")
    for binary in (args.before, args.after):
        if not os.access(binary, os.X_OK):
            parser.error(f"not an executable file: {binary}")

    values = defaultdict(lambda: ([], []))  # name -> (before values, after values)
    for _ in range(args.rounds):
        for side, binary in enumerate((args.before, args.after)):
            for name, entry in run(binary, args).items():
                if args.counter in entry:
                    values[name][side].append(float(entry[args.counter]))
    if not values:
        sys.exit(f"compare_benchmarks: no benchmark matched '{args.filter}' "
                 f"with a '{args.counter}' value")

    print("| benchmark | before, median (min) | after, median (min) | ratio |")
    print("| --- | --- | --- | --- |")
    for name in sorted(values):
        before, after = values[name]
        if not before or not after:
            print(f"| {name} | {'-' if not before else f'{statistics.median(before):.4g}'} | "
                  f"{'-' if not after else f'{statistics.median(after):.4g}'} | only in one |")
            continue
        b, a = statistics.median(before), statistics.median(after)
        ratio = f"{a / b:.2f}" if b > 0 else "-"
        print(f"| {name} | {b:.4g} ({min(before):.4g}) | {a:.4g} ({min(after):.4g}) | {ratio} |")


if __name__ == "__main__":
    main()
