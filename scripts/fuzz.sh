#!/usr/bin/env bash
# Builds the libFuzzer targets (clang-14, ASan + UBSan; CMakePresets.json "fuzz", folder
# build-fuzz) and runs their CTests: fuzz.gltf and fuzz.scene_json, each for
# PENUMBRA_FUZZ_SECONDS seconds (default 20) from the seeds of scripts/make-fuzz-corpus.py.
# Fails on any crash, sanitizer report, leak, timeout or out-of-memory; the reproducer is left in
# build-fuzz/fuzz/run-<name>/artifacts/. docs/hardening.md, Fuzzing.
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake --preset fuzz "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_gltf fuzz_scene_json
# One at a time: each fuzzer gets the whole machine for its bounded time.
ctest --test-dir build-fuzz -R '^fuzz\.' --output-on-failure
