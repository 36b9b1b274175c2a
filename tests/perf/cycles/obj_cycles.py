# Renders a Wavefront OBJ with Blender's Cycles as glint-render renders the bare OBJ
# (docs/obj-assets.md): Blender's OBJ importer (bpy.ops.import_scene.obj, OBJ's +y up becoming
# Blender's +z), glint-render's framing camera, a uniform white world of radiance 1, a box pixel
# filter, linear output. For the side-by-side of tests/perf/cycles/obj_compare.sh.
#
#   blender -b -P tests/perf/cycles/obj_cycles.py -- model.obj --width 640 --height 480 \
#       --spp 256 --threads 2 --out /tmp/cycles.exr [--lambert]
#
# --lambert replaces every Principled BSDF the importer built by a Lambertian (a Diffuse BSDF of
# roughness 0) of its base colour, as Glint reads an MTL material with a non-black Kd: the
# importer turns Ks and Ns into a specular layer that Glint does not model, and the Principled
# diffuse lobe is Burley's, not Lambert's (a few % apart by angle). Prints one JSON line
# starting with {"renderer": "cycles" on stdout.
import argparse
import json
import math
import sys
import time

import bpy
from mathutils import Vector


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="obj_cycles.py")
    p.add_argument("obj")
    p.add_argument("--width", type=int, required=True)
    p.add_argument("--height", type=int, required=True)
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--max-depth", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--lambert", action="store_true")
    p.add_argument("--out", required=True)
    return p.parse_args(argv)


def framing_camera(scene, width, height):
    """glint-render's camera for a bare OBJ: on the OBJ's +z (Blender's -y) of the centre of the
    vertices' bounding box, looking back at it, fovY 40 degrees, at the distance at which the
    sphere of half the box's diagonal fits the narrower field of view."""
    points = [o.matrix_world @ v.co for o in scene.objects if o.type == "MESH"
              for v in o.data.vertices]
    lo = Vector([min(p[i] for p in points) for i in range(3)])
    hi = Vector([max(p[i] for p in points) for i in range(3)])
    centre, radius = (lo + hi) / 2, max((hi - lo).length / 2, 1e-6)
    half_y = math.radians(40.0) / 2
    half_x = math.atan(math.tan(half_y) * width / height)
    distance = radius / math.sin(min(half_x, half_y))
    data = bpy.data.cameras.new("frame")
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(40.0)
    data.clip_start, data.clip_end = distance * 1e-3, distance * 10 + radius * 10
    cam = bpy.data.objects.new("frame", data)
    cam.location = centre + Vector((0.0, -distance, 0.0))
    cam.rotation_euler = (math.pi / 2, 0.0, 0.0)  # looks down +y (the OBJ's -z), z up
    scene.collection.objects.link(cam)
    return cam


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.obj(filepath=args.obj)
    scene = bpy.context.scene
    scene.camera = framing_camera(scene, args.width, args.height)
    if args.lambert:
        for material in bpy.data.materials:
            tree = material.node_tree if material.use_nodes else None
            for node in list(tree.nodes) if tree else []:
                if node.type != "BSDF_PRINCIPLED":
                    continue
                # A Diffuse BSDF of roughness 0 is Lambertian; it takes the base colour (value or
                # image) and replaces the Principled BSDF at the material output.
                diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
                base = node.inputs["Base Color"]
                diffuse.inputs["Color"].default_value = base.default_value
                for link in base.links:
                    tree.links.new(link.from_socket, diffuse.inputs["Color"])
                for link in list(node.outputs["BSDF"].links):
                    tree.links.new(diffuse.outputs["BSDF"], link.to_socket)

    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.world = world

    scene.render.engine = "CYCLES"
    scene.render.resolution_x = args.width
    scene.render.resolution_y = args.height
    scene.render.resolution_percentage = 100
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"  # linear values, no Filmic curve
    scene.view_settings.look = "None"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = args.spp
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = args.seed
    cycles.max_bounces = args.max_depth
    cycles.diffuse_bounces = args.max_depth
    cycles.glossy_bounces = args.max_depth
    cycles.transmission_bounces = args.max_depth
    cycles.transparent_max_bounces = args.max_depth
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.filter_width = 0.01  # a box over the pixel, as Glint's film
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = args.out

    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    print(json.dumps({"renderer": "cycles", "obj": args.obj, "spp": args.spp,
                      "seconds": time.perf_counter() - start, "out": args.out}), flush=True)


main()
