#!/usr/bin/env bash
# The shared levels as a player sees them: penumbra-viewer at spawn cameras (CAMERAS, default
# "0 2": the first and third) with its lamp under the ceiling ahead (the viewer's default),
# 320x180, against `raytrace` with TRUTH_SAMPLES (default 4096) light samples of the same view
# (alpha-aware: it tests the textured levels' grates and flames). Both sets of levels: the
# untextured ones and ../shared/levels/textured/ (the same triangles with their game materials).
# Per method: mean |V - V_truth| over the pixels with a surface, the pixels off by more than
# 0.05, and the frame (median of 4) over `hard`'s of the same view; then each view's frames
# of hard and auto, textured against untextured, ROUNDS (default 3) rounds alternating.
# Writes docs/levels-lamp.md. Usage: bash scripts/levels-lamp.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
viewer=$BUILD/bin/penumbra-viewer
N=${TRUTH_SAMPLES:-4096}
CAMERAS=${CAMERAS:-0 2}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
run=()
if [[ -z ${DISPLAY:-} && -z ${WAYLAND_DISPLAY:-} ]]; then run=(xvfb-run -a -s "-screen 0 640x480x24"); fi
methods=(hard wedges-blend wedges-bitmask occlusion pcss auto)
rows=()
for set in "" textured/; do
for level in kaos2 oa_dm1 oa_dm4 oa_dm5; do
  for camera in $CAMERAS; do
    glb=../shared/levels/$set$level.glb
    view=${set%/}$level-$camera
    echo "== $set$level camera $camera (raytrace N = $N)" >&2
    "${run[@]}" "$viewer" "$glb" --camera "$camera" --method raytrace --samples "$N" --size 320x180 \
        --frames 1 --hide-ui --visibility "$OUT/$view-truth.pfm" --report "$OUT/$view-truth.json" >/dev/null
    for m in "${methods[@]}"; do
        "${run[@]}" "$viewer" "$glb" --camera "$camera" --method "$m" --size 320x180 --frames 4 \
            --hide-ui --visibility "$OUT/$view-$m.pfm" --report "$OUT/$view-$m.json" >/dev/null
    done
    rows+=("$(/usr/bin/python3 - "$OUT" "$view" "${set:+textured }$level, camera $camera" "${methods[@]}" <<'PY'
import json, sys
import numpy as np
out, view, name, methods = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
sys.path.insert(0, "scripts")
from pfm import read_pfm
def pfm(path):
    return read_pfm(path)[..., 0]
truth = pfm(f"{out}/{view}-truth.pfm")
hard = json.load(open(f"{out}/{view}-hard.json"))["frame_ms_median"]
cells = []
for m in methods:
    v = pfm(f"{out}/{view}-{m}.pfm")
    both = np.isfinite(v) & np.isfinite(truth) # (no surface: NaN in both)
    if (np.isfinite(v) != np.isfinite(truth)).any():
        sys.exit(f"{view} {m}: surface coverage differs from the truth's")
    d = np.abs(v - truth)[both]
    ms = json.load(open(f"{out}/{view}-{m}.json"))["frame_ms_median"]
    cells.append("%.5f (%d) / %.1f×" % (d.mean(), int((d > 0.05).sum()), ms / hard))
print("| %s | %s |" % (name, " | ".join(cells)))
PY
)")
  done
done
done
# Textured against untextured on the same run: hard and auto on each view, the two levels
# alternating, ROUNDS (default 3) rounds; the table takes each one's median over the rounds.
ROUNDS=${ROUNDS:-3}
for level in kaos2 oa_dm1 oa_dm4 oa_dm5; do
  for camera in $CAMERAS; do
    echo "== $level camera $camera: frames, untextured and textured alternating" >&2
    for r in $(seq "$ROUNDS"); do
      for set in "" textured/; do
        for m in hard auto; do
          "${run[@]}" "$viewer" ../shared/levels/$set$level.glb --camera "$camera" --method "$m" \
              --size 320x180 --frames 4 --hide-ui --report "$OUT/ab-${set%/}$level-$camera-$m-$r.json" >/dev/null
        done
      done
    done
  done
done
first=${CAMERAS%% *}
renderer=$(/usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['gl_renderer'] + ', CPU ' + d['cpu'])" "$OUT/kaos2-$first-hard.json")
{
    echo "<!-- written by scripts/levels-lamp.sh; do not edit by hand -->"
    echo "The shared levels from spawn cameras (\`--camera N\`) with the viewer's lamp, 320×180: mean"
    echo "|V − V_truth| over the pixels with a surface (pixels off by > 0.05) / frame over \`hard\`'s"
    echo "(median of 4 frames). Truth: \`raytrace\` N = $N of the same view (alpha-aware). On the"
    echo "textured levels a method that occludes with whole triangles shadows the opaque part and"
    echo "auto's alpha path the alpha-tested one (pcss: on these levels it surrounds the lamp, so sample maps cannot hold it). GL_RENDERER $renderer ($(nproc) cores)."
    echo
    echo "| view |$(printf ' %s |' "${methods[@]}")"
    echo "|---|$(printf -- '---|%.0s' "${methods[@]}")"
    printf '%s\n' "${rows[@]}"
    echo
    echo "The same views' frames in milliseconds, textured level against untextured: what the game"
    echo "materials (G-buffer textures, the alpha-tested part's shadows) add. Each the median over"
    echo "$ROUNDS rounds (the two levels alternating) of a median of 4 frames."
    echo
    /usr/bin/python3 - "$OUT" "$CAMERAS" "$ROUNDS" <<'PY'
import json, statistics, sys
out, cameras, rounds = sys.argv[1], sys.argv[2].split(), int(sys.argv[3])
ms = lambda view, m: statistics.median(
    json.load(open(f"{out}/ab-{view}-{m}-{r}.json"))["frame_ms_median"]
    for r in range(1, rounds + 1))
print("| view | hard: untextured / textured | auto: untextured / textured |")
print("|---|---|---|")
for level in ["kaos2", "oa_dm1", "oa_dm4", "oa_dm5"]:
    for c in cameras:
        cells = []
        for m in ["hard", "auto"]:
            a, b = ms(f"{level}-{c}", m), ms(f"textured{level}-{c}", m)
            cells.append("%.1f / %.1f ms (%.2f×)" % (a, b, b / a))
        print("| %s, camera %s | %s |" % (level, c, " | ".join(cells)))
PY
} > docs/levels-lamp.md
cat docs/levels-lamp.md
