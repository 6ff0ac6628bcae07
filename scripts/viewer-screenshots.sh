#!/usr/bin/env bash
# The viewer screenshots of docs/viewer.md, made by penumbra-viewer's automation mode (--frames N
# --screenshot FILE) in a real window (Xvfb when there is no display): docs/viewer/*.png.
set -euo pipefail
cd "$(dirname "$0")/.."
viewer=build/bin/penumbra-viewer
[[ -x $viewer ]] || { echo "viewer-screenshots: build first (scripts/build.sh)" >&2; exit 1; }
run=()
if [[ -z ${DISPLAY:-} && -z ${WAYLAND_DISPLAY:-} ]]; then run=(xvfb-run -a -s "-screen 0 1920x1080x24"); fi
mkdir -p docs/viewer
kaos2=../shared/levels/kaos2.glb
dm4=../shared/levels/oa_dm4.glb
# kaos2 at its first spawn point with the panel, wedges-blend; then the stats overlay only.
"${run[@]}" "$viewer" "$kaos2" --method wedges-blend --size 960x540 --frames 3 \
    --screenshot docs/viewer/kaos2-panel.png
"${run[@]}" "$viewer" "$kaos2" --method wedges-blend --size 960x540 --camera 4 --frames 3 \
    --keys 1:Tab --screenshot docs/viewer/kaos2-spawn4.png
# oa_dm4: shadow volumes' stencil count and the error heat map against the progressive reference
# (64 frames of 16 samples: the 1024-sample reference complete).
"${run[@]}" "$viewer" "$dm4" --method hard --size 640x360 --camera 2 --frames 3 \
    --debug-view stencil --keys 1:Tab --screenshot docs/viewer/oa_dm4-stencil.png
"${run[@]}" "$viewer" "$dm4" --method wedges-blend --size 640x360 --camera 2 --frames 64 \
    --samples 1024 --debug-view error --keys 1:Tab --screenshot docs/viewer/oa_dm4-error.png
echo "wrote docs/viewer/{kaos2-panel,kaos2-spawn4,oa_dm4-stencil,oa_dm4-error}.png"
