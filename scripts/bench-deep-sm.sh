#!/usr/bin/env bash
# deep-sm benchmark (docs/methods/deep-sm.md): the views whose casters are translucent or
# alpha-tested (the oak's leaf cards; textured levels from spawn cameras with the viewer's lamp:
# oa_dm1's third under a translucent beam, oa_dm4's first with a translucent doorway edge, and
# oa_dm5's and kaos2's first) at 256x256 (levels 256x144), against `raytrace` N = 1024 with the
# transmittance rule (transmittance=on: the product of 1 - alpha along each ray): deep-sm's
# error beside occlusion's and pcss's (the alpha test at the materials' cutoffs), also over the
# pixels where the rule matters (the alpha-tested raytrace differs from the reference there by
# more than 0.02); its frame over hard's (ROUNDS alternating runs, each the median of 5 frames
# after the first, which builds the deep maps); precompute, memory and function lengths. Then
# the supersampling, tolerance and resolution swept on two views. Writes docs/bench-deep-sm.md.
# Usage: bash scripts/bench-deep-sm.sh   (build first; OUT defaults to out/bench-deep-sm, ROUNDS
# to 3)
set -euo pipefail
cd "$(dirname "$0")/.."
render=build/bin/penumbra-render
root=${OUT:-out/bench-deep-sm}
rounds=${ROUNDS:-3}
levels=../shared/levels/textured
views=("data/tree-oak.json|256x256|tree-oak"
       "$levels/oa_dm1.glb@2|256x144|textured oa_dm1 camera 2"
       "$levels/oa_dm4.glb@0|256x144|textured oa_dm4 camera 0"
       "$levels/oa_dm5.glb@0|256x144|textured oa_dm5 camera 0"
       "$levels/kaos2.glb@0|256x144|textured kaos2 camera 0")
mkdir -p "$root"
rows=()
sweeps=()
for entry in "${views[@]}"; do
    IFS='|' read -r file size name <<<"$entry"
    scene=${file%@*}
    camera=()
    [ "$file" = "$scene" ] || camera=(--camera "${file#*@}")
    o="$root/${name// /-}"
    rows+=("$o|$name")
    echo "== $name" >&2
    [ -f "$o/reference/visibility.pfm" ] ||
        "$render" --scene "$scene" "${camera[@]}" --method raytrace --param transmittance=on \
            --samples 1024 --size "$size" --out "$o/reference" --quiet
    ref=(--compare "$o/reference/visibility.pfm")
    "$render" --scene "$scene" "${camera[@]}" --method raytrace --samples 1024 --size "$size" \
        --out "$o/raytrace-alpha-test" "${ref[@]}" --quiet
    for run in $(seq "$rounds"); do
        "$render" --scene "$scene" "${camera[@]}" --method hard --frames 6 --size "$size" \
            --out "$o/hard-$run" --quiet
        "$render" --scene "$scene" "${camera[@]}" --method deep-sm --frames 6 --size "$size" \
            --out "$o/deep-sm-$run" "${ref[@]}" --quiet
    done
    for m in occlusion pcss; do
        "$render" --scene "$scene" "${camera[@]}" --method "$m" --size "$size" --out "$o/$m" \
            "${ref[@]}" --quiet
    done
    case "$name" in
    tree-oak | "textured oa_dm4 camera 0")
        for p in supersample=1 supersample=2 supersample=4 tolerance=0.016 resolution=256 \
            resolution=1024; do
            "$render" --scene "$scene" "${camera[@]}" --method deep-sm --param "$p" \
                --size "$size" --out "$o/deep-sm-$p" "${ref[@]}" --quiet
            sweeps+=("$o|$name|$p")
        done
        ;;
    esac
