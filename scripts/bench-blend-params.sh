#!/usr/bin/env bash
# wedges-blend's parameters (parts, bits, overlap): per overlap scene, the GPU reference (N = 1024
# by default), hard, then every combination at 512x512 with --frames 5; prints a markdown table of
# the mean error against the reference and the frame time over the hard frame of the same run.
# Usage: bash scripts/bench-blend-params.sh [SCENE ...]   (default: the five overlap scenes)
# Writes $OUT/<scene>/<variant>/ and $OUT/table.md (OUT defaults to out/bench-blend-params;
# SIZE, SAMPLES and FRAMES override 512x512, 1024 and 5).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >/dev/null
bash scripts/build.sh >/dev/null
render=build/bin/penumbra-render
size=${SIZE:-512x512}
samples=${SAMPLES:-1024}
frames=${FRAMES:-5}
root=${OUT:-out/bench-blend-params}
if (($# == 0)); then
    set -- data/plates-three.json data/bars-cross.json data/diamonds.json \
        data/spheres-nine.json data/torus-box.json
fi
variants=()
for overlap in paper centroid; do
    for bits in 8 16; do
        for parts in 4 1 8; do variants+=("$parts,$bits,$overlap"); done
    done
done
mkdir -p "$root"
for scene in "$@"; do
    [[ -f "$scene" ]] || { echo "bench-blend-params: missing $scene" >&2; exit 2; }
    name=$(basename "${scene%.*}")
    echo "== $name: reference ($samples samples)" >&2
    "$render" --scene "$scene" --method reference --samples "$samples" --size "$size" \
        --out "$root/$name/reference" --quiet
    ref="$root/$name/reference/visibility.pfm"
    echo "== $name: hard" >&2
    "$render" --scene "$scene" --method hard --frames "$frames" --size "$size" \
        --out "$root/$name/hard" --compare "$ref" --quiet
    for v in "${variants[@]}"; do
        IFS=, read -r parts bits overlap <<<"$v"
        echo "== $name: wedges-blend parts=$parts bits=$bits overlap=$overlap" >&2
        "$render" --scene "$scene" --method wedges-blend --param "parts=$parts" \
            --param "bits=$bits" --param "overlap=$overlap" --frames "$frames" --size "$size" \
            --out "$root/$name/blend-$parts-$bits-$overlap" --compare "$ref" --quiet
    done
done
/usr/bin/python3 - "$root" "$@" <<'PY' | tee "$root/table.md"
import json, os, sys
root, scenes = sys.argv[1], [os.path.splitext(os.path.basename(s))[0] for s in sys.argv[2:]]
def report(scene, run):
    with open(os.path.join(root, scene, run, "report.json")) as f:
        return json.load(f)
print("| scene | parts | bits | overlap | mean abs err | p99 | % > 0.05 | frame ms | / hard |")
print("|---|---:|---:|---|---:|---:|---:|---:|---:|")
for scene in scenes:
    hard = report(scene, "hard")
    e = hard["error"]
    print(f"| {scene} | hard | | | {e['mean_abs_err']:.5f} | {e['p99_err']:.4f} | "
          f"{e['bad_pixel_pct']:.2f} | {hard['frame_ms']:.1f} | 1.00 |")
    for overlap in ("paper", "centroid"):
        for bits in (8, 16):
            for parts in (4, 1, 8):
                r = report(scene, f"blend-{parts}-{bits}-{overlap}")
                e = r["error"]
                print(f"| {scene} | {parts} | {bits} | {overlap} | {e['mean_abs_err']:.5f} | "
                      f"{e['p99_err']:.4f} | {e['bad_pixel_pct']:.2f} | {r['frame_ms']:.1f} | "
                      f"{r['frame_ms'] / hard['frame_ms']:.2f} |")
PY
