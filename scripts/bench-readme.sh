#!/usr/bin/env bash
# The bench run of docs/benchmarks.md: every real-time method on the overlap scenes of data/,
# the stability suite (data/stability/) and two OpenArena levels (from their first spawn camera
# with the viewer's lamp, the bench's default), against the GPU reference of the same view, with
# flicker along a light sweep; then the foliage scene against raytrace (the reference occludes
# with whole triangles, so the bench refuses it as the truth of alpha-tested casters). Prints the markdown tables of scripts/bench_table.py
# (also written to $OUT/tables.md); they go into docs/benchmarks.md, § Every method.
# Usage: bash scripts/bench-readme.sh   (OUT defaults to out/bench-readme; SIZE to 256x256,
# TRUTH_SAMPLES to 1024, FLICKER_STEPS to 6, FRAMES to 5). Took 7 min on 2 Intel Xeon cores and
# about an hour on 2 AMD EPYC cores (llvmpipe).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >/dev/null
bash scripts/build.sh >/dev/null
root=${OUT:-out/bench-readme}
common=(--size "${SIZE:-256x256}" --truth-samples "${TRUTH_SAMPLES:-1024}"
        --flicker-steps "${FLICKER_STEPS:-6}" --frames "${FRAMES:-5}" --save-images)
scenes=()
for f in data/*.json; do
    [[ "$f" == data/tree-oak.json ]] || scenes+=("$f")
done
build/bin/penumbra-bench "${scenes[@]}" data/stability ../shared/levels/kaos2.glb \
    ../shared/levels/oa_dm4.glb "${common[@]}" --out "$root/main"
build/bin/penumbra-bench data/tree-oak.json --truth raytrace "${common[@]}" --out "$root/foliage"
for run in main foliage; do
    echo "## $run"
    /usr/bin/python3 scripts/bench_table.py "$root/$run/results.csv"
done | tee "$root/tables.md"
