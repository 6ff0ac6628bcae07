#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer + LeakSanitizer
# (CMakePresets.json "asan", docs/hardening.md › Sanitizers): configure, build into ./build-asan,
# run every test, GL and viewer tests included. Any sanitizer report fails the test it comes from.
set -euo pipefail
cd "$(dirname "$0")/.."

launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
cmake --preset asan "${launcher[@]}" >/dev/null
cmake --build --preset asan -j"$(nproc)"
# The test preset sets CI=1 and the sanitizers' options (the suppressions file for third-party
# libraries' own leaks: tests/sanitizers/lsan.supp).
ctest --preset asan -j"$(nproc)"
