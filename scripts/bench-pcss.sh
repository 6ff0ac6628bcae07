#!/usr/bin/env bash
# pcss benchmark (docs/methods/pcss.md): per scene at 256x256, the GPU reference (N = 1024), then
# RUNS (default 3) alternating runs of hard and pcss (--frames 5), then one run per parameter
# variant and one of wedges-blend and occlusion for comparison. Prints per scene the frame ratio
# pcss / hard per run and their median, the GPU pass times and the errors.
# Usage: bash scripts/bench-pcss.sh   (build penumbra-render first; OUT defaults to out/bench-pcss)
set -euo pipefail
cd "$(dirname "$0")/.."
render=build/bin/penumbra-render
root=${OUT:-out/bench-pcss}
runs=${RUNS:-3}
size=${SIZE:-256x256}
scenes=(demo parallel-square overlap spheres-nine)
for s in "${scenes[@]}"; do
    o=$root/$s
    echo "== $s" >&2
    "$render" --scene data/$s.json --method reference --samples 1024 --size $size \
        --out $o/reference --quiet
    for run in $(seq "$runs"); do
        for m in hard pcss; do
            "$render" --scene data/$s.json --method $m --frames 5 --size $size --out $o/$m-$run \
                --compare $o/reference/visibility.pfm --quiet
        done
    done
    for p in resolution=512 resolution=2048 blocker_samples=32 blocker_samples=64 \
        pcf_samples=16 pcf_samples=64 bias=0.0 bias=3.0 horizon=off; do
        "$render" --scene data/$s.json --method pcss --param $p --frames 5 --size $size \
            --out "$o/pcss-$p" --compare $o/reference/visibility.pfm --quiet
    done
    for m in wedges-blend occlusion; do
        "$render" --scene data/$s.json --method $m --frames 5 --size $size --out $o/$m \
            --compare $o/reference/visibility.pfm --quiet
    done
done
/usr/bin/python3 - "$root" "$runs" "${scenes[@]}" <<'PY'
import json, os, statistics, sys
root, runs, scenes = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
def report(path):
    try:
        with open(os.path.join(path, "report.json")) as f:
            return json.load(f)
    except OSError:
        return None
for scene in scenes:
    d = os.path.join(root, scene)
    ratios = []
    for run in range(1, runs + 1):
        h, p = report(f"{d}/hard-{run}"), report(f"{d}/pcss-{run}")
        if h and p:
            ratios.append(p["frame_ms"] / h["frame_ms"])
    print(f"{scene}: pcss / hard per run " + ", ".join(f"{r:.2f}" for r in ratios) +
          f"; median {statistics.median(ratios):.2f}")
    p = report(f"{d}/pcss-1")
    print("  GPU ms " + ", ".join(f"{k} {v:.1f}" for k, v in p["gpu_ms"].items()))
    for name in sorted(os.listdir(d)):
        r = report(os.path.join(d, name))
        if r and "error" in r and (name in ("hard-1", "pcss-1", "wedges-blend", "occlusion")
                                   or "=" in name):
            e = r["error"]
            print(f"  {name:24s} mean {e['mean_abs_err']:.4f} p99 {e['p99_err']:.3f} "
                  f"> 0.05: {e['bad_pixel_pct']:.2f}% frame {r['frame_ms']:.1f} ms")
PY
