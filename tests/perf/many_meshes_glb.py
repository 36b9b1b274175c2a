#!/usr/bin/env python3
"""Writes a .glb of N meshes of one triangle each, each placed by a node of its own (a grid of
small triangles): the many-mesh asset of docs/renderer.md, "Memory".

    python3 tests/perf/many_meshes_glb.py /tmp/m100k.glb 100000
"""
import json
import struct
import sys


def main():
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 1000000
    side = int(n ** 0.5) + 1
    data = bytearray()
    for i in range(n):
        x, y = i % side, i // side
        data += struct.pack("<9f", x, y, 0, x + 0.9, y, 0, x, y + 0.9, 0)
    accessors = [{"bufferView": 0, "byteOffset": 36 * i, "componentType": 5126, "type": "VEC3",
                  "count": 3, "min": [i % side, i // side, 0],
                  "max": [i % side + 0.9, i // side + 0.9, 0]} for i in range(n)]
    doc = {"asset": {"version": "2.0"},
           "buffers": [{"byteLength": len(data)}],
           "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
           "accessors": accessors,
           "meshes": [{"primitives": [{"attributes": {"POSITION": i}}]} for i in range(n)],
           "nodes": [{"mesh": i} for i in range(n)],
           "scenes": [{"nodes": list(range(n))}], "scene": 0}
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    data += b"\0" * (-len(data) % 4)
    with open(out, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(data)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A))
        f.write(text)
        f.write(struct.pack("<II", len(data), 0x004E4942))
        f.write(data)


if __name__ == "__main__":
    main()
