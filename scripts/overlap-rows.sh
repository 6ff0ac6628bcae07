#!/usr/bin/env bash
# The figure of docs/methods/wedges-blend.md: per overlap scene, one row hard / wedges-additive /
# wedges-multiply / wedges-blend / reference (visibility, 128x128, reference N = 256), with each
# method's mean error against the reference. Writes docs/overlap-rows.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >/dev/null
bash scripts/build.sh >/dev/null
render=build/bin/penumbra-render
scenes=(overlap plates-three bars-cross diamonds spheres-nine torus-box)
methods=(hard wedges-additive wedges-multiply wedges-blend)
root=out/overlap-rows
for s in "${scenes[@]}"; do
    "$render" --scene "data/$s.json" --method reference --samples 256 --size 128x128 \
        --out "$root/$s/reference" --quiet
    for m in "${methods[@]}"; do
        "$render" --scene "data/$s.json" --method "$m" --size 128x128 --out "$root/$s/$m" \
            --compare "$root/$s/reference/visibility.pfm" --quiet
    done
done
mkdir -p docs
/usr/bin/python3 - "$root" docs/overlap-rows.png "${scenes[@]}" -- "${methods[@]}" <<'PY'
import json, sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

args = sys.argv[1:]
root, out = args[0], args[1]
split = args.index("--")
scenes, methods = args[2:split], args[split + 1:]

sys.path.insert(0, "scripts")
from pfm import read_pfm

cols = methods + ["reference"]
fig, axes = plt.subplots(len(scenes), len(cols), figsize=(1.6 * len(cols), 1.75 * len(scenes)))
for r, scene in enumerate(scenes):
    for c, m in enumerate(cols):
        ax = axes[r, c]
        v = np.nan_to_num(read_pfm(f"{root}/{scene}/{m}/visibility.pfm")[..., 0], nan=0.3)
        ax.imshow(v, cmap="gray", vmin=0, vmax=1, interpolation="nearest")
        ax.set_xticks([]); ax.set_yticks([])
        title = m if r == 0 else ""
        if m != "reference":
            err = json.load(open(f"{root}/{scene}/{m}/report.json"))["error"]["mean_abs_err"]
            title = (title + "\n" if title else "") + f"mean {err:.4f}"
        ax.set_title(title, fontsize=7)
        if c == 0:
            ax.set_ylabel(scene, fontsize=7)
plt.tight_layout(pad=0.3)
plt.savefig(out, dpi=80)
PY
echo "wrote docs/overlap-rows.png"
