#!/usr/bin/python3
"""The equal-time race's reference floor (docs/lab/race.md, "The references' floor"): a race
result's relMSE against a reference of its own noise, with that noise subtracted.

A reference is the mean r of K independent renders r_1 … r_K (different seeds). For a result x
independent of them and the truth t, E[(x − r)²] = (x − t)² + Var(r) per pixel and channel, and
Var(r) = Var(r_k) / K is estimated without bias by s² / K, s² the sample variance of the K renders
(ddof 1). With relMSE's weights w = 1 / (r² + 0.01) (glint-image's relmse, pbrt's):

    raw       = mean(w (x − r)²)            what glint-image diff --metric relmse gives
    floor     = mean(w s² / K)              the reference's own error, estimated
    corrected = raw − floor                 an unbiased estimate of mean(w (x − t)²)

(the weights use r for t: a bias of the order of r's relative variance, 10⁻⁴ here). Pixels that
are not finite in x or r are skipped, as glint-image does.

    race_floor.py mean OUT.exr REF.exr...          the reference: the renders' mean (RGB EXR)
    race_floor.py relmse IMAGE.exr REF.exr...      prints "raw floor corrected" (K >= 2)
    race_floor.py relmse IMAGE.exr REF.exr... --split
        also the corrected relMSE against each half of the renders alone (two references of
        half the samples, twice the floor): the check that the correction holds
    race_floor.py self-test                        a synthetic case of known truth

Reads the R, G, B channels (the first part of a multi-part EXR) with python3-openimageio."""
import os
import sys

import numpy as np

EPSILON = 1e-2  # image/src/metrics.cpp's kRelEpsilon


def read_rgb(path):
    import OpenImageIO as oiio

    buf = oiio.ImageBuf(path)
    if buf.has_error:
        sys.exit(f"race_floor.py: {path}: {buf.geterror()}")
    spec = buf.spec()
    px = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)
    try:
        return px[:, :, [names.index(c) for c in ("R", "G", "B")]].astype(np.float64)
    except ValueError:
        sys.exit(f"race_floor.py: {path}: no R, G, B channels (has {', '.join(names[:6])}, …)")


def write_rgb(path, rgb):
    import OpenImageIO as oiio

    tmp = path + ".tmp.exr"
    out = oiio.ImageOutput.create(tmp)
    spec = oiio.ImageSpec(rgb.shape[1], rgb.shape[0], 3, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B")
    spec.attribute("compression", "zip")
    if not out or not out.open(tmp, spec) or not out.write_image(rgb.astype(np.float32)):
        sys.exit(f"race_floor.py: cannot write {path}")
    out.close()
    os.replace(tmp, path)


def reference(renders):
    """The mean of K renders and the estimated variance of that mean, per pixel and channel."""
    stack = np.stack(renders)
    if len(stack) < 2:
        sys.exit("race_floor.py: the floor needs at least two references of different seeds")
    return stack.mean(axis=0), stack.var(axis=0, ddof=1) / len(stack)


def relmse(x, renders):
    """(raw, floor, corrected) relMSE of x against the mean of renders."""
    r, var = reference(renders)
    ok = np.all(np.isfinite(x), axis=2) & np.all(np.isfinite(r), axis=2)
    w = 1.0 / (r[ok] ** 2 + EPSILON)
    raw = float(np.mean(w * (x[ok] - r[ok]) ** 2))
    floor = float(np.mean(w * var[ok]))
    return raw, floor, raw - floor


def self_test():
    """Truth known: a heavy-tailed positive image, K = 4 references and a result more accurate than
    them (the floor 4 times the result's error, as at the race's largest budget). The corrected
    relMSE must match the result's relMSE against the truth: within 10 % in each of 20 trials
    (the estimate's own noise, about 2.5 % here) and within 2 % on their mean (no bias), where the
    raw one is 5 times it."""
    rng = np.random.default_rng(7)
    shape = (192, 256, 3)
    ratios = []
    for trial in range(20):
        truth = rng.lognormal(mean=-1.0, sigma=1.0, size=shape)
        sigma_ref = 0.03 * truth + 0.002  # each render's noise, heteroscedastic
        renders = [truth + sigma_ref * rng.standard_normal(shape) for _ in range(4)]
        x = truth + 0.5 * (sigma_ref / 2) * rng.standard_normal(shape)  # 1/4 of the floor
        # relMSE against the truth, with the reference's weights (what the estimator targets).
        r = np.mean(renders, axis=0)
        true = float(np.mean((x - truth) ** 2 / (r**2 + EPSILON)))
        raw, floor, corrected = relmse(x, renders)
        ratios.append(corrected / true)
        print(f"trial {trial}: truth {true:.4g}, raw {raw:.4g} ({raw / true:.2f}x), "
              f"floor {floor:.4g}, corrected {corrected:.4g} ({corrected / true:.3f}x)")
    worst, mean = max(abs(q - 1.0) for q in ratios), float(np.mean(ratios))
    print(f"self-test: corrected / truth: worst {worst:+.3f} off (tolerance 0.10), "
          f"mean {mean:.4f} (tolerance 1 ± 0.02)")
    return 0 if worst < 0.10 and abs(mean - 1.0) < 0.02 else 1


def main(argv):
    if argv[:1] == ["self-test"]:
        return self_test()
    if len(argv) >= 3 and argv[0] == "mean":
        write_rgb(argv[1], np.mean([read_rgb(p) for p in argv[2:]], axis=0))
        return 0
    if len(argv) >= 4 and argv[0] == "relmse":
        split = "--split" in argv
        paths = [a for a in argv[1:] if a != "--split"]
        x, renders = read_rgb(paths[0]), [read_rgb(p) for p in paths[1:]]
        values = list(relmse(x, renders))
        if split:
            half = len(renders) // 2
            if half < 2:
                sys.exit("race_floor.py: --split needs at least four references")
            values += [relmse(x, renders[:half])[2], relmse(x, renders[half:])[2]]
        print(" ".join("%.6g" % v for v in values))
        return 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
