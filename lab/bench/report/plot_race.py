#!/usr/bin/python3
"""The equal-time race's plot and pictures (docs/lab/race.md; lab/bench/race.sh writes race.csv):
error against render time per scene (relMSE, 1 - SSIM and HDR-FLIP, each renderer against its
own 4096-spp reference) into race.png, and, given the race's images, a sheet of the denoised
results per scene into race_<scene>.png. Prints the table of docs/lab/race.md (markdown).

    /usr/bin/python3 lab/bench/report/plot_race.py docs/tradeoffs [--images DIR --references DIR]

Run by lab/bench/race.sh, and by lab/bench/report/run.sh (make report) from the committed
race.csv when there is one."""
import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

DPI = 80
STYLE = {"cycles+oidn": ("tab:blue", "Cycles + OIDN"), "glint+auto": ("tab:red", "Glint + auto")}


def parse_args():
    p = argparse.ArgumentParser(prog="plot_race.py")
    p.add_argument("out", help="the folder of race.csv; the PNGs go there too")
    p.add_argument("--images", help="the race's EXRs (img_SCENE_RENDERER_THRESHOLD_BUDGET.exr)")
    p.add_argument("--references", help="the references (glint_SCENE.exr, cycles_SCENE.exr)")
    return p.parse_args()


def plot(rows, out):
    scenes = sorted({r["scene"] for r in rows})
    metrics = [("relmse", "relMSE"), ("ssim", "1 − SSIM"), ("flip", "HDR-FLIP")]
    fig, axes = plt.subplots(len(scenes), 3, figsize=(13, 3.6 * len(scenes)), squeeze=False)
    for i, scene in enumerate(scenes):
        for j, (key, label) in enumerate(metrics):
            ax = axes[i][j]
            for renderer, (colour, name) in STYLE.items():
                for threshold, dash in zip(sorted({r["threshold"] for r in rows}, reverse=True),
                                           ["-", "--", ":"]):
                    pts = sorted((float(r["render_seconds"]), float(r[key]))
                                 for r in rows if r["scene"] == scene
                                 and r["renderer"] == renderer and r["threshold"] == threshold)
                    if not pts:
                        continue
                    ys = [1.0 - y if key == "ssim" else y for _, y in pts]
                    ax.loglog([x for x, _ in pts], ys, dash, color=colour, marker="o",
                              label=f"{name}, threshold {threshold}")
            budgets = sorted({float(r["budget"]) for r in rows})
            ax.set_xticks(budgets, [f"{b:g}" for b in budgets])
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_xlabel("render wall-clock (s, 2 threads)")
            ax.set_ylabel(label)
            ax.set_title(f"{scene}: {label} after denoising")
            ax.grid(True, which="both", alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "race.png"), dpi=DPI)
    plt.close(fig)


def read_rgb(path):
    import OpenImageIO as oiio  # Debian's python3-openimageio, only for the sheets
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    px = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    return px[:, :, [names.index(c) for c in ("R", "G", "B")]]


def srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def sheets(rows, out, images, references):
    """Per scene: a row per renderer (default threshold), the budgets then the reference."""
    for scene in sorted({r["scene"] for r in rows}):
        threshold = max({r["threshold"] for r in rows}, key=float)
        budgets = sorted({r["budget"] for r in rows if r["scene"] == scene}, key=float)
        fig, axes = plt.subplots(2, len(budgets) + 1, figsize=(2.6 * (len(budgets) + 1), 5.2),
                                 squeeze=False)
        for i, (renderer, ref) in enumerate((("cycles", "cycles"), ("glint", "glint"))):
            name = STYLE[f"{renderer}+{'oidn' if renderer == 'cycles' else 'auto'}"][1]
            for j, budget in enumerate(budgets):
                path = os.path.join(images, f"img_{scene}_{renderer}_{threshold}_{budget}.exr")
                axes[i][j].imshow(srgb(read_rgb(path)), interpolation="nearest")
                axes[i][j].set_title(f"{name}, {budget} s", fontsize=8)
            axes[i][-1].imshow(srgb(read_rgb(os.path.join(references, f"{ref}_{scene}.exr"))),
                               interpolation="nearest")
            axes[i][-1].set_title(f"{name.split()[0]} 4096 spp", fontsize=8)
        for ax in axes.flat:
            ax.set_axis_off()
        fig.tight_layout()
        fig.savefig(os.path.join(out, f"race_{scene}.png"), dpi=DPI)
        plt.close(fig)


def table(rows):
    print("| scene | budget (s) | threshold | Cycles + OIDN: render s, relMSE, SSIM, FLIP "
          "| Glint + auto: render s (auto s), mean spp, relMSE, SSIM, FLIP | Glint / Cycles relMSE |")
    print("|---|---|---|---|---|---|")
    key = lambda r: (r["scene"], float(r["budget"]), -float(r["threshold"]))
    cells = {}
    for r in rows:
        cells.setdefault(key(r), {})[r["renderer"]] = r
    for k in sorted(cells):
        c, g = cells[k].get("cycles+oidn"), cells[k].get("glint+auto")
        if not c or not g:
            continue
        print(f"| {k[0]} | {g['budget']} | {g['threshold']} | {float(c['render_seconds']):.1f}, "
              f"{float(c['relmse']):.3g}, {float(c['ssim']):.4f}, {float(c['flip']):.4f} | "
              f"{float(g['render_seconds']):.1f} ({float(g['denoise_seconds']):.0f}), "
              f"{float(g['mean_spp']):.0f}, {float(g['relmse']):.3g}, {float(g['ssim']):.4f}, "
              f"{float(g['flip']):.4f} | {float(g['relmse']) / float(c['relmse']):.2f} |")


def main():
    args = parse_args()
    with open(os.path.join(args.out, "race.csv")) as f:
        rows = list(csv.DictReader(f))
    plot(rows, args.out)
    if args.images and args.references:
        sheets(rows, args.out, args.images, args.references)
    table(rows)


if __name__ == "__main__":
    main()
