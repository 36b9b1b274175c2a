#!/usr/bin/python3
"""How much box area clusters of 16 triangles add over single triangles, for a `.glb`'s first
mesh primitive (docs/assets-tried.md, "Clusters and the buffer reader on real assets").

The triangles are put in Hilbert order of their centroids (16 bits an axis over their bounding
cube, as renderer/src/embree/cluster_geometry.cpp orders them; ties by index), and for
comparison in Morton order, and cut into runs of 16. By the surface-area argument, the sum of
the boxes' areas over the scene box's area is the number of boxes a random ray through the scene
box enters: the script prints it for the triangles' own boxes and for the clusters' boxes (each
entered cluster costs 16 triangle tests), and their ratio.

  /usr/bin/python3 lab/bench/cluster_box_area.py A.glb [B.glb ...]
"""
import json
import struct
import sys

import numpy as np


def fail(message):
    print(f"cluster_box_area: {message}", file=sys.stderr)
    sys.exit(2)


def first_primitive(path):
    data = open(path, "rb").read()
    if data[:4] != b"glTF":
        fail(f"{path}: byte 0: not a binary glTF")
    json_length = struct.unpack("<I", data[12:16])[0]
    doc = json.loads(data[20:20 + json_length])
    binary = data[20 + json_length + 8:]
    primitive = doc["meshes"][0]["primitives"][0]

    def accessor(index, width):
        a = doc["accessors"][index]
        view = doc["bufferViews"][a["bufferView"]]
        packed = np.dtype(kinds[a["componentType"]]).itemsize * width
        if view.get("byteStride", 0) not in (0, packed):
            fail(f"{path}: accessors[{index}]: interleaved data is not read here")
        offset = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        values = np.frombuffer(binary, dtype=kinds[a["componentType"]], count=a["count"] * width,
                               offset=offset)
        return values.reshape(a["count"], width)

    kinds = {5126: np.float32, 5125: np.uint32, 5123: np.uint16, 5121: np.uint8}
    if "indices" not in primitive:
        fail(f"{path}: meshes[0].primitives[0]: no indices")
    positions = accessor(primitive["attributes"]["POSITION"], 3).astype(np.float64)
    return positions, accessor(primitive["indices"], 1).reshape(-1, 3)


def spread_bits(x):
    x = x.astype(np.uint64) & np.uint64(0xFFFF)
    result = np.zeros_like(x)
    for bit in range(16):
        result |= ((x >> np.uint64(bit)) & np.uint64(1)) << np.uint64(3 * bit)
    return result


def hilbert_index(q):
    """48-bit Hilbert indices of 16-bit points (rows of q): Skilling's transform of the axes into
    the transpose of the index (J. Skilling, "Programming the Hilbert curve", 2004), its bits
    interleaved with x's first, as renderer/src/embree/cluster_geometry.cpp computes them."""
    x = [q[:, a].astype(np.uint64) for a in range(3)]
    top = 1 << 15
    bit = top
    while bit > 1:
        low = np.uint64(bit - 1)
        for a in range(3):
            set_ = (x[a] & np.uint64(bit)) != 0
            if a == 0:
                x[0] = np.where(set_, x[0] ^ low, x[0])
                continue
            t = (x[0] ^ x[a]) & low
            x[0] = np.where(set_, x[0] ^ low, x[0] ^ t)
            x[a] = np.where(set_, x[a], x[a] ^ t)
        bit >>= 1
    x[1] ^= x[0]
    x[2] ^= x[1]
    t = np.zeros_like(x[2])
    bit = top
    while bit > 1:
        t = np.where((x[2] & np.uint64(bit)) != 0, t ^ np.uint64(bit - 1), t)
        bit >>= 1
    return spread_bits(x[0] ^ t) << np.uint64(2) | spread_bits(x[1] ^ t) << np.uint64(1) | \
        spread_bits(x[2] ^ t)


def box_area(lo, hi):
    e = hi - lo
    return 2 * (e[:, 0] * e[:, 1] + e[:, 1] * e[:, 2] + e[:, 2] * e[:, 0])


def main():
    if len(sys.argv) < 2:
        fail("usage: cluster_box_area.py A.glb [B.glb ...]")
    for path in sys.argv[1:]:
        positions, indices = first_primitive(path)
        corners = positions[indices]
        centroid = corners.mean(axis=1)
        lo, hi = centroid.min(axis=0), centroid.max(axis=0)
        q = ((centroid - lo) / max((hi - lo).max(), 1e-30) * 65536).clip(0, 65535).astype(np.uint64)
        morton = spread_bits(q[:, 0]) << np.uint64(2) | spread_bits(q[:, 1]) << np.uint64(1) | \
            spread_bits(q[:, 2])
        scene = box_area(positions.min(axis=0)[None], positions.max(axis=0)[None])[0]
        triangles = box_area(corners.min(axis=1), corners.max(axis=1)).sum()
        line = f"{path}: {len(indices)} triangles; boxes a random ray enters: triangles " \
               f"{triangles / scene:.2f}"
        for name, code in (("Hilbert", hilbert_index(q)), ("Morton", morton)):
            order = np.argsort(code, kind="stable")
            whole = len(order) // 16 * 16
            clusters = corners[order[:whole]].reshape(-1, 16 * 3, 3)
            boxes = box_area(clusters.min(axis=1), clusters.max(axis=1)).sum()
            line += f", clusters of 16 in {name} order {boxes / scene:.2f} " \
                    f"({boxes / triangles:.2f}x)"
        print(line)


if __name__ == "__main__":
    main()
