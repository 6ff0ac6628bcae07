#!/usr/bin/env bash
# README command 1: install what is missing, build, render the demo scene with the GPU reference
# and with hard shadow volumes, and print timing and error of the latter against the former.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
render=build/bin/penumbra-render
scene=data/demo.json
echo "== reference: 256 stratified hard-shadow passes =="
"$render" --scene "$scene" --method reference --samples 256 --size 512x512 --out out/demo-reference
echo "== hard shadow volumes, error against the reference =="
"$render" --scene "$scene" --method hard --frames 5 --size 512x512 --out out/demo-hard \
    --compare out/demo-reference/visibility.pfm
echo "images: out/demo-reference/image.png out/demo-hard/image.png"
