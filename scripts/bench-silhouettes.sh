#!/usr/bin/env bash
# Issue 3 benchmark: the per-frame CPU silhouette step (classification, groups, loops, side
# quads, wedges, bounds) on 10k-1M-triangle meshes and the OpenArena levels, one thread.
# Writes out/silhouette_bench.{json,txt,md}; the README table comes from the .md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
build/bin/silhouette_bench --benchmark_min_time=0.3 --benchmark_out=out/silhouette_bench.json \
    --benchmark_out_format=json | tee out/silhouette_bench.txt
/usr/bin/python3 scripts/silhouette_table.py out/silhouette_bench.json | tee out/silhouette_bench.md
