#!/usr/bin/python3
"""Plots of the speed-versus-accuracy report (docs/tradeoffs.md) from the CSVs glint-report
writes. Run by tests/perf/report/run.sh with Debian's python3-matplotlib:

    /usr/bin/python3 tests/perf/report/plot_tradeoffs.py docs/tradeoffs

Also writes summary.csv: the fitted convergence slopes and the frontier's winners."""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

OUT = sys.argv[1] if len(sys.argv) > 1 else "docs/tradeoffs"
DPI = 80


def rows(name):
    with open(os.path.join(OUT, name)) as f:
        return list(csv.DictReader(f))


def slope(xs, ys):
    """Least-squares slope of log y against log x."""
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


def save(fig, name):
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, name), dpi=DPI)
    plt.close(fig)


summary = [["what", "key", "value"]]

# 1. Convergence: relMSE and SSIM against spp, slopes fitted over 16 ... 1024 spp.
scenes = ["cornell", "glossy", "door", "pool", "dof"]
fig, axes = plt.subplots(2, 5, figsize=(17, 6.5))
for i, scene in enumerate(scenes):
    data = rows(f"convergence_{scene}.csv")
    for method in ["power", "balance", "none", "mlt"]:
        pts = [(int(r["spp"]), float(r["relmse"]), float(r["ssim"])) for r in data
               if r["method"] == method]
        if not pts:
            continue
        fit = [(s, e) for s, e, _ in pts if s >= 16]
        k = slope([s for s, _ in fit], [e for _, e in fit]) if len(fit) >= 2 else float("nan")
        summary.append(["convergence_slope", f"{scene}/{method}", f"{k:.3f}"])
        label = {"power": "PT power", "balance": "PT balance", "none": "PT no MIS (BSDF)",
                 "mlt": "MLT"}[method]
        axes[0][i].loglog([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3,
                          label=f"{label} (slope {k:.2f})")
        axes[1][i].semilogx([p[0] for p in pts], [p[2] for p in pts], "o-", ms=3, label=label)
    spp = [1, 1024]
    first = [float(r["relmse"]) for r in data if r["method"] == "power" and r["spp"] == "16"]
    if first:
        axes[0][i].loglog(spp, [first[0] * 16 / s for s in spp], "k:", lw=1, label="1/N")
    axes[0][i].set_title(f"{scene}: relMSE vs spp")
    axes[0][i].set_xlabel("samples per pixel")
    axes[0][i].legend(fontsize=7)
    axes[1][i].set_title(f"{scene}: SSIM vs spp")
    axes[1][i].set_xlabel("samples per pixel")
axes[0][0].set_ylabel("relMSE to reference")
axes[1][0].set_ylabel("SSIM to reference")
save(fig, "convergence.png")

# Seconds per spp, for the same renders.
fig, ax = plt.subplots(figsize=(7, 4.5))
for scene in scenes:
    data = rows(f"convergence_{scene}.csv")
    pts = [(int(r["spp"]), float(r["seconds"])) for r in data if r["method"] == "power"]
    ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3, label=scene)
ax.set_xlabel("samples per pixel")
ax.set_ylabel("seconds (2 threads, half resolution)")
ax.set_title("Render time vs spp (PT, power heuristic)")
ax.legend()
save(fig, "convergence_seconds.png")

# 2. Against Cycles at equal time.
fig, ax = plt.subplots(figsize=(7, 4.5))
glint = rows("peer_glint.csv")
for method, label in [("power", "Glint PT"), ("mlt", "Glint MLT")]:
    pts = [(float(r["seconds"]), float(r["relmse"])) for r in glint if r["method"] == method]
    ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3, label=label)
cycles = rows("peer_cycles.csv")
if cycles:
    ax.loglog([float(r["seconds"]) for r in cycles], [float(r["relmse"]) for r in cycles], "s-",
              ms=3, label="Cycles 3.4.1")
    # Who wins at each budget: relMSE interpolated in log-log at Cycles' times.
    pts = sorted((float(r["seconds"]), float(r["relmse"])) for r in glint if r["method"] == "power")
    for r in cycles:
        t, e = float(r["seconds"]), float(r["relmse"])
        below = [p for p in pts if p[0] <= t]
        if below:
            summary.append(["peer_at_cycles_time", f"{t:.2f}s",
                            f"glint {below[-1][1]:.5f} cycles {e:.5f}"])
ax.set_xlabel("wall-clock seconds (2 threads; Cycles: render call only)")
ax.set_ylabel("relMSE to scenes/cornell/reference.exr")
ax.set_title("Cornell box 256²: error against time")
ax.legend()
save(fig, "peer.png")

# 3. Denoising: seconds against SSIM gain at 4, 16 and 64 spp.
den = rows("denoise.csv")
fig, axes = plt.subplots(1, 3, figsize=(15, 4.5), sharey=True)
markers = {"default": "o", "soft25": "v", "soft75": "^"}
for ax, spp in zip(axes, ["4", "16", "64"]):
    sel = [r for r in den if r["spp"] == spp and r["filter"] != "none"]
    if not sel:
        continue
    for name in sorted({r["filter"] for r in sel}):
        for r in sel:
            if r["filter"] != name:
                continue
            gain = float(r["ssim"]) - float(r["ssim_noisy"])
            ax.semilogx(float(r["filter_seconds"]), gain, markers[r["setting"]],
                        color=f"C{sorted({q['filter'] for q in sel}).index(name)}",
                        label=name if r["setting"] == "default" else None)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_title(f"{spp} spp (noisy SSIM {float(sel[0]['ssim_noisy']):.3f})")
    ax.set_xlabel("filter seconds (2 threads, 256²)")
