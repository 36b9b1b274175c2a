#!/usr/bin/python3
"""Where a race result's error is (docs/lab/race.md, "Where Glint's error is"): for each renderer,
its two seeds' denoised results x1, x2 of one scene and budget against its reference r (the mean
of its K renders), the per-pixel relMSE terms w (x − r)², w = 1 / (r² + 0.01) summed over the
channels, split into

    noise  = w (x1 − x2)² / 2                the results' own variance (independent seeds)
    bias   = w ((x1 + x2) / 2 − r)² − noise / 2 − floor     what both seeds get wrong alike
    floor  = w s² / K                        the reference's own noise (race_floor.py)

(E[(x̄ − r)²] = bias² + Var(x)/2 + Var(r); each term's mean is an unbiased estimate of its part of
the relMSE, the map of one pixel is noisy). The table gives each part's share of the relMSE and
where it sits: the worst 1 % of pixels, the edges (the top 10 % of the reference's gradient) and
the light (the top 1 % of the reference's luminance). The PNG shows the maps side by side.

    race_errmap.py SCENE BUDGET [--run build/race/run] [--refs build/race] [--png OUT.png]"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from race_floor import EPSILON, read_rgb  # noqa: E402

RUNS = {"Glint": ("glint", "img_{scene}_glint_final_{budget}_{seed}.exr"),
        "Cycles + OIDN 0.01": ("cycles", "img_{scene}_cycles_0.01_{budget}_{seed}.exr"),
        "Cycles + OIDN 0.002": ("cycles", "img_{scene}_cycles_0.002_{budget}_{seed}.exr")}
REF_SEEDS = (99, 100, 101, 102)


def parts(x1, x2, renders):
    r = renders.mean(axis=0)
    w = 1.0 / (r * r + EPSILON)
    k = renders.shape[0]
    floor = (w * renders.var(axis=0, ddof=1) / k).sum(axis=2)
    noise = (w * (x1 - x2) ** 2 / 2).sum(axis=2)
    mean_err = (w * ((x1 + x2) / 2 - r) ** 2).sum(axis=2)
    bias = mean_err - noise / 2 - floor
    raw = ((w * (x1 - r) ** 2).sum(axis=2) + (w * (x2 - r) ** 2).sum(axis=2)) / 2
    return r, raw / 3, noise / 3, bias / 3, floor / 3


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene")
    ap.add_argument("budget")
    ap.add_argument("--run", default="build/race/run")
    ap.add_argument("--refs", default="build/race")
    ap.add_argument("--png")
    a = ap.parse_args()
    rows, maps = [], []
    for name, (renderer, pattern) in RUNS.items():
        paths = [os.path.join(a.run, pattern.format(scene=a.scene, budget=a.budget, seed=s))
                 for s in (1, 2)]
        if not all(os.path.exists(p) for p in paths):
            continue
        renders = np.stack([read_rgb(os.path.join(a.refs, "raw", f"{renderer}_{a.scene}_{s}.exr"))
                            for s in REF_SEEDS])
        r, raw, noise, bias, floor = parts(read_rgb(paths[0]), read_rgb(paths[1]), renders)
        lum = r.mean(axis=2)
        gy, gx = np.gradient(lum)
        grad = np.hypot(gx, gy) / (lum + 0.1)
        edges = grad >= np.quantile(grad, 0.9)
        light = lum >= np.quantile(lum, 0.99)
        err = raw - floor
        worst = err >= np.quantile(err, 0.99)
        total = err.mean()
        rows.append((name, total, noise.mean(), bias.mean(), floor.mean(),
                     err[worst].sum() / err.sum(), err[edges].sum() / err.sum(),
                     bias[edges].sum() / max(bias.sum(), 1e-30), err[light].sum() / err.sum()))
        maps.append((name, err, noise, bias))
    print("| run | relMSE − floor | noise part | bias part | worst 1 % of pixels | edges (10 %) "
          "| bias on edges | light (1 %) |")
    print("|---|---|---|---|---|---|---|---|")
    for name, total, noise, bias, floor, worst, edges, bias_edges, light in rows:
        print(f"| {name} | {total:.3g} | {noise:.3g} ({noise / total:.0%}) | {bias:.3g} "
              f"({bias / total:.0%}) | {worst:.0%} | {edges:.0%} | {bias_edges:.0%} | {light:.0%} |")
    if a.png and maps:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(len(maps), 3, figsize=(9, 3 * len(maps)), squeeze=False)
        vmax = max(np.quantile(m[1], 0.995) for m in maps)
        for row, (name, err, noise, bias) in zip(axes, maps):
            for ax, (title, img) in zip(row, (("w (x − r)² − floor", err), ("noise", noise),
                                              ("bias", bias))):
                ax.imshow(np.clip(img, 0, None), cmap="inferno", vmin=0, vmax=vmax)
                ax.set_title(f"{name}: {title}", fontsize=8)
                ax.axis("off")
        fig.tight_layout()
        tmp = a.png + ".tmp.png"
        fig.savefig(tmp, dpi=80)
        os.replace(tmp, a.png)


if __name__ == "__main__":
    main()
