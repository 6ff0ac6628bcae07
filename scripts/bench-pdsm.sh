#!/usr/bin/env bash
# pdsm benchmark (docs/methods/pdsm.md): on every view of the wedge benches (scripts/wedge-scenes.sh:
# the data/ scenes, the stability suite's hard cases, two levels' first spawn views with the
# viewer's lamp) at 256x256, against `reference` N = 1024 of the same view: pdsm's error (and
# sample-maps' with the same 256 samples and wedges-bitmask's beside it), its frame over hard's
# once both are warm (ROUNDS alternating runs of 30 frames each: the medians of frames 11-30;
# the first builds the deep map, and on llvmpipe every pass of the next few frames runs up to
# 1.7x slower, both methods'; frames 2-6, the measure of the runs before, beside it), whether it built one map or the cube around the light, its precompute, memory and
# function lengths and the share of the depths kept for the receivers. Then the compression's
# noise bound, its tolerance, the samples, the receiver offset (bias) and cull=off swept on two
# scenes, and the noise bound, the offset and cull=off on the levels' views. Writes
# docs/bench-pdsm.md.
# Usage: bash scripts/bench-pdsm.sh   (build first; OUT defaults to out/bench-pdsm, ROUNDS to 3;
# TABLES_ONLY=1 writes the tables again from OUT's last run without rendering)
set -euo pipefail
cd "$(dirname "$0")/.."
render() {
    [ -n "${TABLES_ONLY:-}" ] || build/bin/penumbra-render "$@"
}
root=${OUT:-out/bench-pdsm}
rounds=${ROUNDS:-3}
size=${SIZE:-256x256}
source scripts/wedge-scenes.sh
mkdir -p "$root"
rows=()
for entry in "${wedge_views[@]}"; do
    wedge_view "$entry"
    o="$root/${name// /-}"
    rows+=("$o|$name")
    echo "== $name" >&2
    [ -f "$o/reference/visibility.pfm" ] ||
        render --scene "$scene" "${camera[@]}" --method reference --samples 1024 --size "$size" \
            --out "$o/reference" --quiet
    ref=(--compare "$o/reference/visibility.pfm")
    for run in $(seq "$rounds"); do
        render --scene "$scene" "${camera[@]}" --method hard --frames 30 --size "$size" \
            --out "$o/hard-$run" --quiet
        render --scene "$scene" "${camera[@]}" --method pdsm --frames 30 --size "$size" \
            --out "$o/pdsm-$run" "${ref[@]}" --quiet
    done
    render --scene "$scene" "${camera[@]}" --method sample-maps --param samples=256 \
        --size "$size" --out "$o/sample-maps" "${ref[@]}" --quiet
    render --scene "$scene" "${camera[@]}" --method wedges-bitmask --size "$size" \
        --out "$o/wedges-bitmask" "${ref[@]}" --quiet
done
sweeps=()
for s in plates-three sphere; do
    o="$root/$s"
    for p in noise=0 noise=1 tolerance=0.003 tolerance=0.008 tolerance=0.016 tolerance=0.032 \
        samples=16 samples=64 bias=0.0 bias=0.1 cull=off; do
        render --scene "data/$s.json" --method pdsm --param "$p" --size "$size" \
            --out "$o/pdsm-$p" --compare "$o/reference/visibility.pfm" --quiet
        sweeps+=("$o|$s|$p")
    done
done
# On the levels' spawn views: the compression's noise bound (memory), the receiver offset
# (where the lamp grazes steps and walls), and every depth kept (cull=off).
for entry in ../shared/levels/kaos2.glb@0 ../shared/levels/oa_dm5.glb@0; do
    wedge_view "$entry"
    o="$root/${name// /-}"
    params=(noise=1 bias=0.0 cull=off)
    [[ "$entry" == *oa_dm5* ]] && params=(noise=0 noise=1 bias=0.0 bias=0.1 cull=off)
    for p in "${params[@]}"; do
        echo "== $name $p" >&2
        render --scene "$scene" "${camera[@]}" --method pdsm --param "$p" --size "$size" \
            --out "$o/pdsm-$p" --compare "$o/reference/visibility.pfm" --quiet
        sweeps+=("$o|$name|$p")
    done
