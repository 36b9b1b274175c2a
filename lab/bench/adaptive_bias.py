#!/usr/bin/python3
"""The bias of adaptive sampling's two choices of the error that steers it (issue 49;
docs/lab/adaptive-bias.md): `adaptiveError=half` (the odd samples decide, so the even half never
steers) against `whole` (every sample decides), measured against a converged uniform reference
over many seeds. For each seed it renders, with glint-render:
  - adaptive, half: the whole image, and its even half (half A, from the half-buffer layers),
  - adaptive, whole: the whole image,
  - uniform, as many samples in all as the half render (a control: no bias by construction),
then averages each estimator over the seeds and compares the average with the reference: the
image-mean relative bias with its standard error (from the spread over seeds), and per pixel
z = (average - reference) / sqrt(spread^2 / seeds + reference variance), whose mean square is 1
for an unbiased estimator (above 1: a bias the pixels see).

    /usr/bin/python3 lab/bench/adaptive_bias.py build/bin/glint-render [--seeds 64] \\
        [--size 64] [--threshold 0.05] [--min-spp 16] [--max-spp 1024] [--ref-spp 16384] \\
        [--cache build/adaptive_bias]

The scene is scenes/cornell at SIZE x SIZE (every pixel noisy). The reference is rendered once
(uniform, REF_SPP, seed 99) and cached. Prints a markdown table. Needs Debian's
python3-openimageio and numpy."""
import argparse
import json
import math
import os
import subprocess
import tempfile

import numpy as np
import OpenImageIO as oiio

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def parse_args():
    p = argparse.ArgumentParser(prog="adaptive_bias.py")
    p.add_argument("glint_render")
    p.add_argument("--seeds", type=int, default=64)
    p.add_argument("--size", type=int, default=64)
    p.add_argument("--threshold", type=float, default=0.05)
    p.add_argument("--min-spp", type=int, default=16)
    p.add_argument("--max-spp", type=int, default=1024)
    p.add_argument("--ref-spp", type=int, default=16384)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--cache", default=os.path.join(ROOT, "build", "adaptive_bias"))
    return p.parse_args()


def scene_file(cache, size):
    """scenes/cornell at size x size (its camera, box and render block)."""
    with open(os.path.join(ROOT, "scenes", "cornell", "scene.json")) as f:
        scene = json.load(f)
    scene["film"] = {"width": size, "height": size}
    for shape in scene["shapes"]:
        if "obj" in shape:
            shape["obj"] = os.path.join(ROOT, "scenes", "cornell", shape["obj"])
    path = os.path.join(cache, f"cornell{size}.json")
    with open(path, "w") as f:
        json.dump(scene, f)
    return path


def layers(path):
    """colour, its variance of the mean, the sample count; with half buffers also half B's."""
    # ImageInput, not ImageBuf: ImageBuf's cache would hand back an earlier file of this name.
    inp = oiio.ImageInput.open(path)
    spec = inp.spec()
    px = inp.read_image(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    inp.close()
    px = px.astype(np.float64)
    names = list(spec.channelnames)
    get = lambda *cs: px[:, :, [names.index(c) for c in cs]]
    out = {"color": get("R", "G", "B"),
           "variance": get("variance.R", "variance.G", "variance.B"),
           "count": get("sampleCount.Y")}
    if "halfColor.R" in names:
        out["half"] = get("halfColor.R", "halfColor.G", "halfColor.B")
        out["halfCount"] = get("halfSampleCount.Y")
    return out


def render(args, scene, out, seed, *options, spp=None):
    subprocess.run([args.glint_render, scene, "--threads", str(args.threads), "--seed", str(seed),
                    "--spp", str(spp or args.max_spp), "--out", out, *options],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return layers(out)


def even_half(frame):
    """Half A (the even samples) from the whole image and half B: n·mean = nA·A + nB·B."""
    n, nb = frame["count"], frame["halfCount"]
    return (frame["color"] * n - frame["half"] * nb) / np.maximum(n - nb, 1)


def main():
    args = parse_args()
    os.makedirs(args.cache, exist_ok=True)
    scene = scene_file(args.cache, args.size)
    ref_path = os.path.join(args.cache, f"reference{args.size}_{args.ref_spp}.exr")
    if not os.path.exists(ref_path):
        tmp = ref_path + ".tmp.exr"
        render(args, scene, tmp, 99, spp=args.ref_spp)
        os.replace(tmp, ref_path)
    ref = layers(ref_path)
    adaptive = ["--set", "halfBuffers=true", "--set", "adaptive=true", "--set",
                f"noiseThreshold={args.threshold}", "--set", f"minSpp={args.min_spp}"]
    lum = np.array([0.2126, 0.7152, 0.0722])
    sums = {}  # estimator -> [sum, sum of squares, each seed's image-mean luminance]
    spp = {}

    def add(name, image):
        s = sums.setdefault(name, [0.0, 0.0, []])
        s[0] = s[0] + image
        s[1] = s[1] + image * image
        s[2].append(float((image @ lum).mean()))

    with tempfile.TemporaryDirectory() as work:
        for seed in range(1, args.seeds + 1):
            out = os.path.join(work, f"seed{seed}.exr")
            half = render(args, scene, out, seed, *adaptive, "--set", "adaptiveError=half")
            add("half, every sample", half["color"])
            add("half, even half", even_half(half))
            whole = render(args, scene, out, seed, *adaptive, "--set", "adaptiveError=whole")
            add("whole, every sample", whole["color"])
            mean_spp = float(half["count"].mean())
            uniform = render(args, scene, out, 1000 + seed, spp=max(1, round(mean_spp)))
            add("uniform (control)", uniform["color"])
            for name, frame in (("half", half), ("whole", whole)):
                spp.setdefault(name, []).append(float(frame["count"].mean()))

    n = args.seeds
    r = ref["color"]
    ref_mean = float((r @ lum).mean())
    print(f"scenes/cornell at {args.size}², threshold {args.threshold}, minSpp {args.min_spp}, "
          f"spp at most {args.max_spp}, {n} seeds; mean spp: half "
          f"{np.mean(spp['half']):.1f}, whole {np.mean(spp['whole']):.1f}; reference "
          f"{args.ref_spp} spp\n")
    print("| estimator | image-mean bias (luminance) | its standard error | bias / error "
          "| mean z² per pixel value | values with \\|z\\| > 3.29 (0.1 % expected) |")
    print("|---|---|---|---|---|---|")
    for name, (s, s2, means) in sums.items():
        mean = s / n
        spread2 = np.maximum(s2 / n - mean * mean, 0.0) * n / (n - 1)  # one seed's variance
        z = (mean - r) / np.sqrt(spread2 / n + ref["variance"] + 1e-30)
        # The image mean's bias, and its standard error from the spread of the seeds' means
        # and the reference's own noise (its variance layer, pixels independent).
        bias = (np.mean(means) - ref_mean) / ref_mean
        ref_error2 = float((ref["variance"] @ (lum * lum)).sum()) / r[:, :, 0].size ** 2
        err = math.sqrt(np.var(means, ddof=1) / n + ref_error2) / ref_mean
        print(f"| {name} | {100 * bias:+.3f} % | {100 * err:.3f} % | {bias / err:+.1f} | "
              f"{float((z * z).mean()):.3f} | {100 * float((np.abs(z) > 3.29).mean()):.2f} % |")

if __name__ == "__main__":
    main()
