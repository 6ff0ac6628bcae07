#!/usr/bin/env bash
# occlusion benchmark (docs/methods/occlusion.md): per scene at 512x512, the GPU reference
# (N = 256), then RUNS (default 3) alternating runs of hard and occlusion (--frames 5), then one
# run per parameter variant; the oak (data/tree-oak.json) has no reference that honours alpha
# masks yet: its hard frame is that of a copy where the oak casts nothing. Prints per scene the
# frame ratio occlusion / hard per run and their median, the GPU pass times and the errors.
# Usage: bash scripts/bench-occlusion.sh   (build penumbra-render first; OUT defaults to
# out/bench-occlusion)
set -euo pipefail
cd "$(dirname "$0")/.."
render=build/bin/penumbra-render
root=${OUT:-out/bench-occlusion}
runs=${RUNS:-3}
size=512x512
mkdir -p "$root/tree-oak"
for s in demo plates-three spheres-nine; do
    o=$root/$s
    echo "== $s" >&2
    "$render" --scene data/$s.json --method reference --samples 256 --size $size --out $o/reference --quiet
    for run in $(seq "$runs"); do
        for m in hard occlusion; do
            "$render" --scene data/$s.json --method $m --frames 5 --size $size --out $o/$m-$run \
                --compare $o/reference/visibility.pfm --quiet
        done
    done
    for p in prefilter=sat prefilter=mipmaps slices=16 slices=4 leakfix=off leakfix=paper \
        horizon=off resolution=1024; do
        "$render" --scene data/$s.json --method occlusion --param $p --frames 5 --size $size \
            --out "$o/occlusion-$p" --compare $o/reference/visibility.pfm --quiet
    done
done
# The oak casting nothing: the hard frame of the same view (files resolved from the repository).
sed -e 's/"type": "gltf", "file"/"type": "gltf", "method": "none", "file"/' \
    -e "s|\.\./\.\./shared|$(pwd)/../shared|" data/tree-oak.json > "$root/tree-oak/scene-none.json"
echo "== tree-oak" >&2
for run in $(seq "$runs"); do
    "$render" --scene "$root/tree-oak/scene-none.json" --method hard --frames 5 --size $size \
        --out $root/tree-oak/hard-$run --quiet
    "$render" --scene data/tree-oak.json --method occlusion --frames 5 --size $size \
        --out $root/tree-oak/occlusion-$run --quiet
done
/usr/bin/python3 - "$root" "$runs" <<'PY'
import json, os, statistics, sys
root, runs = sys.argv[1], int(sys.argv[2])
def report(path):
    try:
        with open(os.path.join(path, "report.json")) as f:
            return json.load(f)
    except OSError:
        return None
for scene in ["demo", "plates-three", "spheres-nine", "tree-oak"]:
    d = os.path.join(root, scene)
    ratios = []
    for run in range(1, runs + 1):
        h, o = report(f"{d}/hard-{run}"), report(f"{d}/occlusion-{run}")
        if h and o:
            ratios.append(o["frame_ms"] / h["frame_ms"])
    print(f"{scene}: occlusion / hard per run " + ", ".join(f"{r:.2f}" for r in ratios) +
          f"; median {statistics.median(ratios):.2f}")
    o = report(f"{d}/occlusion-1")
    print("  GPU ms " + ", ".join(f"{k} {v:.1f}" for k, v in o["gpu_ms"].items()))
    for name in sorted(os.listdir(d)):
        r = report(os.path.join(d, name))
        if r and "error" in r and (name in ("hard-1", "occlusion-1") or "=" in name):
            e = r["error"]
            print(f"  {name:28s} mean {e['mean_abs_err']:.4f} p99 {e['p99_err']:.3f} "
                  f"> 0.05: {e['bad_pixel_pct']:.2f}% frame {r['frame_ms']:.0f} ms")
PY
