#!/usr/bin/python3
"""Side-by-side check of glint::ssim against scikit-image (Debian python3-skimage).

Benchmark mode (default): runs bench_ssim, which times glint::ssim on two deterministic
1024x1024 RGB images and writes them as raw float32; then times scikit-image's
structural_similarity on the same arrays (single-threaded, float64) and checks that the values
agree. Prints one JSON object; exits 1 if the values disagree.

    /usr/bin/python3 lab/bench/ssim_skimage.py build/bin/bench_ssim

Test-values mode: prints scikit-image's SSIM of the small deterministic images that
tests/image/metrics_test.cpp builds with the same integer formulas (the values pasted there).

    /usr/bin/python3 lab/bench/ssim_skimage.py --test-values

Use /usr/bin/python3: Debian's python3-skimage is installed for the system interpreter.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

# Keep any threaded numerics single-threaded: the figure to beat is skimage single-threaded.
for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

import numpy as np  # noqa: E402
from skimage.metrics import structural_similarity  # noqa: E402


def skimage_ssim(a, b):
    """SSIM exactly as shared/DESIGN.md names it; inputs (H, W, C), computed in float64."""
    return structural_similarity(
        a.astype(np.float64), b.astype(np.float64), gaussian_weights=True, sigma=1.5,
        use_sample_covariance=False, data_range=1.0, channel_axis=2)


def srgb_encode(v):
    """IEC 61966-2-1 encoding of linear values in [0, 1] (float64)."""
    v = v.astype(np.float64)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1.0 / 2.4) - 0.055)


def test_images():
    """The images of metrics_test.cpp's SkimageAgreement tests, as (name, a, b) with (H, W, C)."""
    cases = []
    h, w, ch = 13, 16, 3
    y, x, c = np.meshgrid(np.arange(h), np.arange(w), np.arange(ch), indexing="ij")
    a = ((7 * x + 13 * y + 5 * c) % 17) / 16.0
    b = ((3 * x + 11 * y + 7 * c) % 19) / 18.0
    cases.append(("modular 16x13x3", a.astype(np.float32), b.astype(np.float32)))

    h, w, ch = 20, 12, 1
    y, x, c = np.meshgrid(np.arange(h), np.arange(w), np.arange(ch), indexing="ij")
    a = (x + 2 * y) / 40.0
    b = a + ((x * y + 3) % 5 - 2) / 50.0
    cases.append(("ramp 12x20x1", a.astype(np.float32), b.astype(np.float32)))

    h, w, ch = 11, 11, 2
    y, x, c = np.meshgrid(np.arange(h), np.arange(w), np.arange(ch), indexing="ij")
    a = ((x * x + 3 * y + c) % 11) / 10.0
    b = ((y * y + 2 * x + 4 * c) % 13) / 12.0
    cases.append(("minimum 11x11x2", a.astype(np.float32), b.astype(np.float32)))
    return cases


def print_test_values():
    for name, a, b in test_images():
        # The full map (mean over channels) checks the mirrored border, which the mean skips.
        _, full = structural_similarity(
            a.astype(np.float64), b.astype(np.float64), gaussian_weights=True, sigma=1.5,
            use_sample_covariance=False, data_range=1.0, channel_axis=2, full=True)
        smap = full.mean(axis=2)
        print(f"{name}: ssim {skimage_ssim(a, b):.17g}, map mean {smap.mean():.17g}, "
              f"map(0,0) {smap[0, 0]:.17g}, map(x=w-1,y=2) {smap[2, -1]:.17g}")


def load_average():
    """1-minute load average (Linux), or None: timings mean little on a busy machine."""
    try:
        with open("/proc/loadavg") as f:
            return float(f.read().split()[0])
    except OSError:
        return None


def run_benchmark(bench, size, repeat):
    load_before = load_average()
    with tempfile.TemporaryDirectory(prefix="glint_ssim_") as tmp:
        out = subprocess.run([bench, "--size", str(size), "--repeat", str(repeat),
                              "--write-dir", tmp], check=True, capture_output=True, text=True)
        glint = json.loads(out.stdout)
        shape = (size, size, 3)
        a = np.fromfile(glint["files"]["image"], dtype="<f4").reshape(shape)
        b = np.fromfile(glint["files"]["reference"], dtype="<f4").reshape(shape)

    a64, b64 = a.astype(np.float64), b.astype(np.float64)
    times = []
    for _ in range(max(1, repeat // 4)):
        t0 = time.perf_counter()
        value = skimage_ssim(a64, b64)
        times.append((time.perf_counter() - t0) * 1000.0)
    times.sort()
    # Display mode: glint encodes with float srgbEncode, numpy in float64, hence 1e-5 there.
    display = skimage_ssim(srgb_encode(np.clip(a64, 0, 1)), srgb_encode(np.clip(b64, 0, 1)))

    value, display = float(value), float(display)
    diff_linear = abs(value - glint["ssim_linear"])
    diff_display = abs(display - glint["ssim_display"])
    ok = bool(diff_linear <= 1e-6 and diff_display <= 1e-5)
    skimage_ms = times[len(times) // 2]
    report = {
        "image": f"{size}x{size}x3",
        "glint_ms": glint["ms"],
        "skimage_ms": {"median": skimage_ms, "min": times[0]},
        "speedup_linear_median": skimage_ms / glint["ms"]["linear"]["median"],
        "speedup_display_median": skimage_ms / glint["ms"]["display"]["median"],
        "ssim": {"glint_linear": glint["ssim_linear"], "skimage_linear": value,
                 "glint_display": glint["ssim_display"], "skimage_display": display},
        "abs_diff": {"linear": diff_linear, "display": diff_display},
        "agree": ok,
        "loadavg_1min_before": load_before,
        "versions": {"skimage": __import__("skimage").__version__, "numpy": np.__version__},
    }
    print(json.dumps(report, indent=2))
    return 0 if ok else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bench", nargs="?", help="path to the bench_ssim executable")
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--repeat", type=int, default=20)
    parser.add_argument("--test-values", action="store_true",
                        help="print skimage SSIM of metrics_test.cpp's small images")
    args = parser.parse_args()
    if args.test_values:
        print_test_values()
        return 0
    if not args.bench:
        parser.error("give the bench_ssim executable (or --test-values)")
    return run_benchmark(args.bench, args.size, args.repeat)


if __name__ == "__main__":
    sys.exit(main())
