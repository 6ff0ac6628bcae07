#!/usr/bin/env bash
# Every spawn view of the shared levels, untextured and textured: penumbra-bench --cameras all
# (each glTF camera lit by the viewer's lamp), 320x180, against alpha-aware `raytrace` with
# TRUTH_SAMPLES (default 4096) light samples, methods hard, wedges-bitmask, pcss, occlusion
# and auto. Then the real-levels targets checked on every view (scripts/levels_spawn_table.py):
# auto's mean error <= 0.002, never worse than hard's on the untextured levels, within 10 % of
# the view's best method; pcss and occlusion within hard + 0.01. Frames are the bench's
# (median of FRAMES, default 4, one run): docs/levels-lamp.md compares frames over rounds.
# Writes docs/levels-spawn-all.md. Usage: bash scripts/levels-spawn-all.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
N=${TRUTH_SAMPLES:-4096}
OUT=${OUT:-out/levels-spawn-all}
rm -rf "$OUT"
scenes=()
for set in "" textured/; do
    for level in kaos2 oa_dm1 oa_dm4 oa_dm5; do scenes+=("../shared/levels/$set$level.glb"); done
done
"$BUILD/bin/penumbra-bench" "${scenes[@]}" --cameras all \
    --methods hard,wedges-bitmask,pcss,occlusion,auto --truth raytrace --truth-samples "$N" \
    --size 320x180 --frames "${FRAMES:-4}" --warmup 1 --flicker-steps 0 --no-chart --out "$OUT"
/usr/bin/python3 scripts/levels_spawn_table.py "$OUT/results.json" >docs/levels-spawn-all.md
echo "wrote docs/levels-spawn-all.md" >&2
