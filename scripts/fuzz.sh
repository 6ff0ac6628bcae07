#!/usr/bin/env bash
# Builds the libFuzzer targets and runs their CTests: fuzz.gltf and fuzz.scene_json, each for
# PENUMBRA_FUZZ_SECONDS seconds (default 20) from the seeds of scripts/make-fuzz-corpus.py.
# The fuzz targets live in the sanitizer build (CMakePresets.json "fuzz" is "asan": clang-14,
# ASan + UBSan, folder build-asan), so after scripts/sanitize.sh there is nothing left to build;
# alone, it builds only the instrumented geometry library, tinygltf and the two targets.
# Fails on any crash, sanitizer report, leak, timeout or out-of-memory; the reproducer is left in
# build-asan/fuzz/run-<name>/artifacts/. docs/hardening.md, Fuzzing.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake --preset fuzz "${launcher[@]}" >/dev/null
cmake --build --preset fuzz -j"$(nproc)"
# One at a time: each fuzzer gets the whole machine for its bounded time. LeakSanitizer stays on
# (ASan's default; the asan test preset's detect_leaks=0 is not used here).
ctest --preset fuzz
