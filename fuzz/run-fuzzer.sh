#!/usr/bin/env bash
# Runs one fuzzer for a bounded time on fresh seeds: run-fuzzer.sh FUZZER KIND WORKDIR
# KIND is gltf or scene_json (which seeds and dictionary). WORKDIR is emptied first; what the run
# finds is left there (corpus/, artifacts/crash-*, fuzz.log). PENUMBRA_FUZZ_SECONDS (default 20)
# bounds the time; extra libFuzzer flags may come in PENUMBRA_FUZZ_FLAGS. Exits non-zero on any
# finding (libFuzzer's own exit code).
set -euo pipefail
fuzzer=$1 kind=$2 work=$3
here=$(cd "$(dirname "$0")" && pwd)
seconds=${PENUMBRA_FUZZ_SECONDS:-20}
case $kind in
    gltf) max_len=65536 ;;
    scene_json) max_len=8192 ;;
    *) echo "run-fuzzer: unknown kind $kind" >&2; exit 2 ;;
esac
rm -rf "$work"
mkdir -p "$work/corpus" "$work/artifacts"
/usr/bin/python3 "$here/../scripts/make-fuzz-corpus.py" --kind "$kind" --out "$work/seeds" >/dev/null
echo "run-fuzzer: $(basename "$fuzzer") for ${seconds} s on $(ls "$work/seeds" | wc -l) seeds"
# -detect_leaks stays on (the default with ASan): a leak is a finding too.
set +e
# shellcheck disable=SC2086
"$fuzzer" "$work/corpus" "$work/seeds" \
    -dict="$here/$kind.dict" -max_len=$max_len -rss_limit_mb=2048 -timeout=10 \
    -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="$work/artifacts/" \
    ${PENUMBRA_FUZZ_FLAGS:-} >"$work/fuzz.log" 2>&1
rc=$?
set -e
tail -n 25 "$work/fuzz.log"
if ((rc != 0)); then
    echo "run-fuzzer: FAILED (exit $rc); reproducer(s): $(ls "$work/artifacts")" >&2
    echo "run-fuzzer: replay with: $fuzzer $work/artifacts/<file>" >&2
fi
exit $rc
