# Renders an asset (glTF .glb/.gltf, or a Wavefront .obj) with Blender's Cycles as glint-render
# renders the bare asset (docs/assets.md, docs/obj-assets.md): imported by Blender's glTF or OBJ
# importer (OBJ's +y up becoming Blender's +z, as glTF's does), the asset's first camera (or
# glint-render's framing camera when it has none), a uniform white world of radiance 1 when the
# asset has no lights (else black), a box pixel filter, linear output. For the side-by-side of
# lab/bench/cycles/gltf_compare.sh.
#
#   blender -b -P lab/bench/cycles/gltf_cycles.py -- model.glb --width 640 --height 427 \
#       --spp 256 --threads 2 --out /tmp/cycles.exr [--single-scatter] [--lambert]
#
# --lambert replaces every Principled BSDF the importer built by a Lambertian (a Diffuse BSDF of
# roughness 0) of its base colour, as Glint reads an MTL material with a non-black Kd: Blender's
# OBJ importer turns Ks and Ns into a specular layer that Glint does not model, and the
# Principled diffuse lobe is Burley's, not Lambert's (a few % apart by angle).
#
# Debian's Blender 3.4 glTF importer still uses numpy.bool, which Debian's numpy 1.24 removed:
# it is set back to bool before the importer runs. Prints one JSON line starting with
# {"renderer": "cycles" on stdout.
import argparse
import json
import math
import sys
import time

import numpy

if not hasattr(numpy, "bool"):
    numpy.bool = bool  # Blender 3.4's glTF importer predates numpy 1.24

import bpy
from mathutils import Vector


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="gltf_cycles.py")
    p.add_argument("asset")
    p.add_argument("--width", type=int, required=True)
    p.add_argument("--height", type=int, required=True)
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--max-depth", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--out", required=True)
    p.add_argument("--single-scatter", action="store_true",
                   help="Principled BSDFs with single-scattering GGX (Cycles' default is "
                        "multiple scattering, which the glTF BRDF does not model)")
    p.add_argument("--lambert", action="store_true",
                   help="Principled BSDFs replaced by Lambertians of their base colour")
    return p.parse_args(argv)


def framing_camera(scene, width, height):
    """glint-render's camera for an asset without one (docs/assets.md): on glTF's +z (Blender's
    -y) of the centre of the vertices' bounding box, looking back at it, fovY 40 degrees, at the
    distance at which the sphere of half the box's diagonal fits the narrower field of view."""
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
    cam.rotation_euler = (math.pi / 2, 0.0, 0.0)  # looks down +y (glTF's -z), z up
    scene.collection.objects.link(cam)
    return cam


def build_scene(args):
    """The imported asset, its camera, world and Cycles' settings (`args` as parse_args gives):
    everything but the output, for this script and lab/bench/cycles/race_cycles.py."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if args.asset.lower().endswith(".obj"):
        bpy.ops.import_scene.obj(filepath=args.asset)
    else:
        bpy.ops.import_scene.gltf(filepath=args.asset)
    scene = bpy.context.scene
    cameras = [o for o in scene.objects if o.type == "CAMERA"]
    if cameras:
        scene.camera = cameras[0]
    else:
        scene.camera = framing_camera(scene, args.width, args.height)

    if args.single_scatter:
        for material in bpy.data.materials:
            for node in (material.node_tree.nodes if material.use_nodes else []):
                if node.type == "BSDF_PRINCIPLED":
                    node.distribution = "GGX"
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

    # A white world of radiance 1 when the asset brings no light (as glint-render's bare
    # asset), else black.
    lit = any(o.type == "LIGHT" for o in scene.objects)
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0 if lit else 1.0
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
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
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
    cycles.blur_glossy = 0.0
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    cycles.filter_width = 0.01  # a box over the pixel, as Glint's film
    return scene


def main():
    args = parse_args()
    scene = build_scene(args)
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = args.out

    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - start
    print(json.dumps({"renderer": "cycles", "asset": args.asset, "spp": args.spp,
                      "seconds": seconds, "out": args.out}), flush=True)


if __name__ == "__main__":
    main()
