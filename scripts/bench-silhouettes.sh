#!/usr/bin/env bash
# Issue 3 benchmark: the per-frame CPU silhouette step (classification, groups, loops, side
# quads, wedges, bounds) on 10k-1M-triangle meshes and the OpenArena levels, one thread: the full
# step and the lean one (SilhouetteSettings::lean()) side by side.
# Writes out/silhouette_bench.{json,txt,md}; the table of docs/benchmarks.md
# (§ Silhouettes) comes from the .md.
#
# SILHOUETTE_BASELINE=/path/to/silhouette_bench (another build, e.g. of an older revision:
# `git worktree add /tmp/base REV` and build its silhouette_bench target) also runs that build's
# full step on the same machine, right after, and adds it to the table with the lean/baseline
# ratio.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
build/bin/silhouette_bench --benchmark_min_time=0.3 --benchmark_out=out/silhouette_bench.json \
    --benchmark_out_format=json | tee out/silhouette_bench.txt
baseline=()
if [[ -n "${SILHOUETTE_BASELINE:-}" ]]; then
    "$SILHOUETTE_BASELINE" --benchmark_filter='silhouette_full/' --benchmark_min_time=0.3 \
        --benchmark_out=out/silhouette_bench_baseline.json --benchmark_out_format=json \
        | tee out/silhouette_bench_baseline.txt
    baseline=(--baseline out/silhouette_bench_baseline.json)
fi
/usr/bin/python3 scripts/silhouette_table.py out/silhouette_bench.json "${baseline[@]}" \
    | tee out/silhouette_bench.md
