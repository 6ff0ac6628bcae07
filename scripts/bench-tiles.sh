#!/usr/bin/env bash
# wedges-bitmask's wedge pass two ways, one run: evaluate=raster (the hulls rasterised, one
# fragment per pixel and wedge) against evaluate=tiles (the wedges binned to 8x8 pixel tiles
# whose surface they may reach, then every pixel over its tile's list in one compute pass), and
# evaluate=auto (tiles from 512 potential edges drawn), all three with estimate=quadrants (which
# either evaluation serves), beside `hard`, silhouettes=centre (the method before per-receiver
# silhouettes) and the default (estimate=moments, which takes the tiled evaluation on every
# frame), on every data/ scene, the stability suite's hard cases and two levels' spawn views
# with the lamp.
# ROUNDS rounds (default 5) run the six variants alternately; each run's frame is the median of
# FRAMES frames after a warm-up, and the table gives the median over the rounds, as ratios to
# `hard`'s frame of the same round; also the largest |V_tiles - V_raster| and the work counts.
# Writes docs/bench-tiles.md. Usage: bash scripts/bench-tiles.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
BIN=$BUILD/bin/penumbra-render
SIZE=${SIZE:-256x256}
FRAMES=${FRAMES:-5}
ROUNDS=${ROUNDS:-5}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
source scripts/wedge-scenes.sh
# tag|method|params
variants=("hard|hard|" "centre|wedges-bitmask|silhouettes=centre"
          "raster|wedges-bitmask|evaluate=raster estimate=quadrants"
          "tiles|wedges-bitmask|evaluate=tiles estimate=quadrants"
          "auto|wedges-bitmask|estimate=quadrants" "default|wedges-bitmask|")
rows=()
renderer=""
for entry in "${wedge_views[@]}"; do
    wedge_view "$entry"
    echo "== $name" >&2
    for round in $(seq "$ROUNDS"); do
        for v in "${variants[@]}"; do
            IFS='|' read -r tag method params <<<"$v"
            args=()
            for p in $params; do args+=(--param "$p"); done
            "$BIN" --scene "$scene" "${camera[@]}" --method "$method" "${args[@]}" --size "$SIZE" \
                --frames "$FRAMES" --out "$OUT/$round-$tag" --quiet
        done
        /usr/bin/python3 - "$OUT" "$round" >>"$OUT/rounds.txt" <<'PY'
import json, sys
out, r = sys.argv[1], sys.argv[2]
rep = {t: json.load(open(f"{out}/{r}-{t}/report.json"))
       for t in ("hard", "centre", "raster", "tiles", "auto", "default")}
c = rep["tiles"]["counters"]
drawn = int(c.get("wedges", 0) - c.get("wedges_hidden", 0))
picked = "tiles" if rep["auto"]["counters"].get("wedge_evaluation_tiled", 0) else "raster"
print(" ".join(str(x) for x in (
    rep["hard"]["frame_ms"], rep["centre"]["frame_ms"], rep["raster"]["frame_ms"],
    rep["tiles"]["frame_ms"], drawn, int(c.get("wedge_tile_entries", 0)),
    int(rep["raster"]["counters"].get("wedge_fragments", 0)), int(c.get("wedge_fragments", 0)),
    rep["tiles"]["gl_renderer"].replace(" ", "_"), rep["auto"]["frame_ms"], picked,
    rep["default"]["frame_ms"])))
PY
    done
    read -r gl row <<<"$(/usr/bin/python3 - "$OUT" "$name" <<'PY'
import statistics, struct, sys
out, name = sys.argv[1], sys.argv[2]
rows = [l.split() for l in open(f"{out}/rounds.txt")]
hard = [float(r[0]) for r in rows]
def over(i):
    return statistics.median(float(r[i]) / h for r, h in zip(rows, hard))
def ratio(i, j):
    return statistics.median(float(r[i]) / float(r[j]) for r in rows)
def pfm(path):
    with open(path, "rb") as f:
        f.readline()
        w, h = map(int, f.readline().split())
        f.readline()
        return struct.unpack("<%df" % (w * h), f.read(4 * w * h))
a, b = pfm(f"{out}/1-raster/visibility.pfm"), pfm(f"{out}/1-tiles/visibility.pfm")
diff = max((abs(x - y) for x, y in zip(a, b) if x == x and y == y), default=0.0)
last = rows[-1]
print(last[8], f"| {name} | {statistics.median(hard):.1f} | {over(1):.1f}× | {over(2):.1f}× "
      f"| {over(3):.1f}× | {ratio(3, 2):.2f} | {over(9):.1f}× ({last[10]}) | {ratio(9, 1):.1f} "
      f"| {over(11):.1f}× | {ratio(11, 1):.1f} "
      f"| {diff:.1g} | {last[4]} | {last[5]} | {last[6]} / {last[7]} |")
PY
)"
    rm -f "$OUT/rounds.txt"
    renderer=$gl
    rows+=("$row")
done
{
    echo "<!-- written by scripts/bench-tiles.sh; do not edit by hand -->"
    echo "wedges-bitmask (silhouettes=potential, N = 64, estimate=quadrants) with its wedges rasterised"
    echo "(\`evaluate=raster\`), evaluated per tile (\`evaluate=tiles\`) or either (\`auto\`), and the default"
    echo "(estimate=moments, always tiled), $SIZE: frame"
    echo "over \`hard\`'s of the same round, median of $ROUNDS alternating rounds (each run the median"
    echo "of $FRAMES frames after a warm-up). GL_RENDERER ${renderer//_/ }, CPU"
    echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //') ($(nproc) cores)."
    echo "auto: evaluate=auto, and the evaluation it took; max |ΔV|: between the raster and tiled"
    echo "evaluations' V (first round); edges: potential edges drawn (after depth-aware culling);"
    echo "entries: (tile, wedge) pairs binned; pairs: (pixel, wedge) pairs that added to the counts"
    echo "(raster: its fragments that passed the shader's discards)."
    echo
    echo "| view | hard ms | centre / hard | raster / hard | tiles / hard | tiles / raster | auto / hard | auto / centre | default / hard | default / centre | max \|ΔV\| | edges | entries | pairs raster / tiles |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    printf '%s\n' "${rows[@]}"
} > docs/bench-tiles.md
cat docs/bench-tiles.md
