#!/usr/bin/env bash
# README command 1: install what is missing, build, render the demo scene with the GPU reference,
# hard shadow volumes, the wedge methods (wedges-bitmask: the recommended one) and auto (the
# default), and print each one's frame time (and its ratio to
# the hard frame of the same run) and its error against the reference.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
render=build/bin/penumbra-render
scene=data/demo.json
methods=(hard wedges-additive wedges-multiply wedges-blend wedges-bitmask auto)
echo "== reference: 256 stratified hard-shadow passes =="
"$render" --scene "$scene" --method reference --samples 256 --size 512x512 --out out/demo-reference
for m in "${methods[@]}"; do
    echo "== $m, error against the reference =="
    "$render" --scene "$scene" --method "$m" --frames 5 --size 512x512 --out "out/demo-$m" \
        --compare out/demo-reference/visibility.pfm
done
/usr/bin/python3 - "${methods[@]}" <<'PY'
import json, sys
rows = [(m, json.load(open(f"out/demo-{m}/report.json"))) for m in sys.argv[1:]]
hard = rows[0][1]["frame_ms"]
print(f"\nsummary ({rows[0][1]['gl_renderer']}), 512x512, medians of 5 frames:")
print(f"{'method':<18}{'frame ms':>10}{'x hard':>8}{'mean err':>10}{'p99 err':>9}{'> 0.05':>9}")
for m, r in rows:
    e = r["error"]
    print(f"{m:<18}{r['frame_ms']:>10.1f}{r['frame_ms'] / hard:>8.2f}{e['mean_abs_err']:>10.4f}"
          f"{e['p99_err']:>9.3f}{e['bad_pixel_pct']:>8.2f}%")
print("images: " + " ".join(f"out/demo-{m}/image.png" for m in ["reference"] + sys.argv[1:]))
PY
