#!/usr/bin/python3
"""Turns silhouette_bench's JSON output into the README's markdown table, with a least-squares
fit of the full per-frame step's time against triangle count and silhouette length."""
import json
import sys

UNIT_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}


def main(path):
    data = json.load(open(path))
    rows = {}
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate":
            continue
        kind, mesh, size = b["name"].split("/")[:3]
        if not size.isdigit():  # levels: "level/oa_dm5"
            mesh = size
        tris = int(b["triangles"])
        ms = b["cpu_time"] * UNIT_MS[b["time_unit"]]
        row = rows.setdefault((mesh, tris), {})
        row[kind] = ms
        if kind == "silhouette_full":
            row["edges"] = int(b.get("sil_edges", 0))
            row["groups"] = int(b.get("groups", 0))
    ctx = data["context"]
    print(f"Machine: {ctx.get('num_cpus')} CPUs at {ctx.get('mhz_per_cpu')} MHz "
          f"(host {ctx.get('host_name')}), one thread; `silhouette_bench` "
          f"({ctx.get('date')}). CPU ms per frame, light moving every frame.\n")
    print("| mesh | triangles | silhouette edges | groups | full step ms | ms per 1M tri "
          "| caps as vertices ms | without wedges ms | classify + groups ms | topology (once) ms |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    fit = []
    for (mesh, tris), r in rows.items():
        full = r.get("silhouette_full")
        if full is None:
            continue
        fit.append((tris, r["edges"], full))

        def f(k):
            return f"{r[k]:.2f}" if k in r else "–"
        print(f"| {mesh} | {tris:,} | {r['edges']:,} | {r['groups']:,} | {full:.2f} "
              f"| {full / (tris * 1e-6):.1f} | {f('silhouette_full_caps')} "
              f"| {f('silhouette_volumes')} | {f('silhouette_classify')} | {f('topology_build')} |")
    # Least squares: full_ms = a * triangles + b * edges (no intercept).
    stt = sum(t * t for t, e, _ in fit)
    see = sum(e * e for t, e, _ in fit)
    ste = sum(t * e for t, e, _ in fit)
    sty = sum(t * y for t, e, y in fit)
    sey = sum(e * y for t, e, y in fit)
    det = stt * see - ste * ste
    if fit and det > 0:
        a = (sty * see - sey * ste) / det
        b = (stt * sey - ste * sty) / det
        print(f"\nFit over these rows: full step ≈ {a * 1e6:.1f} ns × triangles + "
              f"{b * 1e6:.0f} ns × silhouette edges.")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/silhouette_bench.json")
