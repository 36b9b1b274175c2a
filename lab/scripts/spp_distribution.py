#!/usr/bin/env python3
"""Where a frame's samples went: per EXR (glint-render's, glint-final's or bench_final
--frames-dir's), the mean, median, 99th percentile and most samples a pixel took, the most over
the mean, and the share of all samples in the top 1 % of pixels (docs/lab/adaptive-unseen.md).

  /usr/bin/python3 lab/scripts/spp_distribution.py FRAME.exr [FRAME.exr ...]
"""
import sys

import numpy as np
import OpenImageIO as oiio


def distribution(path):
    buf = oiio.ImageBuf(path)
    names = list(buf.spec().channelnames)
    if "sampleCount.Y" not in names:
        sys.exit(f"{path}: no sampleCount.Y layer (expected a Glint render)")
    pixels = buf.get_pixels(oiio.FLOAT)
    if pixels is None or pixels.size == 0:
        sys.exit(f"{path}: could not read the pixels: {buf.geterror()}")
    counts = pixels[..., names.index("sampleCount.Y")].ravel().astype(np.float64)
    mean = counts.mean()
    top = np.sort(counts)[::-1][: max(1, counts.size // 100)]
    return {
        "mean": mean,
        "median": np.median(counts),
        "p99": np.percentile(counts, 99),
        "most": counts.max(),
        "mostOverMean": counts.max() / mean if mean > 0 else float("nan"),
        "top1Share": top.sum() / counts.sum() if counts.sum() > 0 else float("nan"),
    }


def main(paths):
    if not paths:
        sys.exit(__doc__.strip())
    print("| frame | mean spp | median | 99th percentile | most | most / mean | samples in the top 1 % |")
    print("|---|---|---|---|---|---|---|")
    for path in paths:
        d = distribution(path)
        print(f"| {path} | {d['mean']:.0f} | {d['median']:.0f} | {d['p99']:.0f} | {d['most']:.0f} | "
              f"{d['mostOverMean']:.1f} | {100 * d['top1Share']:.0f} % |")


if __name__ == "__main__":
    main(sys.argv[1:])
