#!/usr/bin/env python3
"""Writes a textured test scene with fine decals and panel lines (docs/lab/first-denoise.md).

A helmet-like panel (an OBJ quad facing the camera, 256 x 192 px) whose base-colour texture holds
one-texel decal lines, small glyph blocks and a stripe, and whose tangent-space normal map holds
two-texel panel grooves; a ground quad; the procedural sky of scenes/envmap (sun and sky light).
One texel covers about one pixel, so the decals are the finest detail the film can show.

    lab/scripts/decal_panel_scene.py OUT_FOLDER

Writes OUT_FOLDER/{scene.json, panel.obj, panel.mtl, decals.png, grooves.png}. Pure Python (no
numpy): the PNGs are written with zlib.
"""
import os
import struct
import sys
import zlib

SIDE = 256  # texels of both textures


def write_png(path, pixels):
    """pixels: rows of (r, g, b) bytes, SIDE x SIDE."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in pixels)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", SIDE, SIDE, 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw))
                + chunk(b"IEND", b""))


def decal(x, y):
    """The base colour at texel (x, y): a light grey-blue panel with dark decals."""
    base = (150, 158, 170)
    dark = (25, 25, 30)
    # Block of one-texel lines, four texels apart (a grille).
    if 24 <= x < 120 and 24 <= y < 72 and x % 4 == 0:
        return dark
    # Rows of glyph-like blocks: 2x3 texels, one texel apart (a line of text).
    if 96 <= y < 140 and 136 <= x < 232 and (y - 96) % 6 < 3 and (x - 136) % 3 < 2 and \
            ((x * 7 + y * 13) // 3) % 5 != 0:
        return dark
    # A two-texel orange stripe with a one-texel dark outline.
    if 160 <= y < 166 and 16 <= x < 240:
        return dark if y in (160, 165) else (230, 120, 30)
    # A one-texel diagonal hairline.
    if 180 <= y < 240 and abs((x - 20) - (y - 180) * 3) < 1:
        return dark
    return base


def groove(x, y):
    """The tangent-space normal at texel (x, y): panel grooves every 64 texels, two wide."""
    nx, ny = 0.0, 0.0
    if x % 64 in (62, 63):
        nx = -0.6 if x % 64 == 62 else 0.6
    if y % 64 in (62, 63):
        ny = -0.6 if y % 64 == 62 else 0.6
    nz = (1.0 - nx * nx - ny * ny) ** 0.5
    return tuple(int(round((v * 0.5 + 0.5) * 255)) for v in (nx, ny, nz))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: decal_panel_scene.py OUT_FOLDER")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    # Row 0 of a PNG is the top; uv (0, 0) is the bottom-left texel in OBJ/MTL.
    write_png(os.path.join(out, "decals.png"),
              [[decal(x, SIDE - 1 - y) for x in range(SIDE)] for y in range(SIDE)])
    write_png(os.path.join(out, "grooves.png"),
              [[groove(x, SIDE - 1 - y) for x in range(SIDE)] for y in range(SIDE)])
    with open(os.path.join(out, "panel.mtl"), "w") as f:
        f.write("newmtl panel\nKd 1 1 1\nmap_Kd decals.png\nnorm grooves.png\n")
    with open(os.path.join(out, "panel.obj"), "w") as f:
        f.write("mtllib panel.mtl\n"
                "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                "vn 0 0 1\n"
                "usemtl panel\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")
    envmap = os.path.relpath(os.path.join(os.path.dirname(__file__), "../../scenes/envmap"), out)
    with open(os.path.join(out, "scene.json"), "w") as f:
        f.write("""{
  "camera": {"position": [0.35, 0.2, 2.55], "lookAt": [0, 0, 0], "up": [0, 1, 0], "fovY": 40},
  "film": {"width": 256, "height": 192},
  "materials": {"ground": {"type": "diffuse", "albedo": [0.5, 0.48, 0.45]}},
  "shapes": [
    {"obj": "panel.obj", "transform": {"rotate": [-20, [0, 1, 0]], "translate": [0, 0.05, 0]}},
    {"obj": "%s/quad.obj", "material": "ground",
     "transform": {"scale": [20, 1, 20], "translate": [0, -1.05, 0]}}
  ],
  "environment": {"image": "%s/sky.exr", "scale": 1.0, "rotate": 0},
  "render": {"spp": 16, "maxDepth": 8, "rrDepth": 3}
}
""" % (envmap, envmap))


if __name__ == "__main__":
    main()
