#!/usr/bin/env python3
"""Does Metropolis report the error of its image's mean? (docs/metropolis.md, "Error of the
image's mean"). Renders SCENE with --set integrator=mlt at render seeds FIRST..LAST and prints, for
b and for the image's mean luminance, the standard deviation of the relative value over the
seeds against the root mean square of the reported relative error (glint:mltBRelStdErr,
glint:mltMeanRelStdErr): 1 means the reported error is right.

  /usr/bin/python3 lab/bench/mlt_error_spread.py build/bin/glint-render \
      tests/render/data/cornell.json 15 34 [--spp 16]
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile

import OpenImageIO as oiio


def main():
    p = argparse.ArgumentParser(prog="mlt_error_spread.py")
    p.add_argument("glint_render")
    p.add_argument("scene")
    p.add_argument("first", type=int)
    p.add_argument("last", type=int)
    p.add_argument("--spp", type=int, default=16)
    a = p.parse_args()
    if a.last - a.first < 2:
        sys.exit("mlt_error_spread.py: give at least three seeds")
    bs, means, b_err, mean_err = [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(a.first, a.last + 1):
            out = os.path.join(tmp, f"s{seed}.exr")
            subprocess.run([a.glint_render, a.scene, "--set", "integrator=mlt", "--spp", str(a.spp),
                            "--seed", str(seed), "--threads", "2", "--out", out],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            buf = oiio.ImageBuf(out)
            spec = buf.spec()
            px = buf.get_pixels(oiio.FLOAT)
            lum = (0.2126 * px[:, :, 0] + 0.7152 * px[:, :, 1] + 0.0722 * px[:, :, 2]).mean()
            means.append(float(lum))
            bs.append(float(spec.get_string_attribute("glint:mltB")))
            b_err.append(float(spec.get_string_attribute("glint:mltBRelStdErr")))
            mean_err.append(float(spec.get_string_attribute("glint:mltMeanRelStdErr")))

    def spread(values):
        m = statistics.fmean(values)
        return statistics.stdev(values) / m

    def rms(values):
        return statistics.fmean(v * v for v in values) ** 0.5

    n = len(bs)
    print(f"{n} seeds; b: spread {100 * spread(bs):.3f} % / reported {100 * rms(b_err):.3f} % "
          f"({spread(bs) / rms(b_err):.2f})")
    print(f"image mean: spread {100 * spread(means):.3f} % / reported "
          f"{100 * rms(mean_err):.3f} % ({spread(means) / rms(mean_err):.2f}); against b's "
          f"error alone {spread(means) / rms(b_err):.2f}")


if __name__ == "__main__":
    main()
