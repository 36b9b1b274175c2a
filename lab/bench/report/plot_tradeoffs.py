#!/usr/bin/python3
"""Plots of the speed-versus-accuracy report (docs/lab/tradeoffs.md) from the CSVs glint-report
writes. Run by lab/bench/report/run.sh with Debian's python3-matplotlib:

    /usr/bin/python3 lab/bench/report/plot_tradeoffs.py docs/tradeoffs

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

# 1. Convergence: relMSE and SSIM against spp. The slope is fitted over 16 ... 1024 spp to the
# relMSE minus the reference's own noise floor (the error of the image itself); the raw slope
# goes to summary.csv too.
scenes = ["cornell", "glossy", "door", "pool", "dof"]
fig, axes = plt.subplots(2, 5, figsize=(17, 6.5))
for i, scene in enumerate(scenes):
    data = rows(f"convergence_{scene}.csv")
    for method in ["power", "balance", "none", "mlt"]:
        pts = [(int(r["spp"]), float(r["relmse"]), float(r["ssim"]), float(r["seconds"]))
               for r in data if r["method"] == method]
        if not pts:
            continue
        floor = float(data[0].get("reference_floor") or 0.0)
        fit = [(s, e - floor) for s, e, *_ in pts if s >= 16 and e > floor]
        k = slope([s for s, _ in fit], [e for _, e in fit]) if len(fit) >= 2 else float("nan")
        raw = [(s, e) for s, e, *_ in pts if s >= 16]
        k_raw = slope([s for s, _ in raw], [e for _, e in raw]) if len(raw) >= 2 else float("nan")
        summary.append(["convergence_slope", f"{scene}/{method}", f"{k:.3f}"])
        summary.append(["convergence_slope_raw", f"{scene}/{method}", f"{k_raw:.3f}"])
        summary.append(["convergence_relmse_1024", f"{scene}/{method}",
                        f"{pts[-1][1]:.5g} SSIM {pts[-1][2]:.4f} in {pts[-1][3]:.2f}s"])
        label = {"power": "PT power", "balance": "PT balance", "none": "PT no MIS (BSDF)",
                 "mlt": "MLT"}[method]
        axes[0][i].loglog([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3,
                          label=f"{label} (slope {k:.2f})")
        axes[1][i].semilogx([p[0] for p in pts], [p[2] for p in pts], "o-", ms=3, label=label)
    spp = [1, 1024]
    first = [float(r["relmse"]) for r in data if r["method"] == "power" and r["spp"] == "16"]
    if first:
        axes[0][i].loglog(spp, [first[0] * 16 / s for s in spp], "k:", lw=1, label="1/N")
    floor = float(data[0].get("reference_floor") or 0.0)
    if floor > 0:
        axes[0][i].axhline(floor, color="grey", ls="--", lw=1,
                           label=f"reference floor ({data[0]['reference_spp']} spp)")
        summary.append(["reference_floor", scene,
                        f"{floor:.3g} (reference {data[0]['reference_spp']} spp)"])
    axes[0][i].set_title(f"{scene}: relMSE vs spp")
    axes[0][i].set_xlabel("samples per pixel")
    axes[0][i].legend(fontsize=6.5, loc="lower left")
    axes[1][i].set_title(f"{scene}: SSIM vs spp")
    axes[1][i].set_xlabel("samples per pixel")
fig.suptitle("Convergence at half resolution (2 threads, seed 1); slope of relMSE minus the "
             "reference floor over 16…1024 spp", fontsize=10)
axes[0][0].set_ylabel("relMSE to reference")
axes[1][0].set_ylabel("SSIM to reference")
save(fig, "convergence.png")

# FLIP (HDR-FLIP's mean error) against spp, for the same renders; CSVs from before it have no
# flip column and are skipped.
fig, axes = plt.subplots(1, 5, figsize=(17, 3.4))
for i, scene in enumerate(scenes):
    data = [r for r in rows(f"convergence_{scene}.csv") if r.get("flip") not in (None, "", "nan")]
    for method in ["power", "balance", "none", "mlt"]:
        pts = [(int(r["spp"]), float(r["flip"])) for r in data if r["method"] == method]
        if pts:
            axes[i].loglog([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3, label=method)
            summary.append(["convergence_flip_1024", f"{scene}/{method}", f"{pts[-1][1]:.4f}"])
    axes[i].set_title(f"{scene}: HDR-FLIP vs spp")
    axes[i].set_xlabel("samples per pixel")
    axes[i].legend(fontsize=6.5, loc="lower left")
axes[0].set_ylabel("HDR-FLIP mean to reference")
save(fig, "convergence_flip.png")

# Seconds against spp and error against seconds, for the same renders.
fig, axes = plt.subplots(2, 5, figsize=(17, 6.5))
for i, scene in enumerate(scenes):
    data = rows(f"convergence_{scene}.csv")
    for method, label in [("power", "PT power"), ("balance", "PT balance"),
                          ("none", "PT no MIS (BSDF)"), ("mlt", "MLT")]:
        pts = [(int(r["spp"]), float(r["seconds"]), float(r["relmse"])) for r in data
               if r["method"] == method]
        axes[0][i].loglog([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3, label=label)
        axes[1][i].loglog([p[1] for p in pts], [p[2] for p in pts], "o-", ms=3, label=label)
    axes[0][i].set_title(f"{scene}: render time vs spp")
    axes[0][i].set_xlabel("samples per pixel")
    axes[1][i].set_title(f"{scene}: relMSE vs render time")
    axes[1][i].set_xlabel("seconds (2 threads)")
fig.suptitle("Cost of the convergence renders (half resolution, 2 threads)", fontsize=10)
axes[0][0].set_ylabel("render seconds")
axes[1][0].set_ylabel("relMSE to reference")
axes[0][0].legend(fontsize=7)
axes[1][0].legend(fontsize=7, loc="lower left")
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
        above = [p for p in pts if p[0] > t]
        if below:
            # Glint's error at Cycles' time: its last finished spp level, and the log-log
            # interpolation between the levels around t (what a time-limited render would get).
            g = below[-1][1]
            if above:
                (t0, e0), (t1, e1) = below[-1], above[0]
                w = math.log(t / t0) / math.log(t1 / t0)
                g = math.exp((1 - w) * math.log(e0) + w * math.log(e1))
            summary.append(["peer_at_cycles_time", f"{t:.2f}s",
                            f"glint {below[-1][1]:.5f} (interpolated {g:.5f}) cycles {e:.5f}"
                            f" ratio {g / e:.2f}"])
floor = float(glint[0].get("reference_floor") or 0.0)
if floor > 0:
    ax.axhline(floor, color="grey", ls="--", lw=1,
               label=f"reference floor ({glint[0]['reference_spp']} spp)")
for method in ["power", "mlt"]:
    for r in glint:
        if r["method"] == method:
            summary.append(["peer_glint", f"{method}/{r['spp']}spp",
                            f"{float(r['seconds']):.3f}s relMSE {float(r['relmse']):.5f}"])
for r in cycles:
    summary.append(["peer_cycles", f"{r['spp']}spp",
                    f"{float(r['seconds']):.3f}s relMSE {float(r['relmse']):.5f}"])
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
    sel = [r for r in den if r["spp"] == spp and r["setting"] in markers]
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
fig.suptitle("Denoising the Cornell box: each filter at its defaults and at 25 % / 75 % of its "
             "parameters' soft ranges", fontsize=10)
save(fig, "denoise.png")
for spp in sorted({int(r["spp"]) for r in den}):
    sel = [r for r in den if int(r["spp"]) == spp and r["filter"] != "none"]
    best = max(sel, key=lambda r: float(r["ssim"]))
    summary.append(["denoise_best", f"{spp}spp",
                    f"noisy {float(best['ssim_noisy']):.4f} -> {float(best['ssim']):.4f} "
                    f"{best['filter']} ({best['setting']}: {best.get('params', '')}) "
                    f"{1000 * float(best['filter_seconds']):.1f}ms"])

# 4. The render + denoise frontier: best SSIM within a budget T over every split of T between
# rendering (any spp of part 3's progressive render) and one filter (part 3's settings and the
# members of a 16-member bank).
budgets = [0.25, 0.5, 1, 2, 4, 8, 15, 30]


def cost(r):
    return float(r["render_seconds"]) + float(r["filter_seconds"])


best_rows = []
for t in budgets:
    best = max((r for r in den if cost(r) <= t), key=lambda r: float(r["ssim"]), default=None)
    render_only = max((r for r in den if r["filter"] == "none" and cost(r) <= t),
                      key=lambda r: float(r["ssim"]), default=None)
    best_rows.append((t, best, render_only))
    if best:
        summary.append(["frontier", f"{t}s",
                        f"{best['spp']} spp ({float(best['render_seconds']):.3f}s) + "
                        f"{best['filter']} ({best['setting']}, {float(best['filter_seconds']):.3f}s):"
                        f" SSIM {float(best['ssim']):.4f}; render only "
                        f"{float(render_only['ssim']) if render_only else float('nan'):.4f}"
                        f" ({render_only['spp'] if render_only else '-'} spp)"])
fig, ax = plt.subplots(figsize=(8.5, 5))
ax.semilogx([cost(r) for r in den if r["filter"] != "none"],
            [float(r["ssim"]) for r in den if r["filter"] != "none"], ".", color="0.8", ms=3,
            label="every render + filter pair (cost = render + filter time)", zorder=1)
pts = [(t, float(b["ssim"])) for t, b, _ in best_rows if b]
ax.semilogx([p[0] for p in pts], [p[1] for p in pts], "o-", label="best split of the budget T",
            zorder=3)
pts2 = [(t, float(r["ssim"])) for t, _, r in best_rows if r]
ax.semilogx([p[0] for p in pts2], [p[1] for p in pts2], "s--", label="render only", zorder=3)
for t, b, _ in best_rows:
    if b:
        frac = float(b["filter_seconds"]) / max(1e-9, cost(b))
        ax.annotate(f"{b['spp']} spp\n{b['filter']}\n{100 * frac:.0f}% filter",
                    (t, float(b["ssim"])), fontsize=6, textcoords="offset points", xytext=(0, 6),
                    ha="center")
ax.set_xlabel("time budget T (seconds: render + filter, 2 threads, cornell 256²)")
ax.set_ylabel("best SSIM reachable within T")
ax.set_title("Render longer or denoise? Best SSIM within a time budget")
ax.set_xlim(0.1, 40)
ax.set_ylim(0.2, 1.1)
ax.legend(loc="lower right", fontsize=8)
save(fig, "frontier.png")

# 5. bilateral-mc: PSNR to the exact filter against samples, per pattern and sigma_s.
bmc = rows("bilateral_mc.csv")
sigmas = sorted({float(r["sigma_s"]) for r in bmc})
fig, grid = plt.subplots(2, len(sigmas), figsize=(3.4 * len(sigmas), 6.5), sharey="row")
for j, sig in enumerate(sigmas):
    ax, at = grid[0][j], grid[1][j]
    for pattern in ["poisson", "regular", "random", "stratified"]:
        name = {"poisson": "Poisson disk", "stratified": "jittered (stratified)"}.get(pattern,
                                                                                 pattern)
        pts = [(int(r["k"]), float(r["psnr"]), float(r["seconds"])) for r in bmc
               if float(r["sigma_s"]) == sig and r["pattern"] == pattern]
        ax.plot([p[0] for p in pts], [min(p[1], 80) for p in pts], "o-", ms=3, label=name)
        at.plot([p[0] for p in pts], [1000 * p[2] for p in pts], "o-", ms=3, label=name)
    r0 = next(r for r in bmc if float(r["sigma_s"]) == sig)
    ax.set_title(f"σs {sig:g} px (radius {r0['radius']}; exact {1000 * float(r0['exact_seconds']):.0f} ms)",
                 fontsize=9)
    at.axhline(1000 * float(r0["exact_seconds"]), color="k", ls=":", lw=1, label="exact filter")
    at.set_xlabel("k (k·N samples a pixel)")
grid[0][0].set_ylabel("PSNR to the exact bilateral (dB)")
grid[1][0].set_ylabel("milliseconds (2 threads, 128²)")
grid[0][0].legend(fontsize=8)
grid[1][0].legend(fontsize=7)
fig.suptitle("bilateral-mc against the exact bilateral (σr 0.1) on Glint's cornell render, "
             "per sampling pattern (Banterle et al. 2012, Fig. 3)", fontsize=10)
save(fig, "bilateral_mc.png")
for sig in sigmas:
    for pattern in ["poisson", "regular", "random", "stratified"]:
        sel = {int(r["k"]): r for r in bmc if float(r["sigma_s"]) == sig and r["pattern"] == pattern}
        summary.append(["bilateral_mc", f"sigma {sig:g}/{pattern}",
                        " ".join(f"k{k}:{float(r['psnr']):.1f}dB/{1000 * float(r['seconds']):.1f}ms"
                                 for k, r in sorted(sel.items()))
                        + f" exact {1000 * float(next(iter(sel.values()))['exact_seconds']):.1f}ms"])

# 6. Threads and memory.
thr = rows("threads.csv")
works = ["render", "bank", "session"]
labels = ["render 16 spp", "bank of 16 (+defaults)", "session: 2 layers"]


def thr_row(w, threads="1"):
    return next(r for r in thr if r["workload"] == w and r["threads"] == threads)


fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
for j, threads in enumerate(["1", "2"]):
    secs = [float(thr_row(w, threads)["seconds"]) for w in works]
    a1.bar([i + 0.38 * j for i in range(3)], secs, width=0.38,
           label=f"{threads} thread{'s' if threads == '2' else ''}")
for i, w in enumerate(works):
    one, two = float(thr_row(w, "1")["seconds"]), float(thr_row(w, "2")["seconds"])
    a1.annotate(f"×{one / two:.2f}", (i + 0.38, two), ha="center", textcoords="offset points",
                xytext=(0, 3), fontsize=8)
a1.set_xticks([i + 0.19 for i in range(3)], labels, fontsize=8)
a1.set_ylabel(f"seconds (cornell {float(thr[0]['megapixels_small']):.3f} MP, best of 3)")
a1.set_title("Thread scaling (×: speed-up on 2 threads)")
a1.legend()
per_mp = [float(thr_row(w)["bytes_per_megapixel"]) / 2**20 for w in works]
a2.bar(range(3), per_mp)
for i, v in enumerate(per_mp):
    a2.annotate(f"{v:.0f}", (i, v), ha="center", textcoords="offset points", xytext=(0, 3),
                fontsize=8)
a2.set_xticks(range(3), labels, fontsize=8)
a2.set_ylabel("MiB per megapixel")
a2.set_title("Peak memory per megapixel (marginal, 256² → 1024²)", fontsize=10)
save(fig, "threads.png")
for w in works:
    one, two = float(thr_row(w, "1")["seconds"]), float(thr_row(w, "2")["seconds"])
    r = thr_row(w)
    summary.append(["threads", w, f"1 thread {one:.3f}s, 2 threads {two:.3f}s "
                                  f"(speed-up {one / two:.2f}), "
                                  f"{float(r['bytes_per_megapixel']) / 2**20:.0f} MiB/MP; peak "
                                  f"{float(r['peak_bytes_small']) / 2**20:.1f} MiB at "
                                  f"{float(r['megapixels_small']):.3f} MP, "
                                  f"{float(r['peak_bytes_large']) / 2**20:.1f} MiB at "
                                  f"{float(r['megapixels_large']):.3f} MP"])

with open(os.path.join(OUT, "summary.csv"), "w", newline="") as f:
    csv.writer(f).writerows(summary)
for row in summary[1:]:
    print(" | ".join(row))
