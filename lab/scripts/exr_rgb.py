"""The colour (R, G, B) of an EXR as a float array of height × width × 3, for the lab's per-pixel
scripts (worst_pixels.py, added_error.py); a file that cannot be read or has no R, G or B ends
the script with one line naming it."""
import sys

import OpenImageIO as oiio


def read_rgb(path, tool):
    image = oiio.ImageInput.open(path)
    if image is None:
        sys.exit(f"{tool}: {path}: cannot open: {oiio.geterror()}")
    spec = image.spec()
    names = list(spec.channelnames)
    data = image.read_image(oiio.FLOAT).reshape(spec.height, spec.width, len(names))
    image.close()
    missing = [c for c in "RGB" if c not in names]
    if missing:
        sys.exit(f"{tool}: {path}: no channel {missing[0]}")
    return data[:, :, [names.index(c) for c in "RGB"]]
