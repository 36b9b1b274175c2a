#!/usr/bin/env python3
"""Writes a .glb of N meshes of one triangle each, each placed by a node of its own (a grid of
small triangles): the many-mesh asset of docs/renderer.md, "Memory".

    python3 lab/bench/many_meshes_glb.py /tmp/m100k.glb 100000
"""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from load_memory_assets import write_glb  # noqa: E402


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
    write_glb(out, doc, data)


if __name__ == "__main__":
    main()
