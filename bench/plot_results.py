#!/usr/bin/python3
"""Figures and summary of an hfts-bench experiment (docs/benchmarks.md).

Reads the CSV that hfts-bench writes and writes into --out-dir:

  fig7_success_vs_time.png    success rate over planning time, all scenes,
                              with Wilson 95 % intervals (the paper's Fig. 7)
  fig7_success_by_case.png    the same for each scene and object
  fig8_nodes_explored.png     HFTS nodes explored (GNS) per object, mean and
                              standard error (Fig. 8)
  fig9_valid_goal_ratio.png   valid goal samples per goal sampling call
                              (VGS/GS) per object, mean and standard error (Fig. 9)
  grasp_quality.png           epsilon of the planned grasps per algorithm
  summary.md                  per algorithm: success with Wilson interval, mean
                              and median time with 95 % intervals, GNS, VGS/GS,
                              epsilon; differences to the coupled planner;
                              success per scene and object

Debian's /usr/bin/python3 with python3-numpy and python3-matplotlib.

    /usr/bin/python3 bench/plot_results.py results.csv --out-dir results --time-limit 8
"""

import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the backend)
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

Z95 = 1.959963984540054
# "paper" is the coupled planner with every addition beyond the paper off
# (planner::PlannerPreset::kPaper); a plain "coupled" is the planner's and
# the robot config's defaults (every kept addition on). CSVs written
# before the preset name the older setting, which turned off the goal
# sampling's switches only; CSVs written before the additions were decided
# (docs/planning.md) name the support options explicitly.
PAPER = "paper"
OLD_PAPER = "coupled:stable_nodes=0:other_postures=0:hand_clearance=0:retreat=0"
LABELS = {PAPER: "coupled (paper)", OLD_PAPER: "coupled (Alg. 2 goal sampling)",
          "coupled": "coupled (defaults)",
          "rrtconnect": "RRTConnect + lazy goals",
          "coupled:stable_nodes=1:other_postures=1:hand_clearance=1":
              "coupled + support options, retreat (before 2026-12-05)"}
# Okabe-Ito: distinguishable with the common colour-vision deficiencies.
PALETTE = ["#0072B2", "#E69F00", "#009E73", "#CC79A7", "#777777", "#D55E00", "#56B4E9", "#F0E442"]


def label(algorithm):
    if algorithm in LABELS:
        return LABELS[algorithm]
    if algorithm.startswith("decoupled"):
        # The paper experiment's decoupled runs keep the paper's multi-tree
        # planner (no retreat): that is what "decoupled" means in its plots.
        base, _, settings = algorithm.partition(":")
        shown = "" if settings in ("", "retreat=0", "preset=paper") else " " + settings
        return "decoupled i=" + base[len("decoupled"):] + shown
    if algorithm.startswith("rrtconnect"):
        return "RRTConnect + lazy goals i=" + algorithm[len("rrtconnect"):]
    return algorithm


def read_runs(path):
    runs = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            success = row["success"] == "1"
            runs.append({
                # Placements other than the scene's target pose name the case too
                # (CSVs written before placements existed have no such column).
                "case": row["scene"] + " / " + row["object"]
                + ("" if row.get("placement", "target") == "target"
                   else " / " + row["placement"]),
                "scene": row["scene"],
                "placement": row.get("placement", "target"),
                "object": row["object"],
                "failure": row.get("failure", "") if not success else "",
                "algorithm": row["algorithm"],
                "success": success,
                "time": float(row["time"]),
                "cpu_time": float(row["cpu_time"]),
                "gs": int(row["gs"]),
                "vgs": int(row["vgs"]),
                "gns": int(row["gns"]),
                "epsilon": float(row["epsilon"]) if success else None,
            })
    if not runs:
        sys.exit(f"plot_results.py: {path} holds no runs")
    return runs


def ordered(values):
    """Distinct values in order of first appearance."""
    return list(dict.fromkeys(values))


def wilson(k, n):
    """Wilson score interval (95 %) of a binomial proportion k/n."""
    if n == 0:
        return (0.0, 1.0)
    p = k / n
    centre = (p + Z95 ** 2 / (2 * n)) / (1 + Z95 ** 2 / n)
    half = Z95 * math.sqrt(p * (1 - p) / n + Z95 ** 2 / (4 * n * n)) / (1 + Z95 ** 2 / n)
    return (max(0.0, centre - half), min(1.0, centre + half))


