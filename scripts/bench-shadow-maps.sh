#!/usr/bin/env bash
# The source papers' shadow-map methods charted beside the others (issue: linear-light-sm, pdsm
# and deep-sm): penumbra-bench on the data/ scenes (the oak aside: its truth is raytrace) and
# the stability suite with linear-light-sm (1, 2, 4 and 8 linear lights), pdsm and deep-sm beside
# pcss, occlusion, sample-maps and wedges-bitmask (their defaults), against the GPU reference
# N = 1024 of the same view, flicker along a light sweep of FLICKER_STEPS steps (each step of pdsm
# and deep-sm builds its map again). Writes docs/bench-shadow-maps.md (the tables of
# scripts/bench_table.py) and docs/bench-shadow-maps.png (the bench's chart: frame time against
# error, a point per run).
# Usage: bash scripts/bench-shadow-maps.sh   (build first; OUT defaults to out/bench-shadow-maps,
# SIZE to 256x256, FLICKER_STEPS to 4, FRAMES to 5, WARMUP to 10: the untimed frames before
# them, the first of which builds what a method precomputes; on llvmpipe every pass of the ten
# or so frames after it runs slower, docs/methods/pdsm.md; TABLES_ONLY=1 writes the page and chart again
# from OUT's results without running the bench)
set -euo pipefail
cd "$(dirname "$0")/.."
root=${OUT:-out/bench-shadow-maps}
scenes=()
for f in data/*.json; do
    [[ "$f" == data/tree-oak.json ]] || scenes+=("$f")
done
if [ -z "${TABLES_ONLY:-}" ]; then
    build/bin/penumbra-bench "${scenes[@]}" data/stability \
        --methods pcss,occlusion,sample-maps,wedges-bitmask,linear-light-sm,pdsm,deep-sm \
        --sweep linear-light-sm:lights=1,2,4,8 --size "${SIZE:-256x256}" \
        --flicker-steps "${FLICKER_STEPS:-4}" --frames "${FRAMES:-5}" \
        --warmup "${WARMUP:-10}" --out "$root"
else
    /usr/bin/python3 apps/bench/chart.py "$root/results.csv" "$root/chart.png" \
        "$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["gl_renderer"])' \
            "$root/results.json")"
fi
machine=$(/usr/bin/python3 -c 'import json, sys
d = json.load(open(sys.argv[1]))
print("GL_RENDERER " + d["gl_renderer"] + ", CPU " + d["cpu"])' "$root/results.json")
{
    echo "<!-- written by scripts/bench-shadow-maps.sh; do not edit by hand -->"
    echo "penumbra-bench at ${SIZE:-256x256} on the data/ scenes and the stability suite (flicker"
    echo "over ${FLICKER_STEPS:-4} steps of the light sweep),"
    echo "against \`reference\` N = 1024; each method with its defaults, linear-light-sm at 1, 2,"
    echo "4 and 8 linear lights. Frame: the median of ${FRAMES:-5} timed frames after ${WARMUP:-10} warm-up"
    echo "frames, the first of which draws or builds the maps: pdsm's, deep-sm's and"
    echo "linear-light-sm's precompute is not in it (their own pages measure it). $machine."
    echo
    echo "![frame time against error](bench-shadow-maps.png)"
    echo
    /usr/bin/python3 scripts/bench_table.py "$root/results.csv"
} > docs/bench-shadow-maps.md
cp "$root/chart.png" docs/bench-shadow-maps.png
cat docs/bench-shadow-maps.md
