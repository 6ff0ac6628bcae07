#!/usr/bin/env bash
# Flicker along the bench's light sweep (penumbra-bench: the light's centre moved along u; per
# pair of neighbouring positions the mean |(V[k+1] - V[k]) - (T[k+1] - T[k])|, T the truth's, as
# DESIGN.md §5 defines it) and the mean error, for wedges-bitmask
# (silhouettes=potential, the default, and silhouettes=centre) against wedges-blend and hard, on
# every data/ scene and the stability suite. Writes docs/bench-flicker.md.
# Usage: bash scripts/bench-flicker.sh [build-dir]   (SIZE defaults to 128x128, STEPS to 6, truth
# the GPU reference with TRUTH_SAMPLES = 16384: against N = 1024 the truth's own sampling noise
# was most of the measure where a method is near exact, 0.0009 of plates-three's 0.0002-0.0003,
# and decided which of two such methods read the lower; about 30 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
SIZE=${SIZE:-128x128}
STEPS=${STEPS:-6}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
scenes=()
for f in data/*.json; do
    [[ "$f" == data/tree-oak.json ]] || scenes+=("$f")
done
"$BUILD/bin/penumbra-bench" "${scenes[@]}" data/stability --methods wedges-blend,wedges-bitmask \
    --sweep wedges-bitmask:silhouettes=potential,centre --size "$SIZE" --flicker-steps "$STEPS" \
    --truth-samples "${TRUTH_SAMPLES:-16384}" --frames 1 --no-chart --out "$OUT" 2> "$OUT/log.txt"
renderer=$(grep -m1 -o 'on .*; truth' "$OUT/log.txt" | sed 's/^on //; s/; truth$//')
{
    echo "<!-- written by scripts/bench-flicker.sh; do not edit by hand -->"
    echo "Flicker along the light sweep ($((STEPS + 1)) positions, the light's centre moved along u"
    echo "by one half-width each way) and mean |V − V_truth| (truth: \`reference\` N ="
    echo "${TRUTH_SAMPLES:-16384} at each position), $SIZE. GL_RENDERER $renderer, CPU"
    echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //') ($(nproc) cores)."
    echo
    # The bitmask columns by their swept parameter alone.
    for metric in flicker err; do
        /usr/bin/python3 scripts/bench_table.py "$OUT/results.csv" --metric "$metric" |
            sed -E 's/wedges-bitmask samples=64 pattern=fixed combine=counts silhouettes=(potential|centre)( [a-z_]+=[a-z0-9]+)*/wedges-bitmask \1/g'
        echo
    done
} > docs/bench-flicker.md
cat docs/bench-flicker.md
