#!/usr/bin/python3
"""The equal-time race's plot and pictures (docs/lab/race.md; lab/bench/race.sh writes race.csv):
error against render time per scene (relMSE with the references' floor subtracted, 1 - SSIM and
HDR-FLIP, each renderer against its own reference; the mean over the seeds, each seed a dot) into
race.png, Cycles + OIDN twice: with native OIDN's estimated time counted in its budget (the
goal's comparison: its point at the render's seconds plus OIDN's) and not counted (its point at
the render's seconds; rows without an oidn_counted column, from before, are such), and, given the race's images, a sheet of the denoised results per scene (the first seed)
into race_<scene>.png. Prints the tables of docs/lab/race.md (markdown).

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
GLINT = "glint-final"
CYCLES = "cycles+oidn"
# (renderer, threshold, OIDN's time counted) -> colour, line, label
SERIES = {(CYCLES, "0.01", "1"): ("tab:blue", "-", "Cycles + OIDN 0.01, OIDN counted"),
          (CYCLES, "0.002", "1"): ("tab:cyan", "--", "Cycles + OIDN 0.002, OIDN counted"),
          (CYCLES, "0.01", "0"): ("tab:purple", ":", "Cycles + OIDN 0.01, OIDN not counted"),
          (CYCLES, "0.002", "0"): ("tab:pink", ":", "Cycles + OIDN 0.002, OIDN not counted"),
          (GLINT, "final", ""): ("tab:red", "-", "Glint (glint-final)")}
METRICS = [("relmse_corrected", "relMSE − reference floor"), ("ssim", "1 − SSIM"),
           ("flip", "HDR-FLIP")]


def parse_args():
    p = argparse.ArgumentParser(prog="plot_race.py")
    p.add_argument("out", help="the folder of race.csv; the PNGs go there too")
    p.add_argument("--images", help="the race's EXRs (img_SCENE_RENDERER_THRESHOLD_BUDGET_SEED.exr)")
    p.add_argument("--references", help="the references (glint_SCENE.exr, cycles_SCENE.exr)")
    return p.parse_args()


def counted(row):
    """"1" when native OIDN's time was taken off Cycles' budget, "0" when not, "" for Glint."""
    if row["renderer"] == GLINT:
        return ""
    return row.get("oidn_counted") or "0"


def value(row, key):
    if key == "seconds":
        # The run's wall-clock in the race's sense: Cycles' render plus OIDN's when counted.
        extra = float(row["oidn_seconds"]) if counted(row) == "1" else 0.0
        return float(row["render_seconds"]) + extra
    return 1.0 - float(row[key]) if key == "ssim" else float(row[key])


def mean_of(rows, key):
    return float(np.mean([value(r, key) for r in rows]))


def groups(rows):
    """{(scene, budget, renderer, threshold, counted): [rows of every seed]}."""
    out = {}
    for r in rows:
        key = (r["scene"], float(r["budget"]), r["renderer"], r["threshold"], counted(r))
        out.setdefault(key, []).append(r)
    return out


def plot(rows, out):
    scenes = sorted({r["scene"] for r in rows})
    g = groups(rows)
    fig, axes = plt.subplots(len(scenes), 3, figsize=(13, 3.6 * len(scenes)), squeeze=False)
    for i, scene in enumerate(scenes):
        for j, (key, label) in enumerate(METRICS):
            ax = axes[i][j]
            for series, (colour, dash, name) in SERIES.items():
                cells = sorted((b, rs) for (sc, b, *rest), rs in g.items()
                               if sc == scene and tuple(rest) == series)
                if not cells:
                    continue
                xs = [mean_of(rs, "seconds") for _, rs in cells]
                ys = [mean_of(rs, key) for _, rs in cells]
                ax.loglog(xs, ys, dash, color=colour, marker="o", label=name)
                for _, rs in cells:
                    ax.loglog([value(r, "seconds") for r in rs], [value(r, key) for r in rs],
                              ".", color=colour, alpha=0.5)
            budgets = sorted({float(r["budget"]) for r in rows})
            ax.set_xticks(budgets, [f"{b:g}" for b in budgets])
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_xlabel("wall-clock s (Cycles, counted: + OIDN)")
            ax.set_ylabel(label)
            ax.set_title(f"{scene}: {label} after denoising", fontsize=10)
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
    """Per scene: Cycles + OIDN (threshold 0.01) and Glint, the budgets then the reference."""
    seed = min({r["seed"] for r in rows}, key=int)
    for scene in sorted({r["scene"] for r in rows}):
        budgets = sorted({r["budget"] for r in rows if r["scene"] == scene}, key=float)
        fig, axes = plt.subplots(2, len(budgets) + 1, figsize=(2.6 * (len(budgets) + 1), 5.2),
                                 squeeze=False)
        for i, (stem, ref, name) in enumerate((("cycles_0.01", "cycles", "Cycles + OIDN 0.01 (counted)"),
                                               ("glint_final", "glint", "Glint"))):
            for j, budget in enumerate(budgets):
                path = os.path.join(images, f"img_{scene}_{stem}_{budget}_{seed}.exr")
                if os.path.exists(path):
                    axes[i][j].imshow(srgb(read_rgb(path)), interpolation="nearest")
                axes[i][j].set_title(f"{name}, {budget} s", fontsize=8)
            axes[i][-1].imshow(srgb(read_rgb(os.path.join(references, f"{ref}_{scene}.exr"))),
                               interpolation="nearest")
            axes[i][-1].set_title(f"{name.split()[0]} reference", fontsize=8)
        for ax in axes.flat:
            ax.set_axis_off()
        fig.tight_layout()
        fig.savefig(os.path.join(out, f"race_{scene}.png"), dpi=DPI)
        plt.close(fig)


def paired(glint, cycles, key):
    """Glint / Cycles of `key` per seed (the runs of a seed were made together): (min, max)."""
    by_seed = {r["seed"]: value(r, key) for r in cycles}
    q = [value(r, key) / by_seed[r["seed"]] for r in glint if r["seed"] in by_seed]
    return (min(q), max(q)) if q else (float("nan"), float("nan"))


def at_time(g, scene, series, seconds, key):
    """Cycles + OIDN's mean `key` at `seconds` of wall-clock: log-log interpolation between its
    budgets' mean (seconds, value) points; None outside them or where a value is not > 0."""
    pts = sorted((mean_of(rs, "seconds"), mean_of(rs, key))
                 for (sc, _, *rest), rs in g.items() if sc == scene and tuple(rest) == series)
    for (t0, v0), (t1, v1) in zip(pts, pts[1:]):
        if t0 <= seconds <= t1 and v0 > 0 and v1 > 0 and t1 > t0:
            f = np.log(seconds / t0) / np.log(t1 / t0)
            return float(np.exp(np.log(v0) + f * np.log(v1 / v0)))
    return None


