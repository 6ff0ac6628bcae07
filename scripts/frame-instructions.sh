#!/usr/bin/env bash
# The instructions one frame of METHOD executes, this tree against an earlier commit, counted
# under valgrind (cachegrind without its cache model) with llvmpipe on one thread: a number
# that does not move between runs, where wall time on a shared machine moves by 10-30 % (the
# frame benches need many alternating rounds to see a few per cent). It measures work, not
# time: memory latency and how well the threads share the frame are not in it, so it says
# whether a change does less, not how much sooner the frame ends (bench-commit.sh does).
# Per view and build: one run to fill Mesa's shader cache, then 1 and 6 frames (after the
# warm-up frame; measured again where the six frames do not count more, up to three times,
# else the view has no number); the per-frame count is their difference over 5. About a minute per run at
# 256²; VIEWS (default: the wedge benches' views) and JOBS (default 2) in parallel.
# Writes docs/frame-instructions.md (DOC: another file). BASELINE=METHOD also counts that method
# on this tree, as a column beside (e.g. METHOD=pdsm BASELINE=hard: the soft frame over the hard
# one in instructions). Usage: bash scripts/frame-instructions.sh COMMIT [build-dir]
# Needs valgrind (the Debian package of that name; not needed to build or test).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ]; then
    echo "usage: bash scripts/frame-instructions.sh COMMIT [build-dir]" >&2
    exit 2
fi
command -v valgrind >/dev/null || { echo "frame-instructions: needs valgrind (apt-get install valgrind)" >&2; exit 2; }
COMMIT=$(git rev-parse --verify "$1^{commit}") || { echo "frame-instructions: no commit '$1'" >&2; exit 2; }
BUILD=${2:-build}
BIN=$(realpath -m "$BUILD/bin/penumbra-render")
METHOD=${METHOD:-wedges-bitmask}
SIZE=${SIZE:-256x256}
JOBS=${JOBS:-2}
DOC=${DOC:-docs/frame-instructions.md}
BASELINE=${BASELINE:-}
[ -x "$BIN" ] || { echo "frame-instructions: build this tree first ($BIN missing)" >&2; exit 2; }
source scripts/commit-build.sh
commit_begin "$COMMIT" "$BUILD"
source scripts/wedge-scenes.sh
wedge_selected_views

# count BIN VIEW TAG [METHOD]: the per-frame instructions in millions, into $OUT/TAG.
count() {
    local bin=$1 entry=$2 tag=$3 method=${4:-$METHOD}
    wedge_view "$entry"
    run() {
        LP_NUM_THREADS=0 valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null \
            --smc-check=all "$bin" --scene "$scene" "${camera[@]}" --method "$method" \
            --size "$2" --frames "$1" --out "$OUT/$tag.render" --quiet 2>&1 |
            sed -n 's/.*I *refs: *//p' | tr -d ,
    }
    # The shader cache filled at the measured size: a program first compiled in the one-frame
    # run (a variant a smaller frame does not take) would count its compilation there and not
    # in the six-frame run, and the difference would come out short (an earlier 64x64 warm-up
    # gave 5c2f487^ 267 M on light-grazing once, 377 M on every run since).
    # One warm-up run has not always been enough (the first count after a shader changed came
    # out with the six-frame run below the one-frame run: a compilation counted in the one-frame
    # run only): a pair whose six-frame run does not count more is measured again, up to three
    # times, and the view reported as failed (no number) after that.
    run 1 "$SIZE" >/dev/null
    local one six try
    for try in 1 2 3; do
        one=$(run 1 "$SIZE")
        six=$(run 6 "$SIZE")
        [ -n "$one" ] && [ -n "$six" ] || break
        if [ "$six" -gt "$one" ]; then
            /usr/bin/python3 -c 'import sys; print((int(sys.argv[2]) - int(sys.argv[1])) / 5e6)' "$one" "$six" >"$OUT/$tag"
            return
        fi
        echo "frame-instructions: $tag counted $six instructions in 6 frames, $one in 1; again" >&2
    done
    echo "frame-instructions: $tag failed" >&2
    echo nan >"$OUT/$tag"
}
export -f count wedge_view
export OUT METHOD SIZE
jobs=()
for i in "${!views[@]}"; do
    jobs+=("$OLD ${views[$i]} old-$i" "$BIN ${views[$i]} new-$i")
    [ -z "$BASELINE" ] || jobs+=("$BIN ${views[$i]} base-$i $BASELINE")
done
printf '%s\n' "${jobs[@]}" | xargs -P "$JOBS" -L 1 bash -c 'count "$0" "$1" "$2" "$3"; echo "== $2 ${1}" >&2'

rows=()
for i in "${!views[@]}"; do
    wedge_view "${views[$i]}"
    base=nan
    [ -z "$BASELINE" ] || base=$(cat "$OUT/base-$i")
    rows+=("$(/usr/bin/python3 - "$name" "$(cat "$OUT/old-$i")" "$(cat "$OUT/new-$i")" "$base" "$BASELINE" <<'PY'
import math, sys
name, old, new, base = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
ratio = lambda a, b: "—" if math.isnan(a) or math.isnan(b) else f"{a / b:.3f}"
fmt = lambda v: "—" if math.isnan(v) else f"{v:.0f}"
extra = f" {fmt(base)} | {ratio(old, base)} | {ratio(new, base)} |" if sys.argv[5] else ""
print(f"| {name} | {fmt(old)} | {fmt(new)} | {ratio(new, old)} |{extra}")
PY
)")
done
{
    echo "<!-- written by scripts/frame-instructions.sh; do not edit by hand -->"
    subject=$(commit_subject "$COMMIT")
    echo "Instructions per frame of \`$METHOD\` at $SIZE (millions; valgrind's count, llvmpipe on one"
    echo "thread), $short (\"old\": $subject) against this tree"
    echo "(\"new\", $(tree_name "$DOC"))."
    [ -z "$BASELINE" ] || echo "Beside them, \`$BASELINE\` on this tree, and each frame over its."
    renderer=$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["gl_renderer"])' "$OUT/new-0.render/report.json")
    echo "GL_RENDERER $renderer, CPU $(cpu_name)."
    echo
    if [ -z "$BASELINE" ]; then
        echo "| view | old | new | new / old |"
        echo "|---|---|---|---|"
    else
        echo "| view | old | new | new / old | $BASELINE | old / $BASELINE | new / $BASELINE |"
        echo "|---|---|---|---|---|---|---|"
    fi
    printf '%s\n' "${rows[@]}"
} >"$DOC"
cat "$DOC"
