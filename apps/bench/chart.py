#!/usr/bin/python3
"""chart.png of a penumbra-bench run: mean error against frame time, one panel per scene.

Usage: chart.py RESULTS.csv CHART.png [RENDERER]

Each run is one point: x = mean |V - V_truth| (log), y = frame time in ms (log); one marker and
colour per method, swept parameters labelled beside their point. The Pareto front of each panel
(runs that no other run beats on both error and time) is the dashed line. Runs without an error
(refused, failed) are left out and counted in the panel title. Needs Debian's python3-matplotlib.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {
    "hard": ("s", "#444444"),
    "reference": ("*", "#000000"),
    "raytrace": ("*", "#777777"),
    "wedges-additive": ("^", "#1f77b4"),
    "wedges-blend": ("o", "#d62728"),
    "wedges-multiply": ("v", "#2ca02c"),
    "wedges-bitmask": ("P", "#9467bd"),
    "occlusion": ("D", "#ff7f0e"),
    "pcss": ("X", "#8c564b"),
    "sample-maps": ("p", "#17becf"),
    "linear-light-sm": ("<", "#bcbd22"),
    "pdsm": (">", "#1a55ff"),
    "deep-sm": ("8", "#000075"),
    "auto": ("h", "#e377c2"),
}
# A method without a style of its own (a new one) gets one of these, by first appearance, so
# that no two methods of a chart share a colour and marker.
SPARE = [("o", "#aec7e8"), ("^", "#ffbb78"), ("v", "#98df8a"), ("D", "#ff9896"),
         ("s", "#c5b0d5"), ("P", "#c49c94"), ("X", "#f7b6d2"), ("*", "#dbdb8d")]
BASE = set(STYLE)
ERROR_FLOOR = 1e-5  # a run scored against itself (error 0) is drawn here


def number(text):
    try:
        x = float(text)
    except ValueError:
        return None
    return x if math.isfinite(x) else None


def pareto(points):
    """Points (err, ms) not dominated by another, sorted by error."""
    front = []
    best = math.inf
    for err, ms in sorted(points):
        if ms < best:
            front.append((err, ms))
            best = ms
    return front


def default_params(rows, method):
    """The parameter text shared by every run of a method (not worth a label)."""
    texts = {r["params"] for r in rows if r["method"] == method}
    return texts.pop() if len(texts) == 1 else None


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: chart.py RESULTS.csv CHART.png [RENDERER]")
    source, target = sys.argv[1], sys.argv[2]
    renderer = sys.argv[3] if len(sys.argv) > 3 else ""
    with open(source, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{source}: no runs")

    panels = {}
    scales = {r["light_scale"] for r in rows}
    for r in rows:
        key = os.path.basename(r["scene"])
        if len(scales) > 1:
            key += f"  (light x{r['light_scale']})"
        panels.setdefault(key, []).append(r)

    n = len(panels)
    cols = min(4, n)
    rws = math.ceil(n / cols)
    fig, axes = plt.subplots(rws, cols, figsize=(4.2 * cols, 3.6 * rws), squeeze=False)
    seen = {}
    for ax, (name, runs) in zip(axes.flat, panels.items()):
        points, skipped = [], 0
        for r in runs:
            err, ms = number(r["mean_abs_err"]), number(r["frame_ms"])
            if err is None or ms is None or not r["status"].startswith("ok"):
                skipped += 1
                continue
            method = r["method"]
            if method not in STYLE:
                STYLE[method] = SPARE[len([m for m in STYLE if m not in BASE]) % len(SPARE)]
            marker, colour = STYLE[method]
            x = max(err, ERROR_FLOOR)
            handle = ax.scatter(x, ms, marker=marker, color=colour, s=46, zorder=3,
                                edgecolors="white", linewidths=0.5)
            seen.setdefault(method, handle)
            if default_params(runs, method) is None and r["params"]:
                ax.annotate(r["params"].replace(";", " "), (x, ms), fontsize=5,
                            xytext=(3, 3), textcoords="offset points", color=colour)
            points.append((x, ms))
        front = pareto(points)
        if len(front) > 1:
            xs, ys = zip(*front)
            ax.step(xs, ys, where="post", linestyle="--", color="#999999", linewidth=0.9,
                    zorder=2)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(name + (f"  [{skipped} runs not scored]" if skipped else ""), fontsize=8)
        ax.set_xlabel("mean |V - V_truth|", fontsize=7)
        ax.set_ylabel("frame ms (median)", fontsize=7)
        ax.tick_params(labelsize=6)
        ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    truth = rows[0].get("truth", "")
    samples = rows[0].get("truth_samples", "")
    size = f"{rows[0].get('width', '')}x{rows[0].get('height', '')}"
    fig.suptitle(f"penumbra-bench: frame time against error ({size}, truth {truth} N={samples})"
                 + (f"\n{renderer}" if renderer else "")
                 + "   dashed: Pareto front; lower left is better", fontsize=9)
    fig.legend(list(seen.values()), list(seen.keys()), loc="lower center",
               ncol=min(len(seen), 8), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.05, 1, 0.95))
    fig.savefig(target, dpi=130)


if __name__ == "__main__":
    main()