def table(rows):
    g = groups(rows)
    seeds = len({r["seed"] for r in rows})
    print(f"Means over {seeds} seeds. relMSE: raw / with the reference's floor subtracted. "
          "Seconds: the run's wall-clock; Cycles' with OIDN counted: render + native OIDN "
          "(its part in brackets).\n")
    print("| scene | budget (s) | " + " | ".join(
        f"{name}: s, relMSE, SSIM, FLIP" if rn == CYCLES
        else f"{name}: s (auto s), spp, relMSE, SSIM, FLIP" for (rn, _, _), (_, _, name)
        in SERIES.items()) + " | load |")
    print("|---|---|" + "---|" * (len(SERIES) + 1))
    cells = sorted({(sc, b) for (sc, b, *_) in g})
    for scene, budget in cells:
        line = f"| {scene} | {budget:g} |"
        load = []
        for series in SERIES:
            rs = g.get((scene, budget, *series))
            if not rs:
                line += " – |"
                continue
            load += [float(r["load"]) for r in rs]
            sec = f"{mean_of(rs, 'seconds'):.1f}"
            if series[0] == GLINT:
                sec += f" ({mean_of(rs, 'denoise_seconds'):.1f}), {mean_of(rs, 'mean_spp'):.0f}"
            elif series[2] == "1":
                sec += f" ({mean_of(rs, 'oidn_seconds'):.2f})"
            line += (f" {sec}, {mean_of(rs, 'relmse'):.3g} / {mean_of(rs, 'relmse_corrected'):.3g},"
                     f" {1 - mean_of(rs, 'ssim'):.4f}, {mean_of(rs, 'flip'):.4f} |")
        print(line + f" {np.mean(load):.1f} |")
    print("\nGlint / Cycles + OIDN: the ratio of the means over the seeds (the per-seed range in "
          "brackets).\n")
    print("| scene | budget (s) | Cycles' threshold | OIDN's time | relMSE raw | relMSE − floor "
          "| 1 − SSIM | FLIP | relMSE − floor at Glint's wall-clock |")
    print("|---|---|---|---|---|---|---|---|---|")
    for scene, budget in cells:
        glint = g.get((scene, budget, GLINT, "final", ""))
        for series in SERIES:
            cycles = g.get((scene, budget, *series))
            if series[0] != CYCLES or not glint or not cycles:
                continue
            how = "counted" if series[2] == "1" else "not counted"
            line = f"| {scene} | {budget:g} | {series[1]} | {how} |"
            for key in ("relmse", "relmse_corrected", "ssim", "flip"):
                lo, hi = paired(glint, cycles, key)
                line += f" {mean_of(glint, key) / mean_of(cycles, key):.2f} ({lo:.2f}–{hi:.2f}) |"
            seconds = mean_of(glint, "seconds")
            there = at_time(g, scene, series, seconds, "relmse_corrected")
            line += (f" {mean_of(glint, 'relmse_corrected') / there:.2f} (Cycles at {seconds:.0f} s) |"
                     if there else " – |")
            print(line)
    largest = max(float(r["budget"]) for r in rows)
    print(f"\nThe floor's check at {largest:g} s: relMSE raw, the floor, and relMSE − floor "
          "against all the reference's renders and against each half of them alone (twice the "
          "floor), means over the seeds.\n")
    print("| scene | run | relMSE raw | floor (all) | − floor: all | first half | second half |")
    print("|---|---|---|---|---|---|---|")
    for scene in sorted({r["scene"] for r in rows}):
        for series, (_, _, name) in SERIES.items():
            rs = g.get((scene, largest, *series))
            if rs:
                print(f"| {scene} | {name} | " + " | ".join(
                    f"{mean_of(rs, k):.3g}" for k in ("relmse", "relmse_floor", "relmse_corrected",
                                                       "relmse_corrected_a", "relmse_corrected_b"))
                      + " |")


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
