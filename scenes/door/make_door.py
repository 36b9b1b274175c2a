#!/usr/bin/env python3
"""Writes door.obj + door.mtl: Veach's door scene (Veach 1997, fig. 11.3, and Veach & Guibas
1997). Two rooms share a wall; the door between them is almost closed, so the only light in
the camera's room comes through a narrow slit from a light in the next room.

Units: metres. Room A (camera): z in [0, 4]; room B (light): z in [-3, 0]; both x in [-2, 2],
y in [0, 2.4]. The shared wall z = 0 has a doorway x in [-0.5, 0.4], y in [0, 2]; the door
(0.9 m wide, hinged at x = 0.4) is opened 12 degrees into room B, leaving a slit of ~19 cm along
its free edge. The light is a 0.5 m square on room B's ceiling, 2.2 m behind the wall.
Run: python3 scenes/door/make_door.py (writes next to itself; deterministic output).
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
verts, faces = [], []  # faces: (material, [vertex indices])


def quad(mat, a, b, c, d):
    base = len(verts) + 1
    verts.extend([a, b, c, d])
    faces.append((mat, [base, base + 1, base + 2, base + 3]))


def box_room(z0, z1, mat_floor, mat_walls, skip_wall_z=None):
    x0, x1, y0, y1 = -2.0, 2.0, 0.0, 2.4
    quad(mat_floor, (x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1))   # floor
    quad(mat_walls, (x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0))   # ceiling
    quad(mat_walls, (x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0))   # left
    quad(mat_walls, (x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1))   # right
    for z in (z0, z1):
        if z != skip_wall_z:
            quad(mat_walls, (x0, y0, z), (x0, y1, z), (x1, y1, z), (x1, y0, z))


# Rooms (the shared wall z = 0 is built separately, with the doorway).
box_room(0.0, 4.0, "floorA", "wallA", skip_wall_z=0.0)
box_room(-3.0, 0.0, "floorB", "wallB", skip_wall_z=0.0)

# Shared wall with the doorway x in [dx0, dx1], y in [0, dh].
dx0, dx1, dh = -0.5, 0.4, 2.0
quad("wallA", (-2.0, 0.0, 0.0), (-2.0, 2.4, 0.0), (dx0, 2.4, 0.0), (dx0, 0.0, 0.0))
quad("wallA", (dx1, 0.0, 0.0), (dx1, 2.4, 0.0), (2.0, 2.4, 0.0), (2.0, 0.0, 0.0))
quad("wallA", (dx0, dh, 0.0), (dx0, 2.4, 0.0), (dx1, 2.4, 0.0), (dx1, dh, 0.0))

# The door: hinged at x = dx1, opened by 6 degrees into room B.
angle = math.radians(12.0)
width = dx1 - dx0
ex, ez = dx1 - width * math.cos(angle), -width * math.sin(angle)
quad("door", (dx1, 0.0, 0.0), (dx1, dh, 0.0), (ex, dh, ez), (ex, 0.0, ez))

# The light: a small square on room B's ceiling, far from the door.
ly = 2.39
quad("light", (0.8, ly, -2.5), (1.3, ly, -2.5), (1.3, ly, -2.0), (0.8, ly, -2.0))

with open(os.path.join(HERE, "door.obj"), "w") as f:
    f.write("# Veach's door scene, written by make_door.py\nmtllib door.mtl\n")
    for v in verts:
        f.write("v %.6f %.6f %.6f\n" % v)
    current = None
    for mat, idx in faces:
        if mat != current:
            f.write("usemtl %s\n" % mat)
            current = mat
        f.write("f %s\n" % " ".join(str(i) for i in idx))

with open(os.path.join(HERE, "door.mtl"), "w") as f:
    f.write("# Materials of the door scene (written by make_door.py)\n")
    for name, kd in [("floorA", (0.55, 0.45, 0.35)), ("wallA", (0.75, 0.75, 0.72)),
                     ("floorB", (0.5, 0.5, 0.5)), ("wallB", (0.75, 0.72, 0.68)),
                     ("door", (0.6, 0.4, 0.25))]:
        f.write("newmtl %s\nKd %.3f %.3f %.3f\n" % ((name,) + kd))
    f.write("newmtl light\nKd 0 0 0\nKe 1200 1080 900\n")
