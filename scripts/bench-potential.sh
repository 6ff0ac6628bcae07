#!/usr/bin/env bash
# wedges-bitmask silhouettes=potential against the methods it replaces as the default, one run:
# every data/ scene and the stability suite's hard cases at SIZE (default 256x256), truth the GPU
# reference with N = 1024, mean |V - V_truth| and the frame over `hard`'s (median of FRAMES after
# a warm-up), plus the wedges drawn (potential vs the centre's silhouette).
# Writes docs/bench-potential.md. Usage: bash scripts/bench-potential.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
BIN=$BUILD/bin/penumbra-render
SIZE=${SIZE:-256x256}
FRAMES=${FRAMES:-5}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
source scripts/wedge-scenes.sh
scenes=("${wedge_scenes[@]}")
# name|method|params
variants=("hard|hard|" "blend|wedges-blend|" "centre 64|wedges-bitmask|silhouettes=centre"
          "samples 64|wedges-bitmask|estimate=samples" "ratio 64|wedges-bitmask|estimate=ratio"
          "quadrants 64|wedges-bitmask|estimate=quadrants" "moments 32|wedges-bitmask|samples=32"
          "moments 64|wedges-bitmask|" "moments 128|wedges-bitmask|samples=128")
rows=()
renderer=""
for scene in "${scenes[@]}"; do
    name=$(basename "$scene" .json)
    echo "== $name" >&2
    "$BIN" --scene "$scene" --method reference --samples 1024 --size "$SIZE" --out "$OUT/$name-ref" --quiet
    row="| $name |"
    hard=""
    for v in "${variants[@]}"; do
        IFS='|' read -r tag method params <<<"$v"
        args=()
        for p in $params; do args+=(--param "$p"); done
        dir="$OUT/$name-${tag// /-}"
        "$BIN" --scene "$scene" --method "$method" "${args[@]}" --size "$SIZE" --frames "$FRAMES" \
            --out "$dir" --compare "$OUT/$name-ref/visibility.pfm" --quiet
        read -r err ms wedges gl <<<"$(/usr/bin/python3 - "$dir/report.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
c = d["counters"]
print("%.4f %.3f %d %s" % (d["error"]["mean_abs_err"], d["frame_ms"], int(c.get("wedges", 0)),
                           d["gl_renderer"].replace(" ", "_")))
PY
)"
        renderer=$gl
        [ "$tag" = hard ] && hard=$ms
        ratio=$(/usr/bin/python3 -c "print('%.1f' % ($ms / $hard))")
        if [ "$method" = wedges-bitmask ] && [ "$tag" = "moments 64" -o "$tag" = "centre 64" ]; then
            row="$row $err / ${ratio}× ($wedges w) |"
        else
            row="$row $err / ${ratio}× |"
        fi
    done
    rows+=("$row")
done
{
    echo "<!-- written by scripts/bench-potential.sh; do not edit by hand -->"
    echo "Mean |V − V_truth| (truth: \`reference\` N = 1024) / frame over \`hard\`'s, $SIZE, median"
    echo "of $FRAMES frames after a warm-up; (w): wedges drawn. GL_RENDERER ${renderer//_/ }, CPU"
    echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //') ($(nproc) cores)."
    echo
    echo "| scene | hard | blend | bitmask centre 64 | potential, samples 64 | potential, ratio 64 | potential, quadrants 64 | potential, moments 32 | potential, moments 64 (default) | potential, moments 128 |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
    printf '%s\n' "${rows[@]}"
} > docs/bench-potential.md
cat docs/bench-potential.md
