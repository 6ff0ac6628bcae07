"""Markdown table of scripts/bench-wedges.sh runs: one row per scene and method.

Usage: wedge_table.py ROOT [ROOT ...] -- METHOD [METHOD ...]
With several roots (repeated runs of the bench), the table is the first root's, and a second
table gives each method's ratio to the hard frame in every run and the median: on a shared,
noisy machine one run's ratio can be off by 2x."""
import json
import os
import platform
import sys


def cpu_name():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def fmt(value):
    return "–" if value is None else f"{int(value)}"


def main(root, methods):
    scenes = sorted(d for d in os.listdir(root) if os.path.isdir(os.path.join(root, d)))
    renderer = None
    rows = []
    for scene in scenes:
        reports = {}
        for m in methods + ["reference"]:
            path = os.path.join(root, scene, m, "report.json")
            if os.path.exists(path):
                reports[m] = json.load(open(path))
        if "hard" not in reports:
            continue
        hard = reports["hard"]["frame_ms"]
        for m in methods:
            r = reports.get(m)
            if not r:
                continue
            renderer = r["gl_renderer"]
            c = r.get("counters", {})
            passes = ", ".join(f"{k} {v:.1f}" for k, v in r["gpu_ms"].items())
            e = r["error"]
            rows.append(
                f"| {scene} | {m} | {r['frame_ms']:.1f} | {r['frame_ms'] / hard:.2f} | "
                f"{int(r['wedges'])} | {int(c.get('wedges_culled', 0))} | "
                f"{int(c.get('wedge_fragments', 0))} | {fmt(c.get('pixels_clamped'))} | "
                f"{fmt(c.get('batches'))} | "
                f"{e['mean_abs_err']:.4f} | {e['p99_err']:.3f} | {e['bad_pixel_pct']:.2f} | "
                f"{passes} |")
        ref = reports.get("reference")
        if ref:
            rows.append(f"| {scene} | reference N={ref['parameters']['samples']} | "
                        f"{ref['frame_ms']:.0f} | {ref['frame_ms'] / hard:.0f} | | | | | | | | | |")
    print(f"Renderer: {renderer}; CPU: {cpu_name()} ({os.cpu_count()} cores). "
          "Frame ms are medians of 5 frames; x hard is the ratio to the hard frame of the same "
          "run; error against the GPU reference of the same view.\n")
    print("| scene | method | frame ms | x hard | wedges | culled | wedge fragments | "
          "clamped px | batches | mean err | p99 err | % > 0.05 | GPU ms per pass |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    for row in rows:
        print(row)


def ratios(roots, methods):
    import statistics
    scenes = sorted(d for d in os.listdir(roots[0]) if os.path.isdir(os.path.join(roots[0], d)))
    print("\nFrame time over the hard frame of the same run, per run, and the median:\n")
    print("| scene | method | " + " | ".join(f"run {i + 1}" for i in range(len(roots))) +
          " | median |")
    print("|---|---|" + "---:|" * (len(roots) + 1))
    for scene in scenes:
        for m in methods:
            if m == "hard":
                continue
            values = []
            for root in roots:
                try:
                    h = json.load(open(os.path.join(root, scene, "hard", "report.json")))
                    r = json.load(open(os.path.join(root, scene, m, "report.json")))
                    values.append(r["frame_ms"] / h["frame_ms"])
                except OSError:
                    pass
            if values:
                print(f"| {scene} | {m} | " + " | ".join(f"{v:.2f}" for v in values) +
                      f" | {statistics.median(values):.2f} |")


if __name__ == "__main__":
    args = sys.argv[1:]
    split = args.index("--") if "--" in args else 1
    roots, methods = args[:split], args[split + 1:] if "--" in args else args[1:]
    main(roots[0], methods)
    if len(roots) > 1:
        ratios(roots, methods)
