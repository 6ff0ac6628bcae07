#!/usr/bin/python3
"""Turns silhouette_bench's JSON output into the markdown table of docs/benchmarks.md, with
least-squares fits of the full and the lean per-frame step's time against triangle count and
silhouette length.

    silhouette_table.py RUN.json [--baseline BASE.json]

--baseline: the JSON of another silhouette_bench build (e.g. an older revision) run on the same
machine; its silhouette_full times get a column of their own and the lean step a ratio to them.
"""
import json
import sys

UNIT_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def load(path):
    data = json.load(open(path))
    rows = {}
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate" or "error_occurred" in b:
            continue
        kind, mesh, size = b["name"].split("/")[:3]
        if not size.isdigit():  # levels: "level/oa_dm5"
            mesh = size
        tris = int(b["triangles"])
        ms = b["cpu_time"] * UNIT_MS[b["time_unit"]]
        row = rows.setdefault((mesh, tris), {})
        row[kind] = ms
        if "upload_bytes" in b:
            row[kind + ":upload"] = b["upload_bytes"]
        if kind == "silhouette_full":
            row["edges"] = int(b.get("sil_edges", 0))
            row["groups"] = int(b.get("groups", 0))
        if kind == "potential_edges":
            row["potential_count"] = int(b.get("potential_edges", 0))
    return data, rows


def fit_line(points):
    """Least squares y = a * triangles + b * edges (no intercept); None when degenerate."""
    stt = sum(t * t for t, e, _ in points)
    see = sum(e * e for t, e, _ in points)
    ste = sum(t * e for t, e, _ in points)
    sty = sum(t * y for t, e, y in points)
    sey = sum(e * y for t, e, y in points)
    det = stt * see - ste * ste
    if not points or det <= 0:
        return None
    return (sty * see - sey * ste) / det, (stt * sey - ste * sty) / det


def main(argv):
    path = argv[1] if len(argv) > 1 and not argv[1].startswith("--") else \
        "out/silhouette_bench.json"
    base_rows = None
    if "--baseline" in argv:
        _, base_rows = load(argv[argv.index("--baseline") + 1])
    data, rows = load(path)
    ctx = data["context"]
    print(f"Machine: {ctx.get('num_cpus')} CPUs at {ctx.get('mhz_per_cpu')} MHz "
          f"(host {ctx.get('host_name')}), one thread; `silhouette_bench` "
          f"({ctx.get('date')}). CPU ms per frame, light moving every frame. Full: "
          f"default settings (volumes with caps by reference, wedges, loops, edge-ray bounds). "
          f"Lean: `SilhouetteSettings::lean()` (triangle ids, directed edges, cone bounds). "
          f"Upload: what the frame holds for the GPU (KB). Potential: "
          f"`PotentialSilhouettes::update`, the edges that are a silhouette from some light point "
          f"(wedges-bitmask's default, `silhouettes=potential`, runs it beside the lean step).\n")
    base_cols = " | full, baseline build ms | lean / baseline full" if base_rows else ""
    print("| mesh | triangles | silhouette edges | groups | full step ms | lean step ms "
          f"| lean / full{base_cols} | full upload KB | lean upload KB | lean ms per 1M tri "
          "| caps as vertices ms | without wedges ms | classify + groups ms "
          "| topology (once) ms | potential edges | potential ms | lean + potential ms per 1M tri |")
    print("|---|---:|---:|---:|---:|---:|---:|" + ("---:|---:|" if base_rows else "") +
          "---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    fit_full, fit_lean, fit_potential = [], [], []
    for (mesh, tris), r in rows.items():
        full = r.get("silhouette_full")
        if full is None:
            continue
        lean = r.get("silhouette_lean")
        fit_full.append((tris, r["edges"], full))
        if lean is not None:
            fit_lean.append((tris, r["edges"], lean))
        if "potential_edges" in r:
            fit_potential.append((tris, r.get("potential_count", 0), r["potential_edges"]))

        def f(k):
            return f"{r[k]:.2f}" if k in r else "–"

        def kb(k):
            return f"{r[k] / 1024:,.0f}" if k in r else "–"
        ratio = f"{lean / full:.3f}" if lean is not None else "–"
        base = ""
        if base_rows is not None:
            # Levels are matched by name: builds may count their triangles differently
            # (before or after welding drops degenerate ones).
            same = [v for (m, t), v in base_rows.items() if m == mesh]
            match = base_rows.get((mesh, tris)) or (same[0] if len(same) == 1 else {})
            b = match.get("silhouette_full")
            base = (f" | {b:.2f}" if b is not None else " | –") + \
                (f" | {lean / b:.3f}" if b is not None and lean is not None else " | –")
        per_mtri = f"{lean / (tris * 1e-6):.1f}" if lean is not None else "–"
        print(f"| {mesh} | {tris:,} | {r['edges']:,} | {r['groups']:,} | {full:.2f} "
              f"| {f('silhouette_lean')} | {ratio}{base} | {kb('silhouette_full:upload')} "
              f"| {kb('silhouette_lean:upload')} | {per_mtri} "
              f"| {f('silhouette_full_caps')} | {f('silhouette_volumes')} "
              f"| {f('silhouette_classify')} | {f('topology_build')} "
              f"| {r.get('potential_count', 0):,} | {f('potential_edges')} | " +
              (f"{(lean + r['potential_edges']) / (tris * 1e-6):.1f}"
               if lean is not None and "potential_edges" in r else "–") + " |")
    for name, points, what in (("full step", fit_full, "silhouette edges"),
                               ("lean step", fit_lean, "silhouette edges"),
                               ("potential edges", fit_potential, "potential edges")):
        line = fit_line(points)
        if line:
            print(f"\nFit over these rows: {name} ≈ {line[0] * 1e6:.1f} ns × triangles + "
                  f"{line[1] * 1e6:.0f} ns × {what}.")


if __name__ == "__main__":
    main(sys.argv)
