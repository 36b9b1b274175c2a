# Splits a gltf_compare.sh comparison by material and facing: the pixels whose Glint albedo is
# ALBEDO (one material, e.g. the gold of blender_scene.glb), in four bands of the shading
# normal's y (down … up), with Glint's and Cycles' mean luminance in each. An up-facing band
# mostly reflects the sky, a down-facing one the ground: a difference that grows downward comes
# from what the surface reflects, not from its own BRDF (docs/assets.md, "Against Cycles").
#   lab/bench/cycles/gltf_compare.sh build ASSET.glb 256 OUT_DIR   (keeps glint.exr, cycles.exr)
#   /usr/bin/python3 lab/bench/cycles/gltf_split_by_normal.py OUT_DIR R G B
import os
import sys

import numpy as np
import OpenImageIO as oiio


def channels(path, names):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    have = list(spec.channelnames)
    px = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    return px[:, :, [have.index(c) for c in names]].astype(np.float64)


def main():
    folder = sys.argv[1]
    albedo = np.array([float(v) for v in sys.argv[2:5]])
    glint_path, cycles_path = os.path.join(folder, "glint.exr"), os.path.join(folder, "cycles.exr")
    glint = channels(glint_path, ("R", "G", "B"))
    cycles = channels(cycles_path, ("R", "G", "B"))
    a = channels(glint_path, ("albedo.R", "albedo.G", "albedo.B"))
    ny = channels(glint_path, ("normal.Y",))[:, :, 0]
    lum = np.array([0.2126, 0.7152, 0.0722])
    material = np.all(np.abs(a - albedo) < 0.03, axis=-1)
    print(f"pixels of albedo {tuple(albedo)}: {int(material.sum())}")
    print(f"{'normal.y':>14} {'pixels':>7} {'Glint':>8} {'Cycles':>8} {'diff %':>7}")
    for lo, hi in ((-1.0, -0.5), (-0.5, 0.0), (0.0, 0.5), (0.5, 1.01)):
        m = material & (ny >= lo) & (ny < hi)
        if m.sum() < 20:
            continue
        g, c = (glint[m] @ lum).mean(), (cycles[m] @ lum).mean()
        print(f"[{lo:+.1f}, {min(hi, 1.0):+.1f}) {int(m.sum()):7d} {g:8.4f} {c:8.4f} "
              f"{100 * (g - c) / c:+7.1f}")


if __name__ == "__main__":
    main()
