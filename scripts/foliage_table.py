"""Tables of scripts/bench-foliage.sh: error over the trees' pixels and frame times."""
import json
import statistics
import os
import platform
import sys

import numpy as np


from pfm import read_pfm as pfm  # (scripts/pfm.py, beside this file)


def report(path):
    with open(os.path.join(path, "report.json")) as f:
        return json.load(f)


def cpu():
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return platform.processor()


root = sys.argv[1]
split = sys.argv.index("--")
trees, variants = sys.argv[2:split], sys.argv[split + 1:]
first = report(os.path.join(root, trees[0], "truth"))
print(f"GL_RENDERER {first.get('gl_renderer', '?')}; CPU {cpu()} ({os.cpu_count()} cores)\n")
print("| tree alone | " + " | ".join(["raytrace N=64"] + variants) + " |")
print("|---" * (len(variants) + 2) + "|")
for t in trees:
    truth = pfm(os.path.join(root, t, "truth", "visibility.pfm"))[..., 0]
    pos = pfm(os.path.join(root, t, "truth", "position.pfm"))
    mask = np.isfinite(pos).all(-1) & (np.abs(pos).sum(-1) > 0)
    cells = []
    for v in ["raytrace-64"] + [v.replace(" ", "-") for v in variants]:
        d = os.path.join(root, t, v)
        e = np.abs(pfm(os.path.join(d, "visibility.pfm"))[..., 0] - truth)[mask]
        frame = report(d).get("frame_ms")
        ms = f", {frame:.1f} ms" if frame is not None and v != "raytrace-64" else ""
        cells.append(f"{e.mean():.4f} ({(e > 0.05).sum()} > 0.05{ms})")
    print(f"| {t} ({mask.sum()} px) | " + " | ".join(cells) + " |")
print("\nMean |dV| over the tree's pixels against raytrace N = 1024 (pixels off by > 0.05, frame"
      " median of 5).\n")
o = os.path.join(root, "tree-oak")


def rounds(name):
    """The reports of every round of one configuration (auto-sample-maps-r1, -r2, ...)."""
    dirs = sorted(d for d in os.listdir(o) if d.startswith(name + "-r") and d[len(name) + 2:].isdigit())
    return [report(os.path.join(o, d)) for d in dirs]


hards = rounds("hard-no-oak")
hard = statistics.median(r["frame_ms"] for r in hards)
print(f"Frames: the median over {len(hards)} rounds (the four alternating) of a median of 5.\n")
print("| tree-oak.json 256² | mean vs raytrace N=1024 | > 0.05 | frame ms | / hard without the oak |")
print("|---|---|---|---|---|")
for a in ["sample-maps", "pcss", "occlusion"]:
    rs = rounds("auto-" + a)
    frame = statistics.median(r["frame_ms"] for r in rs)
    e = rs[0]["error"]
    print(f"| auto alpha={a} | {e['mean_abs_err']:.4f} | {e['bad_pixel_pct']:.2f} % "
          f"| {frame:.1f} | {frame / hard:.1f}× |")
print(f"| hard, oak removed | | | {hard:.1f} | 1.0× |")
