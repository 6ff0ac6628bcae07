#!/usr/bin/env bash
# This tree's frames against an earlier commit's, built side by side and run alternately on the
# same machine: the wedge benches' scenes (scripts/wedge-scenes.sh) and two levels' spawn views,
# 256x256. Per round, four runs: `hard` (this tree), METHOD at COMMIT ("old"), METHOD here
# ("new") and METHOD here with EXTRA parameters ("variant"; default silhouettes=centre, the
# wedges-bitmask of before per-receiver silhouettes). Each run's frame is the median of its
# FRAMES frames (default 30: the first, which compiles the shaders, and the ten or so after it
# that llvmpipe runs slower are fewer than half of them; an older build has no --warmup); the table gives medians over ROUNDS rounds (default 5) of the ratios
# within each round; VIEWS (file or file@camera, space-separated) measures those views only.
# Writes docs/bench-commit.md.
# Usage: bash scripts/bench-commit.sh COMMIT [build-dir]
#   COMMIT: what to compare with (the issue's frame target: 5c2f487^, the method when
#   per-receiver silhouettes were asked for). Its penumbra-render is built Release in a git
#   worktree under build-dir/commit-<sha> (removed afterwards unless KEEP=1, which also reuses
#   one already built).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ]; then
    echo "usage: bash scripts/bench-commit.sh COMMIT [build-dir]" >&2
    exit 2
fi
COMMIT=$(git rev-parse --verify "$1^{commit}") || { echo "bench-commit: no commit '$1'" >&2; exit 2; }
BUILD=${2:-build}
BIN=$BUILD/bin/penumbra-render
METHOD=${METHOD:-wedges-bitmask}
EXTRA=${EXTRA:-silhouettes=centre}
SIZE=${SIZE:-256x256}
FRAMES=${FRAMES:-30}
ROUNDS=${ROUNDS:-5}
[ -x "$BIN" ] || { echo "bench-commit: build this tree first ($BIN missing)" >&2; exit 2; }

source scripts/commit-build.sh
commit_begin "$COMMIT" "$BUILD"

source scripts/wedge-scenes.sh
extra=()
for p in $EXTRA; do extra+=(--param "$p"); done
rows=()
renderer=""
wedge_selected_views
for entry in "${views[@]}"; do
    wedge_view "$entry"
    echo "== $name" >&2
    : >"$OUT/rounds.txt"
    for round in $(seq "$ROUNDS"); do
        line=""
        for tag in hard old new variant; do
            bin=$BIN
            args=(--method "$METHOD")
            case $tag in
                hard) args=(--method hard) ;;
                old) bin=$OLD ;;
                variant) args+=("${extra[@]}") ;;
            esac
            # (A scene the older build cannot read is a dash in its column, not a failure.)
            if "$bin" --scene "$scene" "${camera[@]}" "${args[@]}" --size "$SIZE" \
                --frames "$FRAMES" --out "$OUT/$tag" --quiet 2>"$OUT/$tag.err"; then
                line+=" $(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["frame_ms"])' "$OUT/$tag/report.json")"
            elif [ "$tag" = old ]; then
                line+=" nan"
            else
                cat "$OUT/$tag.err" >&2
                exit 1
            fi
        done
        echo "$line" >>"$OUT/rounds.txt"
    done
    renderer=$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["gl_renderer"])' "$OUT/hard/report.json")
    rows+=("$(/usr/bin/python3 - "$OUT/rounds.txt" "$name" <<'PY'
import math, statistics, sys
rows = [[float(x) for x in l.split()] for l in open(sys.argv[1])]
name = sys.argv[2]
def med(f):
    values = [f(r) for r in rows]
    values = [v for v in values if not math.isnan(v)]
    return statistics.median(values) if values else math.nan
def cell(v, fmt):
    return "—" if math.isnan(v) else fmt.format(v)
print(f"| {name} | {med(lambda r: r[0]):.1f} | {cell(med(lambda r: r[1] / r[0]), '{:.1f}×')} "
      f"| {med(lambda r: r[2] / r[0]):.1f}× | {med(lambda r: r[3] / r[0]):.1f}× "
      f"| {cell(med(lambda r: r[2] / r[1]), '{:.2f}')} | {cell(med(lambda r: r[3] / r[1]), '{:.2f}')} "
      f"| {med(lambda r: r[2] / r[3]):.2f} |")
PY
)")
done
{
    echo "<!-- written by scripts/bench-commit.sh; do not edit by hand -->"
    subject=$(commit_subject "$COMMIT")
    echo "\`$METHOD\` at $short (\"old\", $(git log -1 --format='%ad' --date=short "$COMMIT"): $subject)"
    echo "against this tree's (\"new\", $(tree_name docs/bench-commit.md)) and this tree's with \`$EXTRA\` (\"variant\"),"
    echo "both built Release and run alternately, $SIZE: frame over this tree's \`hard\` of the same round,"
    echo "and ratios, medians of $ROUNDS rounds (each run the median of its $FRAMES frames, the first among them)."
    echo "GL_RENDERER $renderer, CPU $(cpu_name) ($(nproc) cores)."
    echo
    echo "| view | hard ms | old / hard | new / hard | variant / hard | new / old | variant / old | new / variant |"
    echo "|---|---|---|---|---|---|---|---|"
    printf '%s\n' "${rows[@]}"
} >docs/bench-commit.md
cat docs/bench-commit.md
