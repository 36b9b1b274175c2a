#!/usr/bin/env python3
"""Compares two PFM images as the unet filter's equality check with the OIDN peer does
(docs/learned.md): mean |a - b| relative to the mean of b, and the largest difference of display
values (clamp to [0, 1], sRGB encoding, x255). Prints one JSON line; exits 1 when a tolerance
(mean relative 1e-3, display 1/255) is exceeded.
  unet_vs_peer.py glint.pfm peer.pfm [label]"""
import json
import struct
import sys


def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(maxsplit=4)
    magic, w, h, scale = parts[0], int(parts[1]), int(parts[2]), float(parts[3])
    chans = 3 if magic == b"PF" else 1
    n = w * h * chans
    body = data[len(data) - 4 * n:]
    vals = struct.unpack(("<" if scale < 0 else ">") + "%df" % n, body)
    return w, h, vals


def srgb(v):
    v = min(max(v, 0.0), 1.0)
    return 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055


def main():
    wa, ha, a = read_pfm(sys.argv[1])
    wb, hb, b = read_pfm(sys.argv[2])
    if (wa, ha) != (wb, hb) or len(a) != len(b):
        sys.exit("sizes differ")
    mean_abs = sum(abs(x - y) for x, y in zip(a, b)) / len(a)
    mean_b = sum(abs(y) for y in b) / len(b)
    display = max(abs(srgb(x) - srgb(y)) for x, y in zip(a, b)) * 255.0
    rel = mean_abs / mean_b if mean_b > 0 else mean_abs
    ok = rel < 1e-3 and display <= 1.0
    print(json.dumps({"label": sys.argv[3] if len(sys.argv) > 3 else sys.argv[1],
                      "width": wa, "height": ha, "meanAbsRelative": rel,
                      "maxDisplayDiff255": display, "pass": ok}))
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
