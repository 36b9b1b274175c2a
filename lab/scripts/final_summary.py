#!/usr/bin/env python3
"""bench_final's TSV rows (any number of files) -> a Markdown table: per scene, budget and seed,
uniform + auto's relMSE and each adaptive way's change against it (mean spp in brackets), then
the geometric mean of each way's ratio per scene and budget (docs/lab/adaptive-sampling.md).
The adaptive ways are the columns in the order the rows first name them (bench_final's fixed,
variance, denoiser; bench_adaptive_equal_time's fixed, variance, spread).
   python3 lab/scripts/final_summary.py run1.tsv run2.tsv ..."""
import csv
import math
import sys
from collections import defaultdict

WAYS = []
rows = defaultdict(dict)
for path in sys.argv[1:]:
    with open(path) as f:
        for r in csv.DictReader((l for l in f if "\t" in l), delimiter="\t"):
            if r.get("relMSE"):
                rows[(r["scene"], int(float(r["budget"])), int(r["seed"]))][r["way"]] = r
                if r["way"] != "uniform" and r["way"] not in WAYS:
                    WAYS.append(r["way"])

print("| scene | budget | seed | uniform | " + " | ".join(WAYS) + " |")
print("|---|---|---|---|" + "---|" * len(WAYS))
ratios = defaultdict(list)
for key in sorted(rows):
    ways = rows[key]
    if "uniform" not in ways:
        continue
    u = float(ways["uniform"]["relMSE"])
    cells = []
    for w in WAYS:
        if w not in ways:
            cells.append("–")
            continue
        ratio = float(ways[w]["relMSE"]) / u
        ratios[(key[0], key[1], w)].append(ratio)
        cells.append(f"{100 * (ratio - 1):+.0f} % ({float(ways[w]['meanSpp']):.0f})")
    print(f"| {key[0]} | {key[1]} s | {key[2]} | {u:.3g} ({float(ways['uniform']['meanSpp']):.0f}) | "
          + " | ".join(cells) + " |")
print()
print("| scene | budget | seeds | " + " | ".join(WAYS) + " |")
print("|---|---|---|" + "---|" * len(WAYS))
for scene, budget in sorted({(s, b) for s, b, _ in ratios}):
    cells, n = [], 0
    for w in WAYS:
        r = ratios.get((scene, budget, w), [])
        n = max(n, len(r))
        g = math.exp(sum(map(math.log, r)) / len(r)) if r else float("nan")
        cells.append(f"{100 * (g - 1):+.0f} %" if r else "–")
    print(f"| {scene} | {budget} s | {n} | " + " | ".join(cells) + " |")