def newcombe(k1, n1, k2, n2):
    """95 % interval of p1 - p2 from the two Wilson intervals (Newcombe 1998, method 10)."""
    p1, p2 = k1 / n1, k2 / n2
    l1, u1 = wilson(k1, n1)
    l2, u2 = wilson(k2, n2)
    d = p1 - p2
    return (d - math.sqrt((p1 - l1) ** 2 + (u2 - p2) ** 2),
            d + math.sqrt((u1 - p1) ** 2 + (p2 - l2) ** 2))


def standard_error(values):
    return float(np.std(values, ddof=1) / math.sqrt(len(values))) if len(values) > 1 else 0.0


def mean_ci(values):
    """Mean and its normal-approximation 95 % interval."""
    m = float(np.mean(values))
    half = Z95 * standard_error(values)
    return m, m - half, m + half


def median_ci(values):
    """Median and its distribution-free 95 % interval from order statistics."""
    x = np.sort(values)
    n = len(x)
    lo = max(0, int(math.floor(n / 2 - Z95 * math.sqrt(n) / 2)) - 1)
    hi = min(n - 1, int(math.ceil(1 + n / 2 + Z95 * math.sqrt(n) / 2)) - 1)
    return float(np.median(x)), float(x[lo]), float(x[hi])


def success_curve(runs, grid):
    """Share of runs that succeeded within each time of `grid`."""
    done = np.sort([r["time"] for r in runs if r["success"]])
    return np.searchsorted(done, grid, side="right") / len(runs)


def style(algorithms):
    return {a: PALETTE[i % len(PALETTE)] for i, a in enumerate(algorithms)}


def time_axis(runs, limit):
    """Log-spaced times from just below the fastest run to the limit (or the slowest run)."""
    low = min(0.1, min(r["time"] for r in runs) * 0.9)
    return np.geomspace(low, max(limit, max(r["time"] for r in runs)) * 1.05, 800)


def plot_success(ax, runs, algorithms, colours, grid, limit):
    """Success-rate curves; Wilson 95 % intervals as bars at the limit and at its
    halvings (shaded bands of five algorithms would hide each other)."""
    checkpoints = limit / 2.0 ** np.arange(6)
    checkpoints = checkpoints[checkpoints >= grid[0]]
    for i, a in enumerate(algorithms):
        mine = [r for r in runs if r["algorithm"] == a]
        if not mine:
            continue
        ax.step(grid, success_curve(mine, grid), where="post", color=colours[a], lw=2,
                ls="--" if a.startswith("rrtconnect") else "-", label=f"{label(a)} (n={len(mine)})")
        k = np.rint(success_curve(mine, checkpoints) * len(mine)).astype(int)
        low, high = np.array([wilson(int(j), len(mine)) for j in k]).T
        rate = k / len(mine)
        dodge = 1.045 ** (i - (len(algorithms) - 1) / 2)  # side by side on the log axis
        yerr = np.clip([rate - low, high - rate], 0, None)  # rounding can put k/n outside
        ax.errorbar(checkpoints * dodge, rate, yerr=yerr, fmt="o", ms=3,
                    color=colours[a], capsize=2, lw=1)
    ax.axvline(limit, color="grey", ls=":", lw=1)
    ax.set_xscale("log")
    ax.set_xlim(grid[0], grid[-1])
    ax.set_ylim(-0.02, 1.02)
    ticks = [t for t in (0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 200)
             if grid[0] <= t <= grid[-1]]
    ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.grid(alpha=0.3, which="both")


def figure_success(runs, algorithms, colours, limit, out):
    grid = time_axis(runs, limit)
    fig, ax = plt.subplots(figsize=(8, 5.2))
    plot_success(ax, runs, algorithms, colours, grid, limit)
    ax.set_xlabel("planning time (s)")
    ax.set_ylabel("success rate")
    ax.set_title("Success rate within a planning time, all scenes and objects\n"
                 f"(bars: Wilson 95 % intervals; dotted: the {limit:g} s limit)")
    ax.legend(loc="lower right", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "fig7_success_vs_time.png"), dpi=130)
    plt.close(fig)


