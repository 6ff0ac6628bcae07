#!/usr/bin/env bash
# linear-light-sm benchmark (docs/methods/linear-light-sm.md): on every view of the wedge
# benches (scripts/wedge-scenes.sh: the data/ scenes, the stability suite's hard cases, two
# levels' first spawn views with the viewer's lamp) and the gap between plates (its own failure)
# at 256x256, against `reference` N = 1024 of the same view: its error at 1, 2, 4 and 8 linear
# lights (the default 2), beside `pcss` and `sample-maps` with 16 samples (its fewest; the
# default has 4 end points); its frame over hard's (ROUNDS alternating runs, each the median of
# 5 frames after the first, which draws the maps and skins) and the first frame's maps and skins.
# Writes docs/bench-linear-light-sm.md.
# Usage: bash scripts/bench-linear-light-sm.sh   (build first; OUT defaults to
# out/bench-linear-light-sm, ROUNDS to 3)
set -euo pipefail
cd "$(dirname "$0")/.."
render=build/bin/penumbra-render
root=${OUT:-out/bench-linear-light-sm}
rounds=${ROUNDS:-3}
size=${SIZE:-256x256}
source scripts/wedge-scenes.sh
mkdir -p "$root"
rows=()
for entry in "${wedge_views[@]}" data/stability/gap-between-plates.json; do
    wedge_view "$entry"
    o="$root/${name// /-}"
    rows+=("$o|$name")
    echo "== $name" >&2
    [ -f "$o/reference/visibility.pfm" ] ||
        "$render" --scene "$scene" "${camera[@]}" --method reference --samples 1024 --size "$size" \
            --out "$o/reference" --quiet
    ref=(--compare "$o/reference/visibility.pfm")
    for run in $(seq "$rounds"); do
        "$render" --scene "$scene" "${camera[@]}" --method hard --frames 6 --size "$size" \
            --out "$o/hard-$run" --quiet
        "$render" --scene "$scene" "${camera[@]}" --method linear-light-sm --frames 6 \
            --size "$size" --out "$o/ll-$run" "${ref[@]}" --quiet
    done
    for k in 1 4 8; do
        "$render" --scene "$scene" "${camera[@]}" --method linear-light-sm --param "lights=$k" \
            --size "$size" --out "$o/ll-lights-$k" "${ref[@]}" --quiet
    done
    "$render" --scene "$scene" "${camera[@]}" --method pcss --size "$size" --out "$o/pcss" \
        "${ref[@]}" --quiet
    "$render" --scene "$scene" "${camera[@]}" --method sample-maps --param samples=16 \
        --size "$size" --out "$o/sample-maps-16" "${ref[@]}" --quiet
    "$render" --scene "$scene" "${camera[@]}" --method linear-light-sm --frames 1 \
        --size "$size" --out "$o/ll-first" --quiet
done
cpu=$(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')
/usr/bin/python3 - "$rounds" "$cpu" "${rows[@]}" > docs/bench-linear-light-sm.md <<'PY'
import json, statistics, sys
rounds, cpu = int(sys.argv[1]), sys.argv[2]
rows = sys.argv[3:]
def rep(path):
    with open(path + "/report.json") as f:
        return json.load(f)
def mean(path):
    return rep(path)["error"]["mean_abs_err"]
def err(path):
    e = rep(path)["error"]
    return f"{e['mean_abs_err']:.4f} ({e['bad_pixel_pct']:.1f})"
first = rep(rows[0].split("|")[0] + "/ll-1")
print("<!-- written by scripts/bench-linear-light-sm.sh; do not edit by hand -->")
print("`linear-light-sm` at 256², against `reference` N = 1024 of the same view: mean |dV| "
      "(% pixels off by > 0.05) at 1, 2 (the default), 4 and 8 linear lights along the light's "
      "longer axis, beside `pcss` and `sample-maps` with 16 samples (its fewest; the default has 4 "
      "end points). Frame: linear-light-sm's (2 lights) over `hard`'s, the median of "
      f"{rounds} alternating runs, each the median of 6 frames; first frame: the GPU ms of its "
      "end points' maps and skins (drawn again whenever the light moves). GL_RENDERER "
      f"{first['gl_renderer']}, CPU {cpu}.")
print()
print("| view | 1 light | 2 lights | 4 lights | 8 lights | pcss | sample-maps N = 16 | "
      "frame / hard | first frame: maps + skins ms |")
print("|---|---|---|---|---|---|---|---|---|")
for row in rows:
    o, name = row.split("|")
    ratios = [rep(f"{o}/ll-{r}")["frame_ms"] / rep(f"{o}/hard-{r}")["frame_ms"]
              for r in range(1, rounds + 1)]
    g = rep(o + "/ll-first")["gpu_ms"]
    build = g.get("linear-light-sm-shadow", 0.0) + g.get("linear-light-sm-skins", 0.0)
    print(f"| {name} | {err(o + '/ll-lights-1')} | {err(o + '/ll-1')} | "
          f"{err(o + '/ll-lights-4')} | {err(o + '/ll-lights-8')} | {err(o + '/pcss')} | "
          f"{err(o + '/sample-maps-16')} | {statistics.median(ratios):.2f}× | {build:.0f} |")
print()
means = {k: [mean(r.split('|')[0] + p) for r in rows]
         for k, p in (("1", "/ll-lights-1"), ("2", "/ll-1"), ("4", "/ll-lights-4"),
                      ("8", "/ll-lights-8"))}
print("Median over the views of the mean error: " +
      ", ".join(f"{statistics.median(v):.4f} at {k} light{'s' if k != '1' else ''}"
                for k, v in means.items()) + ".")
PY
cat docs/bench-linear-light-sm.md
