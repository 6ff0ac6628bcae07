#!/usr/bin/python3
"""Tables for docs/levels-spawn-all.md from penumbra-bench's results.json (scripts/levels-spawn-all.sh).

One row per spawn view: each method's mean |V - V_truth| over the pixels with a surface, with
the share of pixels off by more than 0.05; auto's frame over hard's. Then the real-levels
targets counted over every view, with the views that miss them named."""
import json
import sys
from collections import OrderedDict

AUTO_MAX = 0.002         # auto's mean error on every spawn view
BEST_SHARE = 1.10        # auto within 10 % of the view's best method ...
BEST_FLOOR = 1e-4        # ... or this close in absolute terms (a best of 0.00000 would allow nothing)
APPROX_SLACK = 0.01      # pcss and occlusion never worse than hard + this

results = json.load(open(sys.argv[1]))
rows = results["runs"]
methods = []
views = OrderedDict()
for r in rows:
    if r["method"] not in methods:
        methods.append(r["method"])
    views.setdefault(r["scene"], {})[r["method"]] = r


def name(scene):
    path, camera = scene.split("@camera")
    level = path.rsplit("/", 1)[-1].removesuffix(".glb")
    return ("textured " if "/textured/" in path else "") + level, int(camera)


def cell(r):
    if r is None or r["status"] != "ok" or r["mean_abs_err"] is None:
        return "(%s)" % (r["status"] if r else "missing")
    return "%.5f (%.2f %%)" % (r["mean_abs_err"], r["bad_pixel_pct"])


print("<!-- written by scripts/levels-spawn-all.sh; do not edit by hand -->")
print("# Every spawn view with the lamp\n")
print("The four shared levels, untextured and textured, from every glTF (spawn) camera with the")
print("viewer's lamp: `penumbra-bench --cameras all` at %dx%d against alpha-aware `raytrace` N = %d"
      % (rows[0]["width"], rows[0]["height"], rows[0]["truth_samples"]))
print("of the same view. Each cell: mean |V − V_truth| over the pixels with a surface (share of")
print("pixels off by more than 0.05). `auto / hard`: auto's frame over hard's on the same run")
print("(median of %d frames; docs/levels-lamp.md compares frames over alternating rounds)."
      % results["settings"].get("frames", 0))
print("GL_RENDERER %s, CPU %s (%s hardware threads), %s.\n"
      % (results["gl_renderer"], results["cpu"], results["hardware_threads"], results["date"]))

print("| view | " + " | ".join(methods) + " | auto / hard |")
print("|---|" + "---|" * (len(methods) + 1))
misses = {"auto": [], "hard": [], "best": [], "pcss": [], "occlusion": []}
counted = {k: 0 for k in misses}
for scene, by in views.items():
    level, camera = name(scene)
    auto = by.get("auto")
    ratio = auto["frame_over_hard"] if auto and auto.get("frame_over_hard") else float("nan")
    print("| %s, camera %d | %s | %.1f× |"
          % (level, camera, " | ".join(cell(by.get(m)) for m in methods), ratio))

    def err(m):
        r = by.get(m)
        return r["mean_abs_err"] if r and r["status"] == "ok" else None

    a, h = err("auto"), err("hard")
    label = "%s camera %d" % (level, camera)
    if a is not None:
        counted["auto"] += 1
        if a > AUTO_MAX:
            misses["auto"].append("%s (%.5f)" % (label, a))
        if h is not None and not level.startswith("textured"):
            counted["hard"] += 1
            if a > h:
                misses["hard"].append("%s (auto %.5f, hard %.5f)" % (label, a, h))
        errs = {m: err(m) for m in methods if err(m) is not None}
        best_m = min(errs, key=errs.get)
        counted["best"] += 1
        if a > max(BEST_SHARE * errs[best_m], errs[best_m] + BEST_FLOOR):
            misses["best"].append("%s (auto %.5f, %s %.5f)" % (label, a, best_m, errs[best_m]))
    for m in ("pcss", "occlusion"):
        e = err(m)
        if e is not None and h is not None:
            counted[m] += 1
            if e > h + APPROX_SLACK:
                misses[m].append("%s (%.5f, hard %.5f)" % (label, e, h))

print("\n## The targets on every view\n")
print("| target | views that meet it | misses |")
print("|---|---|---|")
targets = [
    ("auto", "auto's mean ≤ %.3f" % AUTO_MAX),
    ("hard", "auto never worse than hard (untextured)"),
    ("best", "auto within 10 %% of the view's best method (or %.4f)" % BEST_FLOOR),
    ("pcss", "pcss ≤ hard + %.2f" % APPROX_SLACK),
    ("occlusion", "occlusion ≤ hard + %.2f" % APPROX_SLACK),
]
for key, text in targets:
    miss = misses[key]
    print("| %s | %d of %d | %s |" % (text, counted[key] - len(miss), counted[key],
                                     "; ".join(miss) if miss else "none"))
