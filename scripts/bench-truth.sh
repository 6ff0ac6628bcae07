#!/usr/bin/env bash
# How much of a method's error against the benches' usual truth (`reference` N = 1024) is that
# reference's own: on the scenes where wedges-bitmask's default reads above 0.001 against it (and
# the big-light cases), everything measured against `reference` with TRUTH_SAMPLES (default
# 16384) samples of the same view instead, the N = 1024 reference among them. SIZE defaults to
# 256x256 (each truth takes about 1.5 min on 2 cores with llvmpipe).
# Writes docs/bench-truth.md. Usage: bash scripts/bench-truth.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
BIN=$BUILD/bin/penumbra-render
SIZE=${SIZE:-256x256}
N=${TRUTH_SAMPLES:-16384}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
scenes=(data/plates-three.json data/spheres-nine.json data/stability/sphere-grid.json
        data/stability/plates-stacked.json data/stability/open-nonmanifold.json
        data/stability/large-light-small-occluder.json data/stability/light-grazing.json)
# tag|method|params|samples
variants=("reference 1024|reference||1024" "blend|wedges-blend||"
          "quadrants|wedges-bitmask|estimate=quadrants|" "moments (default)|wedges-bitmask||")
rows=()
renderer=""
for scene in "${scenes[@]}"; do
    name=$(basename "$scene" .json)
    echo "== $name (reference N = $N)" >&2
    "$BIN" --scene "$scene" --method reference --samples "$N" --size "$SIZE" --out "$OUT/$name-truth" --quiet
    row="| $name |"
    for v in "${variants[@]}"; do
        IFS='|' read -r tag method params samples <<<"$v"
        args=()
        for p in $params; do args+=(--param "$p"); done
        [ -n "$samples" ] && args+=(--samples "$samples")
        dir="$OUT/$name-${tag%% *}"
        "$BIN" --scene "$scene" --method "$method" "${args[@]}" --size "$SIZE" --out "$dir" \
            --compare "$OUT/$name-truth/visibility.pfm" --quiet
        IFS=$'\t' read -r cell gl <<<"$(/usr/bin/python3 - "$dir/report.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
e = d["error"]
print("%.5f (%.2f%%)\t%s" % (e["mean_abs_err"], e["bad_pixel_pct"], d["gl_renderer"].replace(" ", "_")))
PY
)"
        renderer=$gl
        row="$row $cell |"
    done
    rows+=("$row")
done
{
    echo "<!-- written by scripts/bench-truth.sh; do not edit by hand -->"
    echo "Mean |V − V_truth| (share of pixels off by more than 0.05) with the truth \`reference\`"
    echo "N = $N, $SIZE; wedges-bitmask at its default N = 64. The first column is the benches' usual"
    echo "truth, \`reference\` N = 1024, against this one: its own error. GL_RENDERER ${renderer//_/ }, CPU"
    echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //') ($(nproc) cores)."
    echo
    echo "| scene | reference N = 1024 | wedges-blend | wedges-bitmask estimate=quadrants | wedges-bitmask (default: estimate=moments) |"
    echo "|---|---|---|---|---|"
    printf '%s\n' "${rows[@]}"
} > docs/bench-truth.md
cat docs/bench-truth.md
