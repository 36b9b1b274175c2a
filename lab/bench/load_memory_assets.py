#!/usr/bin/env python3
"""Writes the assets the load's memory prediction was checked on (docs/renderer.md, "Memory";
docs/lab/mesh-memory.md): a grid of n × n quads in several forms.

    python3 lab/bench/load_memory_assets.py KIND OUT N [IMAGE_SIDE]

KIND:
  textured   .glb: the grid with uvs, a material with an embedded PNG of IMAGE_SIDE² texels
  primitives .glb: one mesh of N primitives of one triangle, each with a material of its own
  quads      .obj: `v` and `f a b c d` (no normals, no uvs)
  uvs        .obj: `v`, `vt`, `vn`, `f a/a/a ...` (smooth, a uv a position)
  flat       .obj: `v`, a `vn` per face, `f a//k b//k c//k d//k` (flat shading)
"""
import json
import struct
import sys
import zlib


def grid(n):
    pos = [(x / n, y / n, 0.0) for y in range(n + 1) for x in range(n + 1)]
    quads = [(y * (n + 1) + x, y * (n + 1) + x + 1, (y + 1) * (n + 1) + x + 1, (y + 1) * (n + 1) + x)
             for y in range(n) for x in range(n)]
    return pos, quads


def png(side):
    rows = b"".join(b"\0" + bytes((x * 7 + y * 3) & 255 for x in range(side * 3)) for y in range(side))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", side, side, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows, 1)) + chunk(b"IEND", b""))


def write_glb(out, doc, data):
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    data += b"\0" * (-len(data) % 4)
    with open(out, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(data)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A))
        f.write(text)
        f.write(struct.pack("<II", len(data), 0x004E4942))
        f.write(data)


def textured(out, n, side):
    pos, quads = grid(n)
    p = b"".join(struct.pack("<3f", *v) for v in pos)
    uv = b"".join(struct.pack("<2f", v[0], v[1]) for v in pos)
    idx = b"".join(struct.pack("<6I", a, b, c, a, c, d) for a, b, c, d in quads)
    image = png(side)
    views, data = [], bytearray()
    for blob in (p, uv, idx, image):
        views.append({"buffer": 0, "byteOffset": len(data), "byteLength": len(blob)})
        data += blob + b"\0" * (-len(blob) % 4)
    doc = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": len(data)}], "bufferViews": views,
           "accessors": [
               {"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": len(pos),
                "min": [0, 0, 0], "max": [1, 1, 0]},
               {"bufferView": 1, "componentType": 5126, "type": "VEC2", "count": len(pos)},
               {"bufferView": 2, "componentType": 5125, "type": "SCALAR", "count": 6 * len(quads)}],
           "images": [{"bufferView": 3, "mimeType": "image/png"}], "textures": [{"source": 0}],
           "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2,
                                       "material": 0}]}],
           "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
    write_glb(out, doc, data)


def primitives(out, n):
    data = bytearray()
    for i in range(n):
        data += struct.pack("<9f", i, 0, 0, i + 0.9, 0, 0, i, 0.9, 0)
    doc = {"asset": {"version": "2.0"}, "buffers": [{"byteLength": len(data)}],
           "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
           "accessors": [{"bufferView": 0, "byteOffset": 36 * i, "componentType": 5126, "type": "VEC3",
                          "count": 3, "min": [i, 0, 0], "max": [i + 0.9, 0.9, 0]} for i in range(n)],
           "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, i / n, 0, 1]}} for i in range(n)],
           "meshes": [{"primitives": [{"attributes": {"POSITION": i}, "material": i} for i in range(n)]}],
           "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
    write_glb(out, doc, data)


def obj(out, n, kind):
    pos, quads = grid(n)
    with open(out, "w") as f:
        for x, y, z in pos:
            f.write("v %.6g %.6g %.6g\n" % (x, y, z))
        if kind == "uvs":
            for x, y, _ in pos:
                f.write("vt %.6g %.6g\n" % (x, y))
            f.write("vn 0 0 1\n" * len(pos))
            for q in quads:
                f.write("f " + " ".join("%d/%d/%d" % (i + 1, i + 1, i + 1) for i in q) + "\n")
        elif kind == "flat":
            f.write("vn 0 0 1\n" * len(quads))
            for k, q in enumerate(quads):
                f.write("f " + " ".join("%d//%d" % (i + 1, k + 1) for i in q) + "\n")
        else:
            for q in quads:
                f.write("f " + " ".join(str(i + 1) for i in q) + "\n")


def main():
    kind, out, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
    if kind == "textured":
        textured(out, n, int(sys.argv[4]) if len(sys.argv) > 4 else 4096)
    elif kind == "primitives":
        primitives(out, n)
    else:
        obj(out, n, kind)


if __name__ == "__main__":
    main()
