#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (CMakePresets.json
# "asan", docs/hardening.md › Sanitizers): configure, build into ./build-asan (clang-14, unity
# build; the libFuzzer targets of scripts/fuzz.sh are built there too), run every test, GL and
# viewer tests included, less the test preset's exclusions. Any sanitizer report fails the test it
# comes from. LeakSanitizer: `ctest --preset asan-leaks` by hand.
set -euo pipefail
cd "$(dirname "$0")/.."

launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
cmake --preset asan "${launcher[@]}" >/dev/null
cmake --build --preset asan -j"$(nproc)"
# The test preset sets CI=1 and the sanitizers' options (the suppressions file for third-party
# libraries' own leaks: tests/sanitizers/lsan.supp), and leaves out fuzz.* (scripts/fuzz.sh).
ctest --preset asan -j"$(nproc)"
