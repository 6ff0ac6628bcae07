#!/usr/bin/python3
"""CPU model of wedges-bitmask's estimators where open plates overlap (data/plates-three.json).

For floor points p under the three plates, D(p, y) = the number of plates the segment p -> y
crosses (each plate counts 1: open quads). The truth is the share of the light where D > 0,
integrated on a dense grid; A, the exact integral of D over the light (what the wedge pass
accumulates), is taken from the same grid. With N stratified samples (jittered 8 x 8 for N = 64;
the engine's pattern is of the same kind), the estimators of the hidden share are:

  samples     S_u, the share of samples with D > 0 (estimate=samples);
  ratio       A S_u / S_s, S_s the samples' mean D (estimate=ratio, the engine's default), with
              the engine's rules: A where no sample is hidden, 1 where every sample is hidden
              behind counts that differ;
  ratio/K     the same per part of the light (K = 4: quadrants, 16: a 4 x 4 grid), each part
              with its own exact integral A_k (the wedge pass would keep K areas instead of one);
  regression  S_u + beta (A - S_s), beta the samples' regression slope of [D > 0] on D (exact
              where D takes one value, as the ratio);
  difference  (A - mean((D - d0)+)) / d0, d0 the least non-zero D (exact where the layers do not
              overlap).

Prints the mean |estimate - truth| over the floor points for each, for N = 64 and 128. Usage:
/usr/bin/python3 scripts/estimator_model.py
"""
import json
import os

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def load_plates():
    scene = json.load(open(os.path.join(ROOT, "data", "plates-three.json")))
    light = scene["light"]
    plates = []
    for o in scene["objects"]:
        if o["name"] == "floor":
            continue
        plates.append((np.array(o["center"], float), abs(o["u"][0]), abs(o["v"][2])))
    return np.array(light["center"], float), light["u"][0], light["v"][2], plates


def hidden_counts(c, lu, lv, plates, px, pz, s, t):
    """D for floor points (px, pz) (columns) and light points (s, t) (rows)."""
    yx = c[0] + s * lu
    yz = c[2] + t * lv
    d = np.zeros(np.broadcast(px, s).shape, int)
    for centre, hu, hv in plates:
        tau = centre[1] / c[1]  # where the segment from the floor (y = 0) meets the plate's height
        x = px + tau * (yx - px)
        z = pz + tau * (yz - pz)
        d += (np.abs(x - centre[0]) <= hu) & (np.abs(z - centre[2]) <= hv)
    return d


def stratified(nx, ny, rng):
    """nx x ny jittered strata of the light's square, as rows."""
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    s = -1 + (i.ravel() + rng.random(nx * ny)) * 2 / nx
    t = -1 + (j.ravel() + rng.random(nx * ny)) * 2 / ny
    return s[None], t[None]


def part_masks(s, t, k):
    for a in range(k):
        for b in range(k):
            lo_s, hi_s = -1 + 2 * a / k, -1 + 2 * (a + 1) / k
            lo_t, hi_t = -1 + 2 * b / k, -1 + 2 * (b + 1) / k
            yield ((s >= lo_s) & (s < hi_s) & (t >= lo_t) & (t < hi_t))[0]


def ratio(A, Dp):
    su = (Dp > 0).mean(1)
    ss = Dp.mean(1)
    least = np.where(Dp > 0, Dp, 1 << 20).min(1)
    mixed = (su == 1) & (least != Dp.max(1))
    r = np.where(ss == 0, A, np.where(mixed, 1.0, A * su / np.maximum(ss, 1e-12)))
    return np.clip(r, 0, 1)


def regression(A, Dp):
    D = Dp.astype(float)
    H = (Dp > 0).astype(float)
    mD, mH = D.mean(1), H.mean(1)
    cov = ((D - mD[:, None]) * (H - mH[:, None])).mean(1)
    var = ((D - mD[:, None]) ** 2).mean(1)
    beta = np.where(var > 1e-12, cov / np.maximum(var, 1e-12),
                    np.where(mD > 0, mH / np.maximum(mD, 1e-12), 1.0))
    return np.clip(np.where(mD == 0, A, mH + beta * (A - mD)), 0, 1)


def difference(A, Dp):
    least = np.where(Dp > 0, Dp, 1 << 20).min(1)
    d0 = np.where(least == 1 << 20, 1, least)
    r = (A - np.maximum(Dp - d0[:, None], 0).mean(1)) / d0
    su = (Dp > 0).mean(1)
    mixed = (su == 1) & (least != Dp.max(1))
    return np.where(mixed, 1.0, np.clip(r, 0, 1))


def main():
    c, lu, lv, plates = load_plates()
    X, Z = np.meshgrid(np.linspace(-1.5, 1.5, 120), np.linspace(-1.5, 2.0, 140))
    px, pz = X.ravel()[:, None], Z.ravel()[:, None]
    g = (np.arange(96) + 0.5) / 96 * 2 - 1
    gs, gt = np.meshgrid(g, g)
    gs, gt = gs.ravel()[None], gt.ravel()[None]
    Dd = hidden_counts(c, lu, lv, plates, px, pz, gs, gt)
    truth = (Dd > 0).mean(1)
    print("floor points %d, in penumbra %.1f %%" % (len(truth), 100 * ((truth > 0) & (truth < 1)).mean()))
    print("| N | samples | ratio | ratio/4 | ratio/16 | regression | difference |")
    print("|---|---|---|---|---|---|---|")
    for nx, ny in ((8, 8), (8, 16)):
        s, t = stratified(nx, ny, np.random.default_rng(1))
        Ds = hidden_counts(c, lu, lv, plates, px, pz, s, t)
        A = Dd.mean(1)
        row = [np.abs((Ds > 0).mean(1) - truth).mean(), np.abs(ratio(A, Ds) - truth).mean()]
        for k in (2, 4):
            est = np.zeros(len(truth))
            for md, ms in zip(part_masks(gs, gt, k), part_masks(s, t, k)):
                est += ratio((Dd * md).sum(1) / md.sum(), Ds[:, ms]) / (k * k)
            row.append(np.abs(est - truth).mean())
        row.append(np.abs(regression(A, Ds) - truth).mean())
        row.append(np.abs(difference(A, Ds) - truth).mean())
        print("| %d | " % s.shape[1] + " | ".join("%.4f" % v for v in row) + " |")


if __name__ == "__main__":
    main()