done
cpu=$(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')
/usr/bin/python3 - "$rounds" "$cpu" "${rows[@]}" -- "${sweeps[@]}" > docs/bench-pdsm.md <<'PY'
import json, statistics, sys
rounds, cpu = int(sys.argv[1]), sys.argv[2]
args = sys.argv[3:]
cut = args.index("--")
rows, sweeps = args[:cut], args[cut + 1:]
def rep(path):
    with open(path + "/report.json") as f:
        return json.load(f)
def err(r):
    e = r["error"]
    return f"{e['mean_abs_err']:.4f} ({e['bad_pixel_pct']:.1f})"
first = rep(rows[0].split("|")[0] + "/pdsm-1")
print("<!-- written by scripts/bench-pdsm.sh; do not edit by hand -->")
print(f"`pdsm` with its defaults (k = 256 samples, maps and deep map of 512², tolerance 0.004, "
      f"noise 0.5, bias 0.05, cull on) at 256², against `reference` N = 1024 of the same view: mean |dV| (% pixels off by > 0.05), "
      f"beside `sample-maps` with the same 256 samples and `wedges-bitmask`'s default. Frame: "
      f"pdsm's over `hard`'s once both are warm: the median over {rounds} alternating runs of 30 "
      f"frames each of the ratio of their medians over frames 11–30 (the first builds the deep "
      f"map; on llvmpipe every pass of the next few frames runs slower, both methods'); beside it "
      f"in parentheses the same over frames 2–6, the measure of the runs before. Maps: one along the light's normal, or the cube of deep "
      f"maps around the light (its faces built) where a lookup of the one map's extent finds "
      f"receivers of the view outside it (the cube then built at once). Precompute: the sample "
      f"maps drawn and read back, merged on the CPU (all cores) and uploaded, in the first frame "
      f"(for the cube, a one map built before it, in parentheses: none where the probe chose "
      f"it). Depths kept: the share of the read texels' depths kept for the receivers (cull). GL_RENDERER {first['gl_renderer']}, CPU {cpu}.")
print()
print("| view | pdsm | sample-maps k = 256 | wedges-bitmask | pdsm frame / hard, warm (frames 2–6) | maps | "
      "precompute s | deep map MiB | points per texel (mean, longest) | depths kept % | "
      "clipped (receivers outside) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for row in rows:
    o, name = row.split("|")
    p = rep(o + "/pdsm-1")
    c = p["counters"]
    def ratio(first, last):
        return statistics.median(
            statistics.median(rep(f"{o}/pdsm-{r}")["frame_ms_each"][first:last]) /
            statistics.median(rep(f"{o}/hard-{r}")["frame_ms_each"][first:last])
            for r in range(1, rounds + 1))
    clipped = f"yes ({int(c['pdsm_pixels_outside'])})" if c["pdsm_clipped"] else "no"
    cube = c.get("pdsm_cube", 0) > 0
    maps = f"cube, {int(c['pdsm_faces'])} faces" if cube else "one"
    pre = f"{c['pdsm_precompute_ms'] / 1000:.1f}"
    if cube:
        pre += f" ({c['pdsm_first_map_ms'] / 1000:.1f})"
    print(f"| {name} | {err(p)} | {err(rep(o + '/sample-maps'))} | "
          f"{err(rep(o + '/wedges-bitmask'))} | {ratio(10, 30):.2f}× ({ratio(1, 6):.2f}×) | {maps} | "
          f"{pre} | {c['pdsm_bytes'] / 2**20:.1f} | "
          f"{c['pdsm_mean_function']:.0f}, {int(c['pdsm_longest_function'])} | "
          f"{100 * c['pdsm_depth_kept']:.1f} | {clipped} |")
print()
print("**Parameters** (one run each, the same reference; the others at their defaults):")
print()
print("| scene | parameter | mean error (% > 0.05) | deep map MiB | points per texel | "
      "largest stored deviation | precompute s |")
print("|---|---|---|---|---|---|---|")
last = None
for s in sweeps:
    o, scene, p = s.split("|")
    for label, path in ([("default", o + "/pdsm-1")] if scene != last else []) + \
            [(p, f"{o}/pdsm-{p}")]:
        last = scene
        r = rep(path)
        c = r["counters"]
        print(f"| {scene} | {label} | {err(r)} | {c['pdsm_bytes'] / 2**20:.1f} | "
              f"{c['pdsm_mean_function']:.0f} | {c['pdsm_max_deviation']:.4f} | "
              f"{c['pdsm_precompute_ms'] / 1000:.1f} |")
PY
cat docs/bench-pdsm.md
