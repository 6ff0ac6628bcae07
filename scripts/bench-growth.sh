#!/usr/bin/env bash
# How the default method's frame grows: `auto` (wedges-bitmask on these scenes) against `hard`
# on data/sphere.json's scene with the sphere tessellated from ~1k to ~1M triangles (512², the
# scene's light), the light's half extents scaled 1/4x to 4x (10k triangles, 512²), and the
# image from 256² to 1024² (10k triangles, the scene's light). Each configuration is rendered
# by both methods in ROUNDS alternating rounds (median frame of FRAMES after WARMUP untimed ones
# per run; the rounds' median is kept), except the two largest spheres (~500k and ~1M
# triangles), whose auto frame takes a minute or two on llvmpipe: one round of one frame each.
# The tessellation series runs again with simplified stand-ins (--simplify $SIMPLIFY, both
# methods), and every tessellation's auto V, with and without stand-ins, is compared with
# raytrace N = 1024 of the full mesh (max error, pixels over 0.05).
# The penumbra pixels (0.001 < V < 0.999 in auto's V) are counted per configuration. Writes
# out/growth/ (scenes, runs, growth.json) and prints the markdown of docs/bench-growth.md; the
# chart goes to docs/bench-growth.png.
#
#   ROUNDS=3 FRAMES=3 WARMUP=1 bash scripts/bench-growth.sh > docs/bench-growth.md
# REPORT_ONLY=1 prints the page and draws the chart again from the runs in out/growth/.
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${ROUNDS:-3}
FRAMES=${FRAMES:-3}
WARMUP=${WARMUP:-1}
SIMPLIFY=${SIMPLIFY:-0.1}
render=build/bin/penumbra-render
[[ -x $render ]] || { echo "bench-growth.sh: build first (bash scripts/build.sh)" >&2; exit 2; }
out=out/growth
if [[ -z ${REPORT_ONLY:-} ]]; then
    rm -rf "$out"
    mkdir -p "$out"
fi

# name segments light-scale size runs (all: every round; once: round 1, one frame)
configs=()
for s in 32 71 100 224 316; do configs+=("tess-$s $s 1 512 all"); done
for s in 708 1000; do configs+=("tess-$s $s 1 512 once"); done
for s in 32 71 100 224 316 708 1000; do configs+=("simp-$s $s 1 512 all"); done
for k in 0.25 0.5 2 4; do configs+=("light-$k 100 $k 512 all"); done
for r in 256 768 1024; do configs+=("size-$r 100 1 $r all"); done

scene() { # segments light-scale -> scene file
    local file="$out/sphere-$1-$2.json"
    [[ -f $file ]] || /usr/bin/python3 - "$1" "$2" "$file" <<'EOF'
import json, sys
segments, scale, path = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
s = json.load(open("data/sphere.json"))
s["light"]["u"] = [c * scale for c in s["light"]["u"]]
s["light"]["v"] = [c * scale for c in s["light"]["v"]]
for o in s["objects"]:
    if o["type"] == "sphere":
        o["segments"] = segments
json.dump(s, open(path, "w"), indent=1)
EOF
    echo "$file"
}