def figure_success_by_case(runs, algorithms, colours, limit, out):
    # Many cases (every object at every placement): one panel per scene and
    # placement, over its objects.
    key = "case"
    if len(set(r["case"] for r in runs)) > 12:
        key = "where"
        runs = [dict(r, where=r["scene"] + " / " + r["placement"]) for r in runs]
    cases = ordered(r[key] for r in runs)
    columns = min(3, len(cases))
    rows = math.ceil(len(cases) / columns)
    grid = time_axis(runs, limit)
    fig, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.3 * rows + 0.9),
                             squeeze=False, sharex=True, sharey=True)
    for ax, case in zip(axes.flat, cases):
        plot_success(ax, [r for r in runs if r[key] == case], algorithms, colours, grid, limit)
        n = sum(1 for r in runs if r[key] == case and r["algorithm"] == algorithms[0])
        ax.set_title(f"{case} (n={n} per algorithm)", fontsize=10)
    for ax in axes.flat[len(cases):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("planning time (s)")
    for ax in axes[:, 0]:
        ax.set_ylabel("success rate")
    handles, names = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, [n.rsplit(" (n=", 1)[0] for n in names], loc="lower center",
               ncol=min(5, len(algorithms)), fontsize=9, frameon=False)
    fig.suptitle("Success rate within a planning time per " +
                 ("scene / object" if key == "case" else "scene / placement (all objects)") +
                 " (bars: Wilson 95 %)")
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(os.path.join(out, "fig7_success_by_case.png"), dpi=110)
    plt.close(fig)


def grouped_bars(runs, algorithms, colours, value, ylabel, title, path):
    """Mean and standard error of value(run) per object (groups) and algorithm (bars)."""
    objects = ordered(r["object"] for r in runs)
    width = 0.8 / len(algorithms)
    many = len(objects) > 10
    fig, ax = plt.subplots(figsize=(min(max(7, 1.6 * len(objects) + 3), 22), 5.5 if many else 5))
    tops, bottoms = [], []
    for i, a in enumerate(algorithms):
        means, errors = [], []
        for o in objects:
            values = [value(r) for r in runs if r["algorithm"] == a and r["object"] == o]
            values = [v for v in values if v is not None]
            means.append(float(np.mean(values)) if values else 0.0)
            errors.append(standard_error(values))
        x = np.arange(len(objects)) + (i - (len(algorithms) - 1) / 2) * width
        ax.bar(x, means, width, yerr=errors, capsize=3, color=colours[a], label=label(a),
               hatch="//" if a.startswith("rrtconnect") else None, edgecolor="white",
               error_kw={"ecolor": "black", "lw": 1})
        tops.extend(m + e for m, e in zip(means, errors))
        bottoms.extend(m for m in means if m > 0)
    ax.set_xticks(np.arange(len(objects)))
    ax.set_xticklabels(objects, rotation=60 if many else 0, ha="right" if many else "center")
    ax.set_xlabel("object (all scenes it was planned in)")
    ax.set_title(title)
    if bottoms and max(tops) / min(bottoms) > 30:  # one algorithm would flatten the others
        ax.set_yscale("log")
        ax.set_ylim(min(bottoms) / 2, max(tops) * 3)
        ylabel += " (log scale)"
    else:
        ax.set_ylim(0, max(tops) * 1.25 if tops and max(tops) > 0 else 1)
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=9, ncol=min(3, len(algorithms)), loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def ratio(run):
    return run["vgs"] / run["gs"] if run["gs"] > 0 else None


def figure_quality(runs, algorithms, colours, out):
    data = [[r["epsilon"] for r in runs if r["algorithm"] == a and r["success"]] for a in algorithms]
    shown = [(a, d) for a, d in zip(algorithms, data) if d]
    fig, ax = plt.subplots(figsize=(8, 5))
    if shown:
        ax.boxplot([d for _, d in shown], widths=0.5, showfliers=False,
                   medianprops={"color": "black"})
        rng = np.random.default_rng(1)
        for i, (a, d) in enumerate(shown, start=1):
            ax.scatter(i + rng.uniform(-0.15, 0.15, len(d)), d, s=12, color=colours[a], alpha=0.7,
                       zorder=3)
        ax.set_xticks(range(1, len(shown) + 1))
        ax.set_xticklabels([f"{label(a)}\n(n={len(d)})" for a, d in shown], fontsize=9)
    ax.set_ylim(bottom=0)
    ax.set_ylabel("Ferrari-Canny epsilon (L1) of the planned grasp")
    ax.set_title("Grasp quality of successful runs (box: quartiles; points: runs)")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "grasp_quality.png"), dpi=130)
    plt.close(fig)


