#!/usr/bin/env bash
# Frames per second of penumbra-viewer flying through a level (docs/viewer.md): each
# method in turn flies the same path through the level's spawn points (--fly-through) at a modest
# size, with the light animated, in a real window (Xvfb when there is no display). Prints a
# markdown table: median frame (wall clock of the whole loop: render, UI, swap), fps, GPU frame
# from the timer queries, and the frame over hard's of the same run.
# Every method flies the same path: 6 legs between spawn points over its frames.
# usage: scripts/viewer-fps.sh [LEVEL.glb] [WxH] [FRAMES] [RENDER_SCALE]
set -euo pipefail
cd "$(dirname "$0")/.."
level=${1:-../shared/levels/kaos2.glb}
size=${2:-640x360}
frames=${3:-240}
scale=${4:-1}
out=out/viewer-fps
mkdir -p "$out"
viewer=build/bin/penumbra-viewer
[[ -x $viewer ]] || { echo "viewer-fps: build first (scripts/build.sh)" >&2; exit 1; }
run=()
if [[ -z ${DISPLAY:-} && -z ${WAYLAND_DISPLAY:-} ]]; then run=(xvfb-run -a -s "-screen 0 1920x1080x24"); fi
methods=(hard wedges-additive wedges-multiply wedges-blend wedges-bitmask occlusion pcss auto reference raytrace)
for m in "${methods[@]}"; do
    echo "viewer-fps: $m" >&2
    n=$frames
    [[ $m == reference || $m == raytrace ]] && n=$(( frames / 8 > 4 ? frames / 8 : 4 )) # seconds a frame
    "${run[@]}" "$viewer" "$level" --method "$m" --size "$size" --render-scale "$scale" --frames "$n" --fly-through \
        --leg-frames $(( n / 6 > 1 ? n / 6 : 1 )) --animate-light --samples 16 --report "$out/$m.json" \
        --screenshot "$out/$m.png" > "$out/$m.log"
done
/usr/bin/python3 - "$out" "${methods[@]}" <<'PY'
import json, sys
out, methods = sys.argv[1], sys.argv[2:]
rows = [(m, json.load(open(f"{out}/{m}.json"))) for m in methods]
hard = rows[0][1]["frame_ms_median"]
r0 = rows[0][1]
print(f"{r0['scene']}, window {r0['size'][0]}x{r0['size'][1]} rendered at "
      f"{r0['render_size'][0]}x{r0['render_size'][1]}, {r0['frames']} frames of --fly-through "
      f"(reference and raytrace: 1/8 of them) along its spawn points with the light animated; "
      f"{r0['gl_renderer']}, {r0['cpu']}\n")
print("| method | frame ms | fps | GPU frame ms | frame / hard |")
print("|---|---:|---:|---:|---:|")
for m, r in rows:
    note = " (16 samples)" if m in ("reference", "raytrace") else ""
    print(f"| {m}{note} | {r['frame_ms_median']:.1f} | {r['fps']:.1f} | "
          f"{r['gpu_frame_ms_median']:.1f} | {r['frame_ms_median'] / hard:.2f} |")
PY
