# Writes a metal-only glTF asset for gltf_compare.sh (docs/assets.md, "Against Cycles"): a row
# of gold spheres (metallic 1, base colour (1, 0.766, 0.336)), one per roughness, and a camera
# looking at them. Under gltf_compare.sh's uniform white sky each sphere shows its BRDF's
# directional albedo, so the comparison isolates the metal lobe.
#   /usr/bin/python3 lab/bench/cycles/metal_spheres.py OUT.glb [ROUGHNESS,...]
import json
import struct
import sys

import numpy as np


def uv_sphere(n=64):
    theta = np.linspace(0, np.pi, n + 1)
    phi = np.linspace(0, 2 * np.pi, 2 * n + 1)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    pos = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], -1)
    pos = pos.reshape(-1, 3).astype(np.float32)
    i = np.arange((n + 1) * (2 * n + 1)).reshape(n + 1, 2 * n + 1)
    a, b, c, d = i[:-1, :-1], i[:-1, 1:], i[1:, :-1], i[1:, 1:]
    return pos, np.stack([a, b, c, b, d, c], -1).reshape(-1).astype(np.uint32)


def main():
    out = sys.argv[1]
    roughness = [float(r) for r in (sys.argv[2] if len(sys.argv) > 2 else "0.05,0.3,0.6,1.0").split(",")]
    pos, idx = uv_sphere()
    data = pos.tobytes() + pos.tobytes() + idx.tobytes()  # a unit sphere's normals are its positions
    vb = len(pos) * 12
    k = len(roughness)
    doc = {
        "asset": {"version": "2.0", "generator": "glint lab/bench/cycles/metal_spheres.py"},
        "scene": 0,
        "scenes": [{"nodes": list(range(k + 1))}],
        "nodes": [{"mesh": j, "translation": [2.2 * (j - (k - 1) / 2), 0, 0]} for j in range(k)]
        + [{"camera": 0, "translation": [0, 0, 4.0 + 1.1 * k]}],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.7, "znear": 0.1, "aspectRatio": 2.0}}],
        "materials": [{"name": f"gold_roughness_{r}",
                       "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.766, 0.336, 1],
                                                "metallicFactor": 1.0, "roughnessFactor": r}}
                      for r in roughness],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                    "material": j}]} for j in range(k)],
        "buffers": [{"byteLength": len(data)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": vb},
                        {"buffer": 0, "byteOffset": vb, "byteLength": vb},
                        {"buffer": 0, "byteOffset": 2 * vb, "byteLength": len(idx) * 4}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
                       "min": [-1, -1, -1], "max": [1, 1, 1]},
                      {"bufferView": 1, "componentType": 5126, "count": len(pos), "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5125, "count": len(idx),
                       "type": "SCALAR"}],
    }
    text = json.dumps(doc).encode()
    text += b" " * ((4 - len(text) % 4) % 4)
    with open(out, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(data)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        f.write(struct.pack("<II", len(data), 0x004E4942) + data)


if __name__ == "__main__":
    main()
