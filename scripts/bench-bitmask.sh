#!/usr/bin/env bash
# wedges-bitmask against wedges-additive and wedges-blend, one run: frame time over the hard
# frame of the same scene and mean error against the reference (N = 256, seed 1: the same
# samples as bitmask at N = 256), at 512x512, bitmask at N = 32, 64, 128, 256, each with
# combine=counts (the default) and combine=parity. Writes
# $OUT/results.csv, $OUT/chart.png (error against frame time, Pareto front) and prints the table.
# Usage: bash scripts/bench-bitmask.sh [SCENE ...]  (default: the overlap scenes and kaos2)
# OUT defaults to out/bench-bitmask, SIZE to 512x512, FRAMES to 5.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >/dev/null
bash scripts/build.sh >/dev/null
if (($# == 0)); then
    set -- data/overlap.json data/plates-three.json data/bars-cross.json data/diamonds.json \
        data/spheres-nine.json data/torus-box.json data/torus.json ../shared/levels/kaos2.glb
fi
out=${OUT:-out/bench-bitmask}
build/bin/penumbra-bench "$@" --methods hard,wedges-additive,wedges-blend,wedges-bitmask \
    --sweep wedges-bitmask:samples=32,64,128,256 --sweep wedges-bitmask:combine=counts,parity \
    --size "${SIZE:-512x512}" \
    --truth reference --truth-samples 256 --frames "${FRAMES:-5}" --flicker-steps 0 --out "$out"
{ /usr/bin/python3 scripts/bench_table.py "$out/results.csv" --metric err
  /usr/bin/python3 scripts/bench_table.py "$out/results.csv" --metric speed; } | tee "$out/table.md"
