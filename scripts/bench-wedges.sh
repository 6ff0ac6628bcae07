#!/usr/bin/env bash
# Wedge-method benchmark: per scene, the GPU reference (error baseline), then each method at
# 512x512 with --frames 5; prints a markdown table of frame time over the hard frame of the same
# run, per-pass GPU ms, wedge and fragment counts, and the error against the reference.
# Usage: bash scripts/bench-wedges.sh [SCENE ...]   (default: the demo, the overlap scenes, kaos2)
# Writes $OUT/<scene>/<method>/ and $OUT/table.md (OUT defaults to out/bench-wedges; FRAMES, the
# frames per method, to 5). Several runs into different OUTs can be summarised together:
# scripts/wedge_table.py OUT1 OUT2 ... -- METHODS prints per-run ratios and their median.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >/dev/null
bash scripts/build.sh >/dev/null
render=build/bin/penumbra-render
size=${SIZE:-512x512}
samples=${SAMPLES:-256}
methods=(${METHODS:-hard wedges-additive wedges-multiply wedges-blend})
if (($# == 0)); then
    set -- data/demo.json data/overlap.json data/plates-three.json data/bars-cross.json \
        data/spheres-nine.json data/torus-box.json ../shared/levels/kaos2.glb
fi
root=${OUT:-out/bench-wedges}
frames=${FRAMES:-5}
mkdir -p "$root"
for scene in "$@"; do
    [[ -f "$scene" ]] || { echo "bench-wedges: missing $scene" >&2; exit 2; }
    name=$(basename "${scene%.*}")
    echo "== $name: reference ($samples samples)" >&2
    "$render" --scene "$scene" --method reference --samples "$samples" --size "$size" \
        --out "$root/$name/reference" --quiet
    for m in "${methods[@]}"; do
        echo "== $name: $m" >&2
        "$render" --scene "$scene" --method "$m" --frames "$frames" --size "$size" \
            --out "$root/$name/$m" --compare "$root/$name/reference/visibility.pfm" --quiet
    done
done
/usr/bin/python3 scripts/wedge_table.py "$root" -- "${methods[@]}" | tee "$root/table.md"
