#!/usr/bin/env python3
"""Where a frame's samples went: per EXR (glint-render's, glint-final's or bench_final
--frames-dir's), the mean, median, 99th percentile and most samples a pixel took, the most over
the mean, and the share of all samples in the top 1 % of pixels (docs/lab/adaptive-unseen.md). With
--reference, also a sample's relative spread, sqrt(variance of the mean x spp) averaged over R, G
and B over the reference's luminance (R, G, B mean): its median over the top 1 % and over all
pixels.

  /usr/bin/python3 lab/scripts/spp_distribution.py [--reference REF.exr] FRAME.exr [FRAME.exr ...]
"""
import sys

import numpy as np
import OpenImageIO as oiio


def read(path, layers):
    buf = oiio.ImageBuf(path)
    names = list(buf.spec().channelnames)
    for layer in layers:
        if layer not in names:
            sys.exit(f"{path}: no {layer} channel (expected a Glint render)")
    pixels = buf.get_pixels(oiio.FLOAT)
    if pixels is None or pixels.size == 0:
        sys.exit(f"{path}: could not read the pixels: {buf.geterror()}")
    return [pixels[..., names.index(layer)].astype(np.float64) for layer in layers]


def distribution(path, reference):
    variance = ["variance.R", "variance.G", "variance.B"]
    channels = read(path, ["sampleCount.Y"] + (variance if reference is not None else []))
    counts = channels[0].ravel()
    mean = counts.mean()
    order = np.argsort(counts)[::-1]
    top = counts[order[: max(1, counts.size // 100)]]
    spread = {}
    if reference is not None:
        if reference.shape != channels[0].shape:
            sys.exit(f"{path}: {channels[0].shape[1]}x{channels[0].shape[0]}, the reference "
                     f"{reference.shape[1]}x{reference.shape[0]}")
        s = np.mean([np.sqrt(v * channels[0]) for v in channels[1:]], axis=0) / (reference + 1e-4)
        s = s.ravel()
        spread = {"topSpread": np.median(s[order[: top.size]]), "spread": np.median(s)}
    return {
        "mean": mean,
        "median": np.median(counts),
        "p99": np.percentile(counts, 99),
        "most": counts.max(),
        "mostOverMean": counts.max() / mean if mean > 0 else float("nan"),
        "top1Share": top.sum() / counts.sum() if counts.sum() > 0 else float("nan"),
        **spread,
    }


def main(args):
    reference = None
    if len(args) >= 2 and args[0] == "--reference":
        reference = np.mean(read(args[1], ["R", "G", "B"]), axis=0)
        args = args[2:]
    if not args:
        sys.exit(__doc__.strip())
    extra = " spread: top 1 % | spread: all |" if reference is not None else ""
    print("| frame | mean spp | median | 99th percentile | most | most / mean | samples in the top 1 % |" + extra)
    print("|---|---|---|---|---|---|---|" + ("---|---|" if reference is not None else ""))
    for path in args:
        d = distribution(path, reference)
        row = (f"| {path} | {d['mean']:.0f} | {d['median']:.0f} | {d['p99']:.0f} | {d['most']:.0f} | "
               f"{d['mostOverMean']:.1f} | {100 * d['top1Share']:.0f} % |")
        if reference is not None:
            row += f" {d['topSpread']:.2f} | {d['spread']:.2f} |"
        print(row)


if __name__ == "__main__":
    main(sys.argv[1:])