done
cpu=$(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')
/usr/bin/python3 - "$rounds" "$cpu" "${rows[@]}" -- "${sweeps[@]}" > docs/bench-deep-sm.md <<'PY'
import json, statistics, sys
import numpy as np
rounds, cpu = int(sys.argv[1]), sys.argv[2]
args = sys.argv[3:]
cut = args.index("--")
rows, sweeps = args[:cut], args[cut + 1:]
def rep(path):
    with open(path + "/report.json") as f:
        return json.load(f)
sys.path.insert(0, "scripts")
from pfm import read_pfm
def pfm(path):
    return read_pfm(path)[..., 0]
def err(r):
    e = r["error"]
    return f"{e['mean_abs_err']:.4f} ({e['bad_pixel_pct']:.1f})"
def masked(o, run, mask):
    if not mask.any():
        return "–"
    ref = pfm(o + "/reference/visibility.pfm")
    v = pfm(f"{o}/{run}/visibility.pfm")
    return f"{np.abs(v - ref)[mask].mean():.4f}"
first = rep(rows[0].split("|")[0] + "/deep-sm-1")
print("<!-- written by scripts/bench-deep-sm.sh; do not edit by hand -->")
print("`deep-sm` with its defaults (deep maps of 512² per face, 3 x 3 rays per texel, tolerance "
      "0.004, pcss's 16 + 32 lookup samples) against `raytrace` N = 1024 with the transmittance "
      "rule (`--param transmittance=on`) of the same view: mean |dV| (% pixels off by > 0.05), "
      "beside `occlusion` and `pcss` (their defaults: the alpha test at each material's cutoff, "
      "BLEND at 0.5) and `raytrace` N = 1024 with the alpha test (how much the rule itself "
      "changes the view). *Translucent pixels*: the mean |dV| over the pixels where the two "
      "raytrace rules differ by more than 0.02 (their share of the view in brackets). Frame: "
      f"deep-sm's over `hard`'s, the median of {rounds} alternating runs, each the median of 6 "
      "frames (the first traces the deep maps). Precompute: the casters' BVH and the maps' rays "
      "(CPU, all cores) and the upload, in the first frame. GL_RENDERER "
      f"{first['gl_renderer']}, CPU {cpu}.")
print()
print("| view | deep-sm | occlusion | pcss | raytrace alpha test | translucent pixels: deep-sm, "
      "occlusion (share) | deep-sm frame / hard | precompute s | faces | deep maps MiB | "
      "points per texel (mean, longest) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for row in rows:
    o, name = row.split("|")
    d = rep(o + "/deep-sm-1")
    c = d["counters"]
    ratios = [rep(f"{o}/deep-sm-{r}")["frame_ms"] / rep(f"{o}/hard-{r}")["frame_ms"]
              for r in range(1, rounds + 1)]
    ref = pfm(o + "/reference/visibility.pfm")
    alpha = pfm(o + "/raytrace-alpha-test/visibility.pfm")
    mask = np.isfinite(ref) & np.isfinite(alpha) & (np.abs(alpha - ref) > 0.02)
    share = mask.sum() / max(np.isfinite(ref).sum(), 1) * 100
    print(f"| {name} | {err(d)} | {err(rep(o + '/occlusion'))} | {err(rep(o + '/pcss'))} | "
          f"{err(rep(o + '/raytrace-alpha-test'))} | {masked(o, 'deep-sm-1', mask)}, "
          f"{masked(o, 'occlusion', mask)} ({share:.1f} %) | {statistics.median(ratios):.2f}× | "
          f"{c['deep_sm_precompute_ms'] / 1000:.1f} | {int(c['deep_sm_faces'])} | "
          f"{c['deep_sm_bytes'] / 2**20:.1f} | {c['deep_sm_mean_function']:.1f}, "
          f"{int(c['deep_sm_longest_function'])} |")
print()
print("**Parameters** (one run each, the same reference):")
print()
print("| view | parameter | mean error (% > 0.05) | deep maps MiB | points per texel | "
      "largest stored deviation | precompute s |")
print("|---|---|---|---|---|---|---|")
for s in sweeps:
    o, name, p = s.split("|")
    for label, path in ([("default", o + "/deep-sm-1")] if p == "supersample=1" else []) + \
            [(p, f"{o}/deep-sm-{p}")]:
        r = rep(path)
        c = r["counters"]
        print(f"| {name} | {label} | {err(r)} | {c['deep_sm_bytes'] / 2**20:.1f} | "
              f"{c['deep_sm_mean_function']:.1f} | {c['deep_sm_max_deviation']:.4f} | "
              f"{c['deep_sm_precompute_ms'] / 1000:.1f} |")
PY
cat docs/bench-deep-sm.md
