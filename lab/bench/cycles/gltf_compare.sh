#!/usr/bin/env bash
# Glint against Blender's Cycles on the same glTF asset (docs/assets.md, "Against Cycles"):
# glint-render renders the bare asset (its own camera, a uniform white environment of radiance
# 1), Cycles renders the same file imported by Blender's glTF importer at the same size, samples
# and depth; then, over the pixels the asset covers (Glint's depth > 0), the per-region means (a
# 4 × 4 grid over its bounding box, luminance) and the relMSE between the two are printed, and
# the two pictures are written as PNGs (and the two renders as EXRs) into OUT_DIR when given.
#   lab/bench/cycles/gltf_compare.sh [BUILD_DIR] ASSET.glb|ASSET.obj [SPP] [OUT_DIR]
#   CYCLES_OPTIONS=--lambert ...   (Principled BSDFs made Lambertian, as Glint reads an MTL Kd)
#   EDGE=drop ...   (the asset's one-pixel silhouette left out of the regions: a pixel there is
#                    part sky, and a sub-pixel difference in the two cameras' conventions moves a
#                    thin dark asset's region means by several %; used for docs/obj-assets.md)
#   CYCLES_OPTIONS=--single-scatter lab/bench/cycles/gltf_compare.sh ...   (Cycles' GGX without
#                                       multiple scattering, as the glTF BRDF)
# Needs Debian's blender and python3-openimageio (make bench-deps). Exit 2 when one is missing.
set -euo pipefail
cd "$(dirname "$0")/../../.."
BUILD_DIR=${1:-build}
ASSET=${2:?usage: gltf_compare.sh [BUILD_DIR] ASSET.glb [SPP] [OUT_DIR]}
SPP=${3:-256}
KEEP=${4:-}
CYCLES_OPTIONS=${CYCLES_OPTIONS:-}  # e.g. --single-scatter, --lambert (gltf_cycles.py)
EDGE=${EDGE:-keep}
GLINT="$BUILD_DIR/bin/glint-render"
PY=/usr/bin/python3  # Debian's Python, which sees Debian's python3-openimageio and numpy
OUT=$(mktemp -d "${TMPDIR:-/tmp}/glint-gltf-compare.XXXXXX")
trap 'rm -rf "$OUT"' EXIT

command -v blender >/dev/null || { echo "gltf_compare.sh: blender not found (make bench-deps)" >&2; exit 2; }
"$PY" -c "import OpenImageIO" 2>/dev/null ||
  { echo "gltf_compare.sh: python3-openimageio not found (make bench-deps)" >&2; exit 2; }
[[ -x "$GLINT" ]] || { echo "gltf_compare.sh: $GLINT not built (make build)" >&2; exit 2; }

"$GLINT" "$ASSET" --spp "$SPP" --threads 2 --set maxDepth=8 --out "$OUT/glint.exr" >/dev/null
read -r WIDTH HEIGHT < <("$PY" -c "
import OpenImageIO as oiio, sys
s = oiio.ImageInput.open(sys.argv[1]).spec(); print(s.width, s.height)" "$OUT/glint.exr")
blender -b -P lab/bench/cycles/gltf_cycles.py -- "$ASSET" --width "$WIDTH" --height "$HEIGHT" \
  --spp "$SPP" --threads 2 --max-depth 8 --out "$OUT/cycles.exr" $CYCLES_OPTIONS 2>/dev/null |
  grep '^{"renderer": "cycles"' >/dev/null

"$PY" - "$OUT/glint.exr" "$OUT/cycles.exr" "$KEEP" "$EDGE" <<'PY'
import os, shutil, sys
import numpy as np
import OpenImageIO as oiio

def channels(path, names):
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    have = list(spec.channelnames)
    px = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    return px[:, :, [have.index(c) for c in names]].astype(np.float64)

glint = channels(sys.argv[1], ("R", "G", "B"))
cycles = channels(sys.argv[2], ("R", "G", "B"))
# The asset's pixels: where Glint's camera rays met a surface (depth > 0); the white sky around
# it would only dilute the differences.
mask = channels(sys.argv[1], ("depth.Z",))[:, :, 0] > 0
if sys.argv[4] == "drop":
    inner = mask.copy()
    inner[1:, :] &= mask[:-1, :]
    inner[:-1, :] &= mask[1:, :]
    inner[:, 1:] &= mask[:, :-1]
    inner[:, :-1] &= mask[:, 1:]
    mask = inner
lum = lambda a: a @ np.array([0.2126, 0.7152, 0.0722])
h, w, _ = glint.shape
ys, xs = np.nonzero(mask)
if len(ys) == 0:
    sys.exit("gltf_compare.sh: the asset covers no pixel")
y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
print(f"asset pixels: {mask.sum()} of {h * w}, box x {x0}..{x1}, y {y0}..{y1}")
print(f"{'region':>8} {'pixels':>7} {'Glint':>9} {'Cycles':>9} {'diff %':>8}")
worst = 0.0
for i in range(4):
    for j in range(4):
        r = (slice(y0 + i * (y1 - y0) // 4, y0 + (i + 1) * (y1 - y0) // 4),
             slice(x0 + j * (x1 - x0) // 4, x0 + (j + 1) * (x1 - x0) // 4))
        m = mask[r]
        if m.sum() < 0.05 * m.size:
            continue  # mostly sky
        g, c = lum(glint[r])[m].mean(), lum(cycles[r])[m].mean()
        d = 100.0 * (g - c) / max(c, 1e-6)
        worst = max(worst, abs(d))
        print(f"{i},{j:>6} {int(m.sum()):7d} {g:9.4f} {c:9.4f} {d:+8.2f}")
g, c = lum(glint)[mask].mean(), lum(cycles)[mask].mean()
rel = np.mean(((glint - cycles) ** 2 / (cycles ** 2 + 1e-2))[mask])
print(f"asset: Glint {g:.4f}, Cycles {c:.4f} ({100 * (g - c) / c:+.2f} %); "
      f"largest region difference {worst:.2f} %; relMSE {rel:.4g}")
if sys.argv[3]:
    os.makedirs(sys.argv[3], exist_ok=True)
    for name in ("glint", "cycles"):  # the renders too, for gltf_split_by_normal.py
        shutil.copyfile(sys.argv[{"glint": 1, "cycles": 2}[name]],
                        os.path.join(sys.argv[3], f"{name}.exr"))
    for name, img in (("glint", glint), ("cycles", cycles)):
        srgb = np.where(img <= 0.0031308, 12.92 * img, 1.055 * np.power(np.clip(img, 0, None), 1 / 2.4) - 0.055)
        out = oiio.ImageBuf(oiio.ImageSpec(w, h, 3, oiio.UINT8))
        out.set_pixels(oiio.ROI(0, w, 0, h, 0, 1, 0, 3),
                       np.ascontiguousarray(np.clip(srgb, 0, 1), dtype=np.float32))
        out.write(os.path.join(sys.argv[3], f"{name}.png"))
PY
