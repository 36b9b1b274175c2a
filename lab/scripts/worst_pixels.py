#!/usr/bin/env python3
"""The pixels that carry a denoised frame's relMSE against a reference: for each OUT, its relMSE
and the N pixels of largest relative squared error (x, y, that error, and the red channel of OUT,
the reference and the input there), then the share of the error those N and the worst 1 % of the
pixels carry. relMSE per pixel as glint-image diff computes it: the mean over RGB of
(out - ref)^2 / (ref^2 + 0.01). The figures behind docs/lab/auto.md's small light (its smear,
its halo, envmap's fireflies).
   /usr/bin/python3 lab/scripts/worst_pixels.py [--count N] REFERENCE.exr INPUT.exr OUT.exr..."""
import sys

import numpy as np

from exr_rgb import read_rgb


def colour(path):
    return read_rgb(path, "worst_pixels.py")


def main(argv):
    count = 6
    if len(argv) > 1 and argv[0] == "--count":
        count = int(argv[1])
        argv = argv[2:]
    if len(argv) < 3:
        sys.exit(__doc__)
    reference, noisy = colour(argv[0]), colour(argv[1])
    for path in argv[2:]:
        out = colour(path)
        if out.shape != reference.shape or noisy.shape != reference.shape:
            sys.exit(f"worst_pixels.py: {path}: its size differs from the reference's")
        error = ((out - reference) ** 2 / (reference ** 2 + 1e-2)).mean(axis=2)
        print(f"{path}: relMSE {error.mean():.4g}")
        flat = error.ravel()
        order = np.argsort(flat)[::-1]
        for k in order[:count]:
            y, x = divmod(int(k), error.shape[1])
            print(f"  ({x}, {y}) error {error[y, x]:.3g}: out {out[y, x, 0]:.4g}, "
                  f"reference {reference[y, x, 0]:.4g}, input {noisy[y, x, 0]:.4g}")
        total = flat.sum()
        worst = order[: max(1, flat.size // 100)]
        print(f"  these {count} carry {flat[order[:count]].sum() / total:.0%}, "
              f"the worst 1 % of the pixels {flat[worst].sum() / total:.0%}")


if __name__ == "__main__":
    main(sys.argv[1:])
