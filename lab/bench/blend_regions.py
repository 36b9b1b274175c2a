#!/usr/bin/python3
# The error of renders over the pixels where camera rays meet a glTF asset's alphaMode BLEND
# surfaces first (docs/lab/gltf-assets.md, "Assets tried": the Aventador's windows). The region: the
# asset rendered once more with every BLEND material made opaque, black and emissive (radiance
# 100) — pixels brighter than 50 are those whose camera rays meet such a surface first at least
# half the time. Then, per render: relMSE over the region ((x − r)² / (r² + 1e-2), as
# glint-image's relmse) against the mean of the reference renders, and the region's mean
# luminance.
#   /usr/bin/python3 lab/bench/blend_regions.py GLINT_RENDER ASSET.gltf REF.exr[,REF2.exr] X.exr...
# Needs Debian's python3-openimageio and numpy. Exit 2 on bad input.
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio


def fail(message):
    print(f"blend_regions.py: {message}", file=sys.stderr)
    sys.exit(2)


def rgb(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        fail(f"{path}: cannot read ({buf.geterror()})")
    spec = buf.spec()
    names = list(spec.channelnames)
    px = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    return px[:, :, [names.index(c) for c in "RGB"]].astype(np.float64)


def lum(a):
    return a @ np.array([0.2126, 0.7152, 0.0722])


def blend_region(glint, asset):
    """Pixels whose camera rays meet a BLEND surface first at least half the time."""
    with open(asset) as f:
        gltf = json.load(f)
    blend = [m for m in gltf.get("materials", []) if m.get("alphaMode") == "BLEND"]
    if not blend:
        fail(f"{asset}: no material with alphaMode BLEND")
    for m in blend:
        m["alphaMode"] = "OPAQUE"
        m["pbrMetallicRoughness"] = {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0}
        m["emissiveFactor"] = [1, 1, 1]
        m.setdefault("extensions", {})["KHR_materials_emissive_strength"] = {
            "emissiveStrength": 100.0}
    used = gltf.setdefault("extensionsUsed", [])
    if "KHR_materials_emissive_strength" not in used:
        used.append("KHR_materials_emissive_strength")
    # Beside the asset, so that its buffers and images resolve.
    fd, marked = tempfile.mkstemp(suffix=".gltf", dir=os.path.dirname(os.path.abspath(asset)))
    out = marked[:-5] + ".exr"
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(gltf, f)
        subprocess.run([glint, marked, "--spp", "16", "--set", "maxDepth=1", "--threads", "2",
                        "--out", out], check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        return lum(rgb(out)) > 50.0
    finally:
        for p in (marked, out):
            if os.path.exists(p):
                os.remove(p)


def main():
    if len(sys.argv) < 5:
        fail("usage: blend_regions.py GLINT_RENDER ASSET.gltf REF.exr[,REF2.exr] X.exr...")
    glint, asset, refs = sys.argv[1], sys.argv[2], sys.argv[3].split(",")
    region = blend_region(glint, asset)
    ref = sum(rgb(p) for p in refs) / len(refs)
    if region.shape != ref.shape[:2]:
        fail(f"{refs[0]}: {ref.shape[1]}x{ref.shape[0]}, the asset renders "
             f"{region.shape[1]}x{region.shape[0]}")
    print(f"BLEND region: {int(region.sum())} pixels; reference mean {lum(ref)[region].mean():.5f}")
    for path in sys.argv[4:]:
        x = rgb(path)
        rel = ((x - ref) ** 2 / (ref ** 2 + 1e-2))[region].mean()
        print(f"{path}: relMSE {rel:.5f}, mean {lum(x)[region].mean():.5f}")


main()