axes[0].set_ylabel("SSIM gain over the noisy render")
axes[0].legend(fontsize=8, title="o default, v/^ 25/75 % of soft range", title_fontsize=7)
save(fig, "denoise.png")

# 4. The render + denoise frontier: best SSIM within a budget T.
budgets = [0.25, 0.5, 1, 2, 4, 8, 15, 30]
best_rows = []
for t in budgets:
    best = None
    for r in den:
        cost = float(r["render_seconds"]) + float(r["filter_seconds"])
        if cost <= t and (best is None or float(r["ssim"]) > float(best["ssim"])):
            best = r
    render_only = max((r for r in den if r["filter"] == "none" and float(r["render_seconds"]) <= t),
                      key=lambda r: float(r["ssim"]), default=None)
    best_rows.append((t, best, render_only))
    if best:
        summary.append(["frontier", f"{t}s",
                        f"{best['spp']} spp + {best['filter']} ({best['setting']}): "
                        f"SSIM {float(best['ssim']):.4f}; render only "
                        f"{float(render_only['ssim']) if render_only else float('nan'):.4f}"])
fig, ax = plt.subplots(figsize=(8, 4.8))
pts = [(t, float(b["ssim"])) for t, b, _ in best_rows if b]
ax.semilogx([p[0] for p in pts], [p[1] for p in pts], "o-", label="best render + filter split")
pts2 = [(t, float(r["ssim"])) for t, _, r in best_rows if r]
ax.semilogx([p[0] for p in pts2], [p[1] for p in pts2], "s--", label="render only")
for t, b, _ in best_rows:
    if b:
        frac = float(b["filter_seconds"]) / max(1e-9, float(b["render_seconds"]) +
                                                float(b["filter_seconds"]))
        ax.annotate(f"{b['spp']} spp\n{b['filter']}\n{100 * frac:.0f}% filter", (t, float(b["ssim"])),
                    fontsize=6, textcoords="offset points", xytext=(0, 6), ha="center")
ax.set_xlabel("time budget T (seconds, 2 threads, cornell 256²)")
ax.set_ylabel("best SSIM reachable")
ax.set_title("Render longer or denoise? The frontier")
ax.set_ylim(top=1.08)
ax.legend(loc="lower right")
save(fig, "frontier.png")

# 5. bilateral-mc: PSNR to the exact filter against samples, per pattern and sigma_s.
bmc = rows("bilateral_mc.csv")
sigmas = sorted({float(r["sigma_s"]) for r in bmc})
fig, grid = plt.subplots(2, len(sigmas), figsize=(3.4 * len(sigmas), 6.5), sharey="row")
for j, sig in enumerate(sigmas):
    ax, at = grid[0][j], grid[1][j]
    for pattern in ["poisson", "regular", "random", "stratified"]:
        pts = [(int(r["k"]), float(r["psnr"]), float(r["seconds"])) for r in bmc
               if float(r["sigma_s"]) == sig and r["pattern"] == pattern]
        ax.plot([p[0] for p in pts], [min(p[1], 80) for p in pts], "o-", ms=3, label=pattern)
        at.plot([p[0] for p in pts], [1000 * p[2] for p in pts], "o-", ms=3, label=pattern)
    r0 = next(r for r in bmc if float(r["sigma_s"]) == sig)
    ax.set_title(f"σs {sig:g} px (radius {r0['radius']}; exact {1000 * float(r0['exact_seconds']):.0f} ms)",
                 fontsize=9)
    at.axhline(1000 * float(r0["exact_seconds"]), color="k", ls=":", lw=1, label="exact filter")
    at.set_xlabel("k (k·N samples a pixel)")
grid[0][0].set_ylabel("PSNR to the exact bilateral (dB)")
grid[1][0].set_ylabel("milliseconds (2 threads, 128²)")
grid[0][0].legend(fontsize=8)
grid[1][0].legend(fontsize=7)
save(fig, "bilateral_mc.png")

# 6. Threads and memory.
thr = rows("threads.csv")
fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
works = ["render", "bank", "session"]
for j, threads in enumerate(["1", "2"]):
    a1.bar([i + 0.38 * j for i in range(3)],
           [float(next(r for r in thr if r["workload"] == w and r["threads"] == threads)["seconds"])
            for w in works], width=0.38, label=f"{threads} thread{'s' if threads == '2' else ''}")
a1.set_xticks([i + 0.19 for i in range(3)], ["render 16 spp", "bank of 16 (+defaults)",
                                             "session: 2 layers"])
a1.set_ylabel("seconds (cornell 256²)")
a1.set_title("Thread scaling")
a1.legend()
a2.bar(range(3), [float(next(r for r in thr if r["workload"] == w)["bytes_per_megapixel"]) / 2**20
                  for w in works])
a2.set_xticks(range(3), works)
a2.set_ylabel("peak memory above baseline (MiB per megapixel)")
a2.set_title("Peak memory per megapixel")
save(fig, "threads.png")
for w in works:
    one = float(next(r for r in thr if r["workload"] == w and r["threads"] == "1")["seconds"])
    two = float(next(r for r in thr if r["workload"] == w and r["threads"] == "2")["seconds"])
    mib = float(next(r for r in thr if r["workload"] == w)["bytes_per_megapixel"]) / 2**20
    summary.append(["threads", w, f"1 thread {one:.3f}s, 2 threads {two:.3f}s "
                                  f"(speed-up {one / two:.2f}), {mib:.0f} MiB/MP"])

with open(os.path.join(OUT, "summary.csv"), "w", newline="") as f:
    csv.writer(f).writerows(summary)
for row in summary[1:]:
    print(" | ".join(row))