def fmt(x, digits=2):
    return f"{x:.{digits}f}"


def summary_rows(runs, algorithms):
    lines = ["| algorithm | runs | success [Wilson 95 %] | mean time s [95 %] | "
             "median time s [95 %] | mean CPU time s | GNS mean ± SE | VGS/GS mean ± SE | "
             "epsilon mean [95 %] | epsilon median [quartiles] |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for a in algorithms:
        mine = [r for r in runs if r["algorithm"] == a]
        n, k = len(mine), sum(r["success"] for r in mine)
        lo, hi = wilson(k, n)
        times = [r["time"] for r in mine]
        m, mlo, mhi = mean_ci(times)
        md, mdlo, mdhi = median_ci(times)
        gns = [r["gns"] for r in mine]
        ratios = [v for v in map(ratio, mine) if v is not None]
        eps = [r["epsilon"] for r in mine if r["success"]]
        eps_text = "- | -"
        if eps:
            em, elo, ehi = mean_ci(eps)
            eps_text = (f"{em:.3f} [{elo:.3f}, {ehi:.3f}] | {np.median(eps):.3f} "
                        f"[{np.percentile(eps, 25):.3f}, {np.percentile(eps, 75):.3f}]")
        ratio_text = f"{np.mean(ratios):.3f} ± {standard_error(ratios):.3f}" if ratios else "-"
        lines.append(
            f"| {a} | {n} | {k}/{n} = {fmt(k / n)} [{fmt(lo)}, {fmt(hi)}] | "
            f"{fmt(m)} [{fmt(mlo)}, {fmt(mhi)}] | {fmt(md)} [{fmt(mdlo)}, {fmt(mdhi)}] | "
            f"{fmt(np.mean([r['cpu_time'] for r in mine]))} | "
            f"{np.mean(gns):.0f} ± {standard_error(gns):.0f} | {ratio_text} | {eps_text} |")
    return lines


def welch(runs, reference, key, digits):
    """Difference of the means of `key` (runs minus reference; None values left out)
    with its Welch normal-approximation 95 % interval, as text."""
    x = [r[key] for r in runs if r[key] is not None]
    y = [r[key] for r in reference if r[key] is not None]
    if not x or not y:
        return "-"
    d = float(np.mean(x) - np.mean(y))
    half = Z95 * math.hypot(standard_error(x), standard_error(y))
    return f"{d:+.{digits}f} [{d - half:+.{digits}f}, {d + half:+.{digits}f}]"


def reference_of(algorithms):
    """The algorithm the others are compared with: the paper's coupled planner, else a plain
    coupled one (None when neither ran)."""
    return next((a for a in (PAPER, OLD_PAPER, "coupled") if a in algorithms), None)


def difference_rows(runs, algorithms, reference):
    if reference not in algorithms:
        return []
    ref = [r for r in runs if r["algorithm"] == reference]
    lines = ["", f"Differences to `{reference}` (other minus {reference}; 95 % intervals: "
             "Welch normal approximation for the means, Newcombe's score method for "
             "the success rate):", "",
             "| algorithm | mean time difference s [95 %] | success difference [95 %] | "
             "mean epsilon difference [95 %] |",
             "| --- | --- | --- | --- |"]
    for a in algorithms:
        if a == reference:
            continue
        mine = [r for r in runs if r["algorithm"] == a]
        k1, k2 = sum(r["success"] for r in mine), sum(r["success"] for r in ref)
        lo, hi = newcombe(k1, len(mine), k2, len(ref))
        lines.append(f"| {a} | {welch(mine, ref, 'time', 2)} | "
                     f"{k1 / len(mine) - k2 / len(ref):+.2f} [{lo:+.2f}, {hi:+.2f}] | "
                     f"{welch(mine, ref, 'epsilon', 3)} |")
    return lines


def within_rows(runs, algorithms, limit):
    """Fig. 7 as numbers: success within the limit and its halvings."""
    times = [limit / 8, limit / 4, limit / 2, limit]
    lines = ["", "Success within a planning time (Fig. 7), Wilson 95 % intervals:", "",
             "| algorithm | " + " | ".join(f"within {t:g} s" for t in times) + " |",
             "| --- |" + " --- |" * len(times)]
    for a in algorithms:
        mine = [r for r in runs if r["algorithm"] == a]
        cells = []
        for t in times:
            k = sum(r["success"] and r["time"] <= t for r in mine)
            lo, hi = wilson(k, len(mine))
            cells.append(f"{k / len(mine):.2f} [{lo:.2f}, {hi:.2f}]")
        lines.append(f"| {a} | " + " | ".join(cells) + " |")
    return lines


def scene_rows(runs, algorithms, reference):
    """Mean time per scene and its difference to the reference, Welch 95 % intervals."""
    if reference not in algorithms:
        return []
    others = [a for a in algorithms if a != reference]
    lines = ["", f"Per scene (all its objects): mean time of `{reference}` and the mean time "
             f"difference of the others to it, s [95 %]:", "",
             f"| scene | {reference} | " + " | ".join(others) + " |",
             "| --- | --- |" + " --- |" * len(others)]
    for scene in ordered(r["scene"] for r in runs):
        mine = [r for r in runs if r["scene"] == scene]
        ref = [r for r in mine if r["algorithm"] == reference]
        m, lo, hi = mean_ci([r["time"] for r in ref])
        cells = [welch([r for r in mine if r["algorithm"] == a], ref, "time", 2) for a in others]
        lines.append(f"| {scene} | {m:.2f} [{lo:.2f}, {hi:.2f}] | " + " | ".join(cells) + " |")
    return lines


def grid_rows(title, corner, runs, group, algorithms, cell):
    """A table with a row per value of group(run) and a column per algorithm;
    cell(the runs of that row and column) gives the text."""
    lines = ["", title, "", f"| {corner} | " + " | ".join(algorithms) + " |",
             "| --- |" + " --- |" * len(algorithms)]
    for g in ordered(group(r) for r in runs):
        cells = []
        for a in algorithms:
            mine = [r for r in runs if group(r) == g and r["algorithm"] == a]
            cells.append(cell(mine) if mine else "-")
        lines.append(f"| {g} | " + " | ".join(cells) + " |")
    return lines


def gns_and_ratio(runs):
    gns = [r["gns"] for r in runs]
    ratios = [v for v in map(ratio, runs) if v is not None]
    if not ratios:
        return "-"
    return (f"{np.mean(gns):.0f} ± {standard_error(gns):.0f} / "
            f"{np.mean(ratios):.3f} ± {standard_error(ratios):.3f}")


def successes_and_median(runs):
    k = sum(r["success"] for r in runs)
    return f"{k}/{len(runs)}, {np.median([r['time'] for r in runs]):.2f}"


def object_rows(runs, algorithms):
    """Figs. 8 and 9 as numbers: GNS and VGS/GS per object, mean ± standard error."""
    return grid_rows("Per object (Figs. 8 and 9): GNS mean ± SE / VGS/GS mean ± SE:", "object",
                     runs, lambda r: r["object"], algorithms, gns_and_ratio)


def reason_rows(runs, algorithms):
    """How the failed runs failed (the result's reason), per algorithm."""
    reasons = ordered(r["failure"] for r in runs if not r["success"])
    if not reasons:
        return []
    lines = ["", "Failed runs by reason:", "", "| algorithm | " + " | ".join(reasons) + " |",
             "| --- |" + " --- |" * len(reasons)]
    for a in algorithms:
        mine = [r for r in runs if r["algorithm"] == a and not r["success"]]
        lines.append(f"| {a} | " + " | ".join(str(sum(r["failure"] == x for r in mine))
                                           for x in reasons) + " |")
    return lines


def placement_rows(runs, algorithms):
    if all(r["placement"] == "target" for r in runs):
        return []
    return grid_rows("Per scene and placement (all objects): successes / runs, median time (s):",
                     "scene / placement", runs, lambda r: r["scene"] + " / " + r["placement"],
                     algorithms, successes_and_median)


SHORT_REASONS = {"no_valid_goal": "nvg", "time_limit": "tl", "object_in_collision": "oic",
                 "no_stable_grasp_clear_of_support": "nsg", "start_in_collision": "sic"}


def outcome(runs):
    """One algorithm's runs of one case: the median time of a success, or
    the short reason of a failure; k/n when there are several runs."""
    k = sum(r["success"] for r in runs)
    if len(runs) > 1:
        return f"{k}/{len(runs)}"
    r = runs[0]
    return f"{r['time']:.1f}" if r["success"] else SHORT_REASONS.get(r["failure"], r["failure"])


def outcome_rows(runs, algorithms):
    """Every object at every placement, when there are placements: a row per
    object, a column per scene and placement, each cell the algorithms'
    outcomes separated by a slash."""
    if all(r["placement"] == "target" for r in runs):
        return []
    places = ordered(r["scene"] + " / " + r["placement"] for r in runs)
    legend = ", ".join(f"{v}: {k}" for k, v in SHORT_REASONS.items())
    lines = ["", f"Every object at every placement: {' / '.join(algorithms)}; a number is the "
             f"time (s) of a success, otherwise the reason ({legend}):", "",
             "| object | " + " | ".join(places) + " |", "| --- |" + " --- |" * len(places)]
    for o in ordered(r["object"] for r in runs):
        cells = []
        for place in places:
            here = [r for r in runs
                    if r["object"] == o and r["scene"] + " / " + r["placement"] == place]
            cells.append(" / ".join(outcome([r for r in here if r["algorithm"] == a])
                                    if any(r["algorithm"] == a for r in here) else "-"
                                    for a in algorithms))
        lines.append(f"| {o} | " + " | ".join(cells) + " |")
    return lines


def case_rows(runs, algorithms):
    return grid_rows("Per scene and object: successes / runs, median time (s):",
                     "scene / object", runs, lambda r: r["case"], algorithms,
                     successes_and_median)


def write_summary(runs, algorithms, limit, out):
    lines = [f"Time limit {limit:g} s; a failed run counts at its time. GNS: HFTS nodes "
             "explored; VGS/GS: valid goal samples per goal sampling call, per run, then "
             "averaged; epsilon over successful runs.", ""]
    lines += summary_rows(runs, algorithms)
    reference = reference_of(algorithms)
    lines += difference_rows(runs, algorithms, reference)
    lines += within_rows(runs, algorithms, limit)
    lines += reason_rows(runs, algorithms)
    lines += scene_rows(runs, algorithms, reference)
    lines += placement_rows(runs, algorithms)
    lines += object_rows(runs, algorithms)
    lines += outcome_rows(runs, algorithms)
    lines += case_rows(runs, algorithms)
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("csv", help="results CSV written by hfts-bench")
    parser.add_argument("--out-dir", required=True, help="where the figures and summary.md go")
    parser.add_argument("--time-limit", type=float,
                        help="the runs' time limit in s (default: the longest run)")
    args = parser.parse_args()
    runs = read_runs(args.csv)
    limit = args.time_limit or max(r["time"] for r in runs)
    algorithms = ordered(r["algorithm"] for r in runs)
    colours = style(algorithms)
    os.makedirs(args.out_dir, exist_ok=True)
    figure_success(runs, algorithms, colours, limit, args.out_dir)
    figure_success_by_case(runs, algorithms, colours, limit, args.out_dir)
    grouped_bars(runs, algorithms, colours, lambda r: r["gns"], "HFTS nodes explored (GNS)",
                 "HFTS nodes explored per run (mean and standard error)",
                 os.path.join(args.out_dir, "fig8_nodes_explored.png"))
    grouped_bars(runs, algorithms, colours, ratio, "valid goal samples / goal sampling calls",
                 "VGS/GS: valid goal samples per goal sampling call (mean, standard error)",
                 os.path.join(args.out_dir, "fig9_valid_goal_ratio.png"))
    figure_quality(runs, algorithms, colours, args.out_dir)
    write_summary(runs, algorithms, limit, args.out_dir)


if __name__ == "__main__":
    main()