total=$(( (${#configs[@]} - 2) * ROUNDS * 2 + 4 + 7 ))
done_runs=0
# The truth of each tessellation: raytrace N = 1024 of the full mesh.
for s in 32 71 100 224 316 708 1000; do
    [[ -z ${REPORT_ONLY:-} ]] || break
    "$render" --scene "$(scene "$s" 1)" --method raytrace --samples 1024 --size 512x512 \
        --out "$out/truth-$s" --quiet
    done_runs=$((done_runs + 1))
    echo "bench-growth: $done_runs / $total (truth, $s segments)" >&2
done
for round in $(seq 1 "$ROUNDS"); do
    [[ -z ${REPORT_ONLY:-} ]] || break
    for c in "${configs[@]}"; do
        read -r name segments scale size runs <<<"$c"
        frames=$FRAMES warmup=$WARMUP
        if [[ $runs == once ]]; then
            (( round == 1 )) || continue
            frames=1 warmup=0
        fi
        file=$(scene "$segments" "$scale")
        # Alternate which method goes first from round to round.
        methods=(hard auto)
        (( round % 2 == 0 )) && methods=(auto hard)
        simplify=0
        [[ $name == simp-* ]] && simplify=$SIMPLIFY
        for m in "${methods[@]}"; do
            dir="$out/$name/$m-$round"
            "$render" --scene "$file" --method "$m" --size "${size}x${size}" \
                --frames "$frames" --warmup "$warmup" --simplify "$simplify" --out "$dir" --quiet
            done_runs=$((done_runs + 1))
            echo "bench-growth: $done_runs / $total ($name, $m, round $round)" >&2
        done
    done
done

/usr/bin/python3 - "$out" "$ROUNDS" "$FRAMES" "$WARMUP" "$SIMPLIFY" "${configs[@]}" <<'EOF'
import json, os, statistics, struct, sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

out, rounds, frames, warmup = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
simplify = sys.argv[5]
configs = [c.split() for c in sys.argv[6:]]

sys.path.insert(0, "scripts")
from pfm import read_pfm

rows = []
renderer = cpu = None
for name, segments, scale, size, once in configs:
    ms = {}
    info = {}
    for m in ("hard", "auto"):
        runs = []
        for r in range(1, (1 if once == "once" else rounds) + 1):
            rep = json.load(open(f"{out}/{name}/{m}-{r}/report.json"))
            runs.append(rep["frame_ms"])
            renderer = rep.get("gl_renderer", renderer)
            if m == "auto":
                info = rep
        ms[m] = statistics.median(runs)
    v = read_pfm(f"{out}/{name}/auto-1/visibility.pfm")[..., 0]
    penumbra = int(np.count_nonzero((v > 0.001) & (v < 0.999)))
    row = {"name": name, "once": once == "once", "segments": int(segments),
           "light_scale": float(scale),
           "size": int(size), "triangles": info["triangles"],
           "wedges": info["counters"].get("wedges", 0),
           "penumbra_pixels": penumbra, "hard_ms": ms["hard"], "auto_ms": ms["auto"]}
    truth = f"{out}/truth-{segments}/visibility.pfm"
    if (name.startswith("tess-") or name.startswith("simp-")) and os.path.exists(truth):
        t = read_pfm(truth)[..., 0]
        ok = np.isfinite(t) & np.isfinite(v)
        d = np.abs(v[ok] - t[ok])
        row["max_error"] = float(d.max())
        row["mean_error"] = float(d.mean())
        row["pixels_over_005"] = int(np.count_nonzero(d > 0.05))
        row["pixels_over_e"] = int(np.count_nonzero(d > float(simplify)))
    if name.startswith("simp-"):
        row["triangles_full"] = info["simplify"]["triangles_before"]
        row["simplify_ms"] = info["simplify"]["ms"]
    rows.append(row)
try:
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
except OSError:
    pass
json.dump(rows, open(f"{out}/growth.json", "w"), indent=1)

def table(rows, first, key):
    print(f"| {first} | triangles | wedges drawn | penumbra pixels | hard ms | auto ms "
          "| auto / hard | (auto − hard) ms per 1k penumbra pixels |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        per = 1e3 * (r["auto_ms"] - r["hard_ms"]) / max(r["penumbra_pixels"], 1)
        mark = " (one frame)" if r["once"] else ""
        print(f"| {key(r)}{mark} | {r['triangles']:,} | {int(r['wedges']):,} | "
              f"{r['penumbra_pixels']:,} | {r['hard_ms']:.1f} | {r['auto_ms']:.1f} | "
              f"{r['auto_ms'] / r['hard_ms']:.1f}× | {per:.2f} |")
    print()

tess = [r for r in rows if r["name"].startswith("tess-")]
simp = [r for r in rows if r["name"].startswith("simp-")]
base = [r for r in tess if r["segments"] == 100]
light = sorted([r for r in rows if r["name"].startswith("light-")] + base,
               key=lambda r: r["light_scale"])
size = sorted([r for r in rows if r["name"].startswith("size-")] + base,
              key=lambda r: r["size"])

print("<!-- written by scripts/bench-growth.sh; do not edit by hand -->")
print("# How the default frame grows\n")
print("`bash scripts/bench-growth.sh`: data/sphere.json's scene (a sphere over a floor, a square "
      "light above), `auto` (wedges-bitmask here) and `hard`, each configuration rendered by "
      f"both in {rounds} alternating rounds (each run the median of {frames} frames after "
      f"{warmup} untimed; the rounds' median). Penumbra pixels: 0.001 < V < 0.999 in auto's V. "
      f"GL_RENDERER {renderer}, CPU {cpu}.\n")
print("![frame growth](bench-growth.png)\n")
print("**Tessellation** (512², the scene's light: half extent 0.6):\n")
table(tess, "sphere segments", lambda r: r["segments"])
print("Against raytrace N = 1024 of the same mesh (512²):\n")
print(f"| sphere segments | triangles | mean \\|V − truth\\| | max | pixels > 0.05 | pixels > {simplify} |")
print("|---:|---:|---:|---:|---:|---:|")
for r in tess:
    if "max_error" in r:
        print(f"| {r['segments']} | {r['triangles']:,} | {r['mean_error']:.5f} | {r['max_error']:.3f} | "
              f"{r['pixels_over_005']:,} | {r['pixels_over_e']:,} |")
print()
if simp:
    print(f"**Tessellation with simplified stand-ins** (`--simplify {simplify}`, both methods on "
          "the stand-in; the error against raytrace N = 1024 of the full mesh; simplification "
          "time once, at load):\n")
    print("| sphere segments | triangles → stand-in | simplify ms | hard ms | auto ms | auto / hard "
          "| auto ms / auto ms at 10k (no stand-in) | mean \\|V − truth\\| | max | pixels > 0.05 "
          f"| pixels > {simplify} |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    ten = base[0]["auto_ms"] if base else float("nan")
    for r in simp:
        print(f"| {r['segments']} | {r['triangles_full']:,} → {r['triangles']:,} | "
              f"{r['simplify_ms']:.0f} | {r['hard_ms']:.1f} | {r['auto_ms']:.1f} | "
              f"{r['auto_ms'] / r['hard_ms']:.1f}× | {r['auto_ms'] / ten:.2f} | "
              f"{r.get('mean_error', float('nan')):.5f} | {r.get('max_error', float('nan')):.3f} | "
              f"{r.get('pixels_over_005', -1):,} | {r.get('pixels_over_e', -1):,} |")
    print()
print("**Light size** (10k triangles, 512²; half extents times the factor):\n")
table(light, "light ×", lambda r: f"{r['light_scale']:g}")
print("**Resolution** (10k triangles, the scene's light):\n")
table(size, "pixels", lambda r: f"{r['size']}²")

fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
ax[0].loglog([r["triangles"] for r in tess], [r["auto_ms"] / r["hard_ms"] for r in tess], "o-",
             label="full mesh: auto / hard")
if simp:
    ax[0].loglog([r["triangles_full"] for r in simp],
                 [r["auto_ms"] / r["hard_ms"] for r in simp], "s--",
                 label=f"--simplify {simplify}: auto / hard, both on the stand-in")
    ax[0].legend(fontsize=8)
ax[0].set_xlabel("sphere triangles (512²)")
ax[0].set_ylabel("frame / hard frame")
for a, series, label in ((ax[1], light, "light half-extent factor"), (ax[2], size, "pixels")):
    pp = [r["penumbra_pixels"] / 1e3 for r in series]
    extra = [r["auto_ms"] - r["hard_ms"] for r in series]
    a.plot(pp, extra, "o-")
    for r, x, y in zip(series, pp, extra):
        a.annotate(f"{r['light_scale']:g}×" if label.startswith("light") else f"{r['size']}²",
                   (x, y), textcoords="offset points", xytext=(4, -10), fontsize=8)
    a.set_xlabel(f"penumbra pixels, thousands ({label})")
    a.set_ylabel("auto − hard frame, ms")
for a in ax:
    a.grid(alpha=0.3)
fig.suptitle(f"auto against hard on data/sphere.json's scene ({renderer})", fontsize=10)
fig.tight_layout()
fig.savefig("docs/bench-growth.png", dpi=110)
EOF
