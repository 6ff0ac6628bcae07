#!/usr/bin/env bash
# Foliage benchmark (docs/methods/sample-maps.md): the alpha paths on the shared trees.
# - each shared tree alone (its own framing) at SIZE (default 200x200): alpha-aware raytrace
#   N = 1024 as the truth, then sample-maps (default and variants), pcss, occlusion and raytrace
#   N = 64 (the sampling error of 64 samples alone), each --frames 5; the error is the mean
#   |dV| over the tree's pixels (those with a surface: the tree is all there is);
# - data/tree-oak.json at 256x256: auto with each alpha path against raytrace N = 1024 over
#   every pixel, and the frame of hard with the oak removed ("method": "none") for the ratio,
#   ROUNDS (default 3) rounds alternating, frames the medians over the rounds.
# Prints one markdown table per part, with GL_RENDERER and the CPU.
# Usage: bash scripts/bench-foliage.sh   (build penumbra-render first; OUT defaults to out/bench-foliage)
set -euo pipefail
cd "$(dirname "$0")/.."
render=build/bin/penumbra-render
root=${OUT:-out/bench-foliage}
size=${SIZE:-200x200}
trees=(oak_hungarian_1 palm_date_new_1)
variants=("sample-maps" "sample-maps resolution=1024" "sample-maps samples=128"
          "sample-maps bias=0.0" "sample-maps bias=1.0" "pcss" "occlusion")
mkdir -p "$root"
for t in "${trees[@]}"; do
    echo "== $t" >&2
    scene=../shared/foliage/$t.glb
    "$render" --scene "$scene" --method raytrace --samples 1024 --size $size --out $root/$t/truth --quiet
    "$render" --scene "$scene" --method raytrace --samples 64 --size $size --out $root/$t/raytrace-64 --quiet
    for v in "${variants[@]}"; do
        read -r m p <<<"$v"
        args=()
        [ -n "${p:-}" ] && args=(--param "$p")
        "$render" --scene "$scene" --method $m "${args[@]}" --frames 5 --size $size \
            --out "$root/$t/${v// /-}" --quiet
    done
done
echo "== tree-oak.json" >&2
o=$root/tree-oak
"$render" --scene data/tree-oak.json --method raytrace --samples 1024 --size 256x256 --out $o/truth --quiet
sed 's|"file": "../../shared/foliage/oak_hungarian_1.glb"}|"file": "../../shared/foliage/oak_hungarian_1.glb", "method": "none"}|' \
    data/tree-oak.json > $root/tree-oak-none.json
# the file's relative path resolves from the scene's directory: keep it beside data/
cp $root/tree-oak-none.json data/.tree-oak-none.json
# ROUNDS (default 3) rounds, the four frames alternating; the table takes medians over them.
for r in $(seq "${ROUNDS:-3}"); do
    for a in sample-maps pcss occlusion; do
        "$render" --scene data/tree-oak.json --method auto --param alpha=$a --frames 5 --size 256x256 \
            --out $o/auto-$a-r$r --compare $o/truth/visibility.pfm --quiet
    done
    "$render" --scene data/.tree-oak-none.json --method hard --frames 5 --size 256x256 \
        --out $o/hard-no-oak-r$r --quiet
done
rm -f data/.tree-oak-none.json
/usr/bin/python3 scripts/foliage_table.py "$root" "${trees[@]}" -- "${variants[@]}"
