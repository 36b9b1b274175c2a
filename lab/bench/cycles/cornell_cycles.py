# Renders scenes/cornell with Blender's Cycles for the speed comparison of issue 3.
#
#   blender -b -P lab/bench/cycles/cornell_cycles.py -- --spp 64 --threads 2 --out /tmp/cycles.exr
#
# Builds the same box as scenes/cornell/scene.json from cornell_box.obj/.mtl (parsed here, so no
# importer add-on is needed), the same camera (vertical fov 39.3 degrees, 256 x 256), the same
# Lambertian albedos and light emission; CPU device, box pixel filter of width 1, adaptive
# sampling, denoising, light/clamp tricks off. Only the render call is timed (Blender start-up,
# scene building and writing the EXR are excluded). Prints one JSON line starting with
# {"renderer": "cycles" on stdout.
import argparse
import json
import math
import os
import sys
import time

import bpy
from mathutils import Vector

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE_DIR = os.path.normpath(os.path.join(HERE, "..", "..", "..", "scenes", "cornell"))


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="cornell_cycles.py")
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--max-depth", type=int, default=8)
    p.add_argument("--width", type=int, default=256)
    p.add_argument("--height", type=int, default=256)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--out", default="")
    p.add_argument("--obj", default=os.path.join(SCENE_DIR, "cornell_box.obj"))
    return p.parse_args(argv)


def read_mtl(path):
    """Kd and Ke of every material in an MTL file."""
    mats, cur = {}, None
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t or t[0].startswith("#"):
                continue
            if t[0] == "newmtl":
                cur = t[1]
                mats[cur] = {"Kd": (0.0, 0.0, 0.0), "Ke": (0.0, 0.0, 0.0)}
            elif t[0] in ("Kd", "Ke") and cur is not None:
                mats[cur][t[0]] = tuple(float(x) for x in t[1:4])
    return mats


def read_obj(path):
    """Vertices and faces (with material names) of an OBJ; negative indices resolved."""
    verts, faces, mtllib, mat = [], [], None, None
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "mtllib":
                mtllib = t[1]
            elif t[0] == "usemtl":
                mat = t[1]
            elif t[0] == "v":
                verts.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == "f":
                idx = []
                for tok in t[1:]:
                    i = int(tok.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                faces.append((idx, mat))
    return verts, faces, mtllib


def to_blender(p):
    """OBJ/Glint frame (+y up) to Blender's (+z up): (x, y, z) -> (x, -z, y), a rotation."""
    return (p[0], -p[2], p[1])


def make_material(name, kd, ke):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    if max(ke) > 0.0:
        # Cycles' emission closure on a mesh emits radiance color * strength.
        em = nt.nodes.new("ShaderNodeEmission")
        s = max(ke)
        em.inputs["Color"].default_value = (ke[0] / s, ke[1] / s, ke[2] / s, 1.0)
        em.inputs["Strength"].default_value = s
        nt.links.new(em.outputs["Emission"], out.inputs["Surface"])
    else:
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")  # roughness 0 = Lambertian
        d.inputs["Color"].default_value = (kd[0], kd[1], kd[2], 1.0)
        d.inputs["Roughness"].default_value = 0.0
        nt.links.new(d.outputs["BSDF"], out.inputs["Surface"])
    return m


def build_scene(args):
    # Start from an empty scene.
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    verts, faces, mtllib = read_obj(args.obj)
    mtl = read_mtl(os.path.join(os.path.dirname(args.obj), mtllib))
    names = sorted({m for _, m in faces})
    mesh = bpy.data.meshes.new("cornell")
    mesh.from_pydata([to_blender(v) for v in verts], [], [f for f, _ in faces])
    for n in names:
        mesh.materials.append(make_material(n, mtl[n]["Kd"], mtl[n]["Ke"]))
    for poly, (_, m) in zip(mesh.polygons, faces):
        poly.material_index = names.index(m)
    mesh.update()
    obj = bpy.data.objects.new("cornell", mesh)
    scene.collection.objects.link(obj)

    # Camera: position (278, 273, -800) looking at (278, 273, 0), up +y, vertical fov 39.3.
    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(39.3)
    cam_data.clip_start = 1.0
    cam_data.clip_end = 1e5
    cam = bpy.data.objects.new("camera", cam_data)
    pos = Vector(to_blender((278.0, 273.0, -800.0)))
    target = Vector(to_blender((278.0, 273.0, 0.0)))
    cam.location = pos
    cam.rotation_euler = (target - pos).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(cam)
    scene.camera = cam

    # Black world: the box is closed except towards the camera.
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world

    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y, r.resolution_percentage = args.width, args.height, 100
    r.threads_mode = "FIXED"
    r.threads = args.threads
    r.use_persistent_data = False
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    scene.view_settings.view_transform = "Standard"

    c = scene.cycles
    c.device = "CPU"
    c.samples = args.spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = args.seed
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.max_bounces = args.max_depth
    c.diffuse_bounces = args.max_depth
    c.glossy_bounces = args.max_depth
    c.transmission_bounces = args.max_depth
    c.volume_bounces = 0
    c.transparent_max_bounces = args.max_depth
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    return scene


def main():
    args = parse_args()
    scene = build_scene(args)
    # Time only the render call (scene sync, BVH build and path tracing, as Cycles reports).
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    seconds = time.perf_counter() - t0
    if args.out:
        bpy.data.images["Render Result"].save_render(filepath=args.out)
    samples = args.width * args.height * args.spp
    print(json.dumps({
        "renderer": "cycles",
        "blender": bpy.app.version_string,
        "width": args.width, "height": args.height, "spp": args.spp,
        "maxDepth": args.max_depth, "threads": args.threads,
        "seconds": seconds, "samples": samples,
        "samplesPerSecond": samples / seconds,
        "out": args.out,
    }), flush=True)


if __name__ == "__main__":
    main()
