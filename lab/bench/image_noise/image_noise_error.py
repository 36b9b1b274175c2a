#!/usr/bin/python3
"""The image-only noise estimator against Glint's own variance layer (docs/auto.md, "Error
estimation without variance or halves").

For each render (a Glint EXR with its variance layer) and its reference: the estimate that
`glint-denoise auto --estimator image --noise-out` writes, compared with the variance layer, and
the SSIM auto reaches with the estimated and with the render's variance. Prints a Markdown table.

  /usr/bin/python3 lab/bench/image_noise/image_noise_error.py --bin build/bin/glint-denoise \\
      RENDER.exr:REFERENCE.exr ...

Figures per render: the frame-mean variance's relative error, mean(est) / mean(true) - 1; the
median over pixels and channels of |est / true - 1| against the variance layer itself (a sample
variance, noisy at low spp) and against it averaged over a 7x7 box (the scale the estimator
works at); SSIM of auto with the render's variance (sure) and with the estimate (image).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio


EXTRA = []  # tuning flags of the image-only estimator


def read_channels(path, names):
    """The named channels of an EXR as an (h, w, len(names)) float array."""
    inp = oiio.ImageInput.open(path)
    if inp is None:
        sys.exit(f"{path}: cannot open ({oiio.geterror()})")
    spec = inp.spec()
    data = inp.read_image(0, 0, 0, spec.nchannels, "float")
    inp.close()
    data = np.asarray(data).reshape(spec.height, spec.width, spec.nchannels)
    idx = [list(spec.channelnames).index(n) for n in names]
    return data[:, :, idx].astype(np.float64)


def box(a, r):
    """Mean over a (2r+1)^2 box per channel, clipped at the borders."""
    h, w = a.shape[:2]
    c = np.cumsum(np.cumsum(np.pad(a, ((1, 0), (1, 0), (0, 0))), 0), 1)
    y0 = np.clip(np.arange(h) - r, 0, h)
    y1 = np.clip(np.arange(h) + r + 1, 0, h)
    x0 = np.clip(np.arange(w) - r, 0, w)
    x1 = np.clip(np.arange(w) + r + 1, 0, w)
    s = c[y1][:, x1] - c[y0][:, x1] - c[y1][:, x0] + c[y0][:, x0]
    n = (y1 - y0)[:, None] * (x1 - x0)[None, :]
    return s / n[:, :, None]


def run_auto(binary, render, reference, estimator, tmp, noise_out=None):
    cmd = [binary, "auto", render, "--out", os.path.join(tmp, "out.exr"), "--reference",
           reference, "--estimator", estimator, "--json"]
    if noise_out:
        cmd += ["--noise-out", noise_out] + EXTRA
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: {r.stderr.strip()}")
    return json.loads(r.stdout)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--bin", default="build/bin/glint-denoise")
    p.add_argument("--noise-window", help="passed to auto --estimator image")
    p.add_argument("--noise-alpha", help="passed to auto --estimator image")
    p.add_argument("--noise-tail", help="passed to auto --estimator image")
    p.add_argument("pairs", nargs="+", help="RENDER.exr:REFERENCE.exr")
    a = p.parse_args()
    for flag, value in (("--noise-window", a.noise_window), ("--noise-alpha", a.noise_alpha),
                        ("--noise-tail", a.noise_tail)):
        if value is not None:
            EXTRA.extend([flag, value])
    print("| render | frame-mean rel. error | median per-pixel rel. error (raw / 7x7) "
          "| SSIM auto, true variance | SSIM auto, estimated |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for pair in a.pairs:
            render, reference = pair.split(":")
            noise = os.path.join(tmp, "noise.exr")
            image = run_auto(a.bin, render, reference, "image", tmp, noise)
            sure = run_auto(a.bin, render, reference, "sure", tmp)
            est = read_channels(noise, ["R", "G", "B"])
            true = read_channels(render, ["variance.R", "variance.G", "variance.B"])
            frame = est.mean() / true.mean() - 1.0
            ok = true > 0
            raw = np.median(np.abs(est[ok] / true[ok] - 1.0))
            smooth = box(true, 3)
            ok = smooth > 0
            local = np.median(np.abs(est[ok] / smooth[ok] - 1.0))
            print(f"| {os.path.basename(render)} | {frame:+.2f} | {raw:.2f} / {local:.2f} "
                  f"| {sure['metrics']['ssim']:.4f} | {image['metrics']['ssim']:.4f} |",
                  flush=True)


if __name__ == "__main__":
    main()
