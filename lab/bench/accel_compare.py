#!/usr/bin/python3
"""Clusters against triangles on one asset (docs/lab/assets-tried.md, "Clusters and the buffer
reader on real assets"; docs/renderer.md, "Acceleration structure").

Renders ASSET with `--set accel=triangles` and `--set accel=clusters` at each seed (default 19 and 20) and
prints, per render, the image mean (the mean of R, G and B over the frame), its standard error
(from the variance layer: the variance of each pixel's mean, pixels independent) and the render's
rays/s; then, per seed, the relMSE of the clusters image against the triangles image of the same
seed (`glint-image diff --metric relmse`) and the difference of their means in standard errors;
and the Monte Carlo noise to judge them by: the relMSE between the first two seeds of one accel.
The two accels agree when every same-seed relMSE is below that noise and every mean differs by
less than 4 standard errors of the difference (the last line says which).

  /usr/bin/python3 lab/bench/accel_compare.py ASSET [--build build] [--spp 16] [--seeds 19 20]
      [--threads 1] [--keep DIR] [-- more glint-render flags]

Exit code: 0 when the accels agree, 1 when they do not, 2 on bad input or a failed render.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

ACCELS = ("triangles", "clusters")


def fail(message):
    print(f"accel_compare: {message}", file=sys.stderr)
    sys.exit(2)


def run_json(command):
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"{' '.join(command)} exited {done.returncode}: {done.stderr.strip()}")
    return json.loads(done.stdout)


def channels(path, names):
    image = oiio.ImageBuf(path)
    if image.has_error:
        fail(f"{path}: {image.geterror()}")
    spec = image.spec()
    pixels = image.get_pixels(oiio.FLOAT)
    missing = [n for n in names if n not in spec.channelnames]
    if missing:
        fail(f"{path}: channels {missing} not found (have {list(spec.channelnames)})")
    return np.stack([pixels[..., spec.channelnames.index(n)] for n in names], axis=-1)


def image_mean(path):
    """Mean of R, G, B over the frame and its standard error."""
    colour = channels(path, ["R", "G", "B"]).astype(np.float64)
    variance = channels(path, ["variance.R", "variance.G", "variance.B"]).astype(np.float64)
    count = colour.size
    return colour.mean(), math.sqrt(variance.sum()) / count


def relmse(build, image, reference):
    result = run_json([f"{build}/bin/glint-image", "diff", image, "--reference", reference,
                       "--metric", "relmse", "--json"])
    return result["value"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("asset")
    parser.add_argument("--build", default="build")
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--seeds", type=int, nargs="+", default=[19, 20])
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--keep", help="write the renders into this folder and keep them")
    parser.add_argument("extra", nargs="*", help="more glint-render flags (after --)")
    args = parser.parse_args()
    if len(args.seeds) < 2:
        fail("--seeds: at least two seeds are needed for the noise between seeds")
    if not os.path.isfile(args.asset):
        fail(f"{args.asset}: no such file")
    work = args.keep or tempfile.mkdtemp(prefix="accel_compare_")
    os.makedirs(work, exist_ok=True)
    stem = os.path.splitext(os.path.basename(args.asset))[0]

    out = {}
    print(f"asset {args.asset}, {args.spp} spp, {args.threads} thread(s), seeds {args.seeds}")
    print("| accel | seed | mean | std. error | rays/s | render s |")
    print("|---|---|---|---|---|---|")
    for accel in ACCELS:
        for seed in args.seeds:
            path = os.path.join(work, f"{stem}_{accel}_{seed}.exr")
            stats = run_json([f"{args.build}/bin/glint-render", args.asset, "--spp",
                              str(args.spp), "--seed", str(seed), "--threads",
                              str(args.threads), "--set", f"accel={accel}", "--out", path, "--json"] +
                             args.extra)
            mean, error = image_mean(path)
            out[accel, seed] = (path, mean, error)
            print(f"| {accel} | {seed} | {mean:.6g} | {error:.3g} | "
                  f"{stats['raysPerSecond']:.4g} | {stats['seconds']:.3g} |")

    first, second = args.seeds[0], args.seeds[1]
    noise = {a: relmse(args.build, out[a, second][0], out[a, first][0]) for a in ACCELS}
    floor = min(noise.values())
    print(f"noise: relMSE seed {second} against seed {first}: "
          + ", ".join(f"{a} {noise[a]:.4g}" for a in ACCELS))
    agree = True
    for seed in args.seeds:
        value = relmse(args.build, out["clusters", seed][0], out["triangles", seed][0])
        _, mc, ec = out["clusters", seed]
        _, mt, et = out["triangles", seed]
        # Same seed: the two images share their samples, so the error of the difference is at
        # most the sum of the two (not independent); 4 of those is a loose bound.
        sigmas = abs(mc - mt) / max(ec + et, 1e-30)
        ok = value < floor and sigmas < 4.0
        agree = agree and ok
        print(f"seed {seed}: clusters against triangles relMSE {value:.4g} "
              f"({value / floor:.3g} of the noise), mean {mc:.6g} against {mt:.6g} "
              f"({(mc - mt) / mt * 100 if mt else 0:+.4f} %, {sigmas:.2f} std. errors)"
              f"{'' if ok else '  <-- differs'}")
    print("agree" if agree else "DIFFER")
    sys.exit(0 if agree else 1)


if __name__ == "__main__":
    main()
