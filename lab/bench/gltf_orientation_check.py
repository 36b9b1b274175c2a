# The Khronos OrientationTest (docs/assets.md, "Assets tried"): for each arrow, the angle between
# its long axis (the node's T · R · S applied to the mesh's longest local axis) and the line from
# the arrow's node origin to the centroid of the target of the same name. A transposed rotation
# shows as 10–70° on this asset, against 1.2–1.5° for the right one. Usage:
#   /usr/bin/python3 lab/bench/gltf_orientation_check.py OrientationTest.glb
import json, struct, sys
import numpy as np
b = open(sys.argv[1], 'rb').read()
n = struct.unpack('<I', b[12:16])[0]; d = json.loads(b[20:20 + n]); binc = b[20 + n + 8:]
def positions(mesh):
    a = d['accessors'][d['meshes'][mesh]['primitives'][0]['attributes']['POSITION']]
    v = d['bufferViews'][a['bufferView']]
    off = v.get('byteOffset', 0) + a.get('byteOffset', 0)
    return np.frombuffer(binc, np.float32, a['count'] * 3, off).reshape(-1, 3)
def rot(q):
    x, y, z, w = q
    return np.array([[1-2*(y*y+z*z), 2*(x*y-z*w), 2*(x*z+y*w)], [2*(x*y+z*w), 1-2*(x*x+z*z), 2*(y*z-x*w)], [2*(x*z-y*w), 2*(y*z+x*w), 1-2*(x*x+y*y)]])
def world(node, p):
    return (rot(node.get('rotation', [0, 0, 0, 1])) @ (p * node.get('scale', [1, 1, 1])).T).T + node.get('translation', [0, 0, 0])
nodes = {nd['name']: nd for nd in d['nodes']}
for name in ['X1', 'X2', 'Y1', 'Y2', 'Z1', 'Z2']:
    arrow, target = nodes['Arrow' + name], nodes['Target' + name]
    p = positions(arrow['mesh']); ext = p.max(0) - p.min(0); k = int(np.argmax(ext))
    axis = world(arrow, np.eye(3)[k][None] * 1.0)[0] - world(arrow, np.zeros((1, 3)))[0]
    to = world(target, positions(target['mesh'])).mean(0) - np.array(arrow.get('translation', [0, 0, 0]))
    c = abs(axis @ to) / np.linalg.norm(axis) / np.linalg.norm(to)
    print(f"{name}: {np.degrees(np.arccos(min(c, 1))):.2f} deg")
