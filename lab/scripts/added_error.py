#!/usr/bin/env python3
"""Where a denoised frame adds error to the render it came from: per pixel, OUT's relative squared
error against the reference less INPUT's (relMSE per pixel as glint-image diff computes it: the
mean over RGB of (x - ref)^2 / (ref^2 + 0.01)), then the frame's relMSE of each, the error added
and removed in all, the N pixels that add the most (x, y, what they add, the red channel of OUT,
INPUT and the reference) and the share of the added error those N carry. The figures behind
docs/lab/auto.md's ring around a small light ("The stacking's noise gate").
   /usr/bin/python3 lab/scripts/added_error.py [--count N] REFERENCE.exr INPUT.exr OUT.exr"""
import sys

import numpy as np

from exr_rgb import read_rgb


def colour(path):
    return read_rgb(path, "added_error.py")


def main(argv):
    count = 100
    if len(argv) > 1 and argv[0] == "--count":
        count = int(argv[1])
        argv = argv[2:]
    if len(argv) != 3:
        sys.exit(__doc__)
    ref, raw, out = (colour(p) for p in argv)
    for path, image in zip(argv[1:], (raw, out)):
        if image.shape != ref.shape:
            sys.exit(f"added_error.py: {path}: its size differs from the reference's")

    def error(x):
        return ((x - ref) ** 2 / (ref ** 2 + 0.01)).mean(axis=2)

    before, after = error(raw), error(out)
    delta = after - before
    added = delta[delta > 0].sum()
    print(f"relMSE: input {before.mean():.4g}, output {after.mean():.4g}; "
          f"added {added / delta.size:.4g}, removed {-delta[delta < 0].sum() / delta.size:.4g}")
    order = np.argsort(delta.ravel())[::-1][:count]
    for k in order[:8]:
        y, x = divmod(int(k), delta.shape[1])
        print(f"  ({x}, {y}) adds {delta[y, x]:.3g}: out {out[y, x, 0]:.4g}, "
              f"input {raw[y, x, 0]:.4g}, reference {ref[y, x, 0]:.4g}")
    share = delta.ravel()[order].clip(min=0).sum() / added if added > 0 else 0.0
    print(f"  the {count} pixels that add the most carry {100 * share:.0f} % of the added error")


if __name__ == "__main__":
    main(sys.argv[1:])
