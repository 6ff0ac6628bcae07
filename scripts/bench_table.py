#!/usr/bin/python3
"""Markdown tables of a penumbra-bench results.csv, for docs/benchmarks.md and docs/methods/.

Usage: bench_table.py RESULTS.csv [--metric err|flicker|speed|all]

One row per scene, one column per run (method, with its swept parameters when a method was run
more than once). Cells:
  err      mean |V - V_truth|, then the share of pixels off by > 0.05 in parentheses
  flicker  flicker along the light path (DESIGN.md §5)
  speed    frame time over the hard frame of the same scene, same run
The best real-time value of each row is in bold (hard and the truth methods excluded). A cell
reads "refused" for a method that refuses the scene (a clear error, in the CSV's status), and is
flagged "GL!" / "NaN!" when a run had GL errors or non-finite pixels.
"""
import csv
import os
import sys

EXCLUDED_FROM_BEST = {"hard", "reference", "raytrace"}


def fmt(value, digits):
    return f"{value:.{digits}f}"


def main():
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    metric = "all"
    if "--metric" in args:
        i = args.index("--metric")
        metric = args[i + 1]
        del args[i:i + 2]
    with open(args[0], newline="") as f:
        rows = list(csv.DictReader(f))

    counts = {}
    for r in rows:
        counts.setdefault(r["method"], set()).add(r["params"])

    def column(r):
        if len(counts[r["method"]]) > 1:
            return r["method"] + " " + r["params"].replace(";", " ")
        return r["method"]

    columns = []
    for r in rows:
        c = column(r)
        if c not in columns:
            columns.append(c)
    scenes = []
    for r in rows:
        key = (os.path.basename(r["scene"]), r["light_scale"])
        if key not in scenes:
            scenes.append(key)
    multi_scale = len({s for _, s in scenes}) > 1
    table = {}
    for r in rows:
        table[(os.path.basename(r["scene"]), r["light_scale"], column(r))] = r

    metrics = ["err", "flicker", "speed"] if metric == "all" else [metric]
    titles = {"err": "mean error (% pixels > 0.05)", "flicker": "flicker",
              "speed": "frame / hard frame"}
    for m in metrics:
        print(f"\n**{titles[m]}**\n")
        print("| scene | " + " | ".join(columns) + " |")
        print("|---|" + "---|" * len(columns))
        for scene, scale in scenes:
            values = {}
            for c in columns:
                r = table.get((scene, scale, c))
                if r is None:
                    continue
                if not r["status"].startswith("ok"):
                    continue
                key = {"err": "mean_abs_err", "flicker": "flicker", "speed": "frame_over_hard"}[m]
                if r[key] != "":
                    values[c] = float(r[key])
            best = None
            candidates = {c: v for c, v in values.items()
                          if c.split(" ")[0] not in EXCLUDED_FROM_BEST}
            if candidates:
                best = min(candidates, key=candidates.get)
            cells = []
            for c in columns:
                r = table.get((scene, scale, c))
                if r is None:
                    cells.append("")
                    continue
                if r["status"].startswith("refused") or r["status"].startswith("no truth"):
                    cells.append("refused")
                    continue
                if not r["status"].startswith("ok"):
                    cells.append("FAILED")
                    continue
                if c not in values:
                    cells.append("–")
                    continue
                v = values[c]
                if m == "err":
                    text = f"{fmt(v, 4)} ({fmt(float(r['bad_pixel_pct']), 1)})"
                elif m == "flicker":
                    text = fmt(v, 4)
                else:
                    text = fmt(v, 1) + "×"
                if c == best:
                    text = f"**{text}**"
                if r["gl_errors"] not in ("", "0"):
                    text += " GL!"
                if r["nan_pixels"] not in ("", "0") or r["out_of_range_pixels"] not in ("", "0"):
                    text += " NaN!"
                cells.append(text)
            name = scene + (f" ×{scale}" if multi_scale else "")
            print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
