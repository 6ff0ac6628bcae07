#!/usr/bin/env bash
# README command 2 (and .ci/run): install what is missing, build, run every test.
# GL tests render on a surfaceless EGL context (Mesa llvmpipe without a GPU); with CI set they
# fail rather than skip when no context can be created.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 300
# One instrumented build (clang-14, ASan + UBSan, build-asan) serves both of these: fuzz.sh builds
# the geometry library, tinygltf and the fuzz targets in it, sanitize.sh the rest.
bash ../scripts/fuzz.sh # libFuzzer on the loaders, bounded (docs/hardening.md, Fuzzing)
bash ../scripts/sanitize.sh  # the same suite under ASan + UBSan (docs/hardening.md, Sanitizers)
