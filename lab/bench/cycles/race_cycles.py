# Cycles' side of the equal-time race (lab/bench/race.sh, docs/lab/race.md): scenes/cornell (the
# scene of cornell_cycles.py) or a bare glTF asset (gltf_cycles.py's import, camera and world),
# rendered with adaptive sampling at a noise threshold within a wall-clock budget that counts
# from the moment the shell started Blender (--started, seconds since the epoch): Blender's
# start-up, the import and the scene building are spent before Cycles' own time limit is set to
# what is left. Writes a multilayer EXR (float): Combined and, with --passes, the Denoising
# Albedo and Normal passes that OIDN takes.
#
#   blender -b -P lab/bench/cycles/race_cycles.py -- cornell --width 256 --height 256 \
#       --budget 8 --started $(date +%s.%N) --noise-threshold 0.01 --passes --out /tmp/c.exr
#   blender -b -P lab/bench/cycles/race_cycles.py -- scenes/fox/Fox.glb --width 256 \
#       --height 192 --spp 4096 --seed 99 --out /tmp/fox_ref.exr          # a reference
#
# A skinned asset is rendered in its rest pose, as Glint renders it: Blender's importer poses the
# armature at the first frame of the first animation, so the Armature modifiers are removed.
# Prints one JSON line starting with {"renderer": "cycles" on stdout.
import argparse
import json
import math
import os
import sys
import time

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cornell_cycles  # noqa: E402  (needs the path above)
import gltf_cycles  # noqa: E402


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="race_cycles.py")
    p.add_argument("scene", help="'cornell', or a .glb/.gltf asset")
    p.add_argument("--width", type=int, default=256)
    p.add_argument("--height", type=int, default=256)
    p.add_argument("--spp", type=int, default=4096, help="the most samples a pixel takes")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--max-depth", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--noise-threshold", type=float, default=0.0,
                   help="adaptive sampling's threshold (0: adaptive off, every pixel takes spp)")
    p.add_argument("--budget", type=float, default=0.0,
                   help="wall-clock seconds from --started to the end of the render (0: none)")
    p.add_argument("--started", type=float, default=0.0,
                   help="when Blender was started (time.time() units); default: now")
    p.add_argument("--passes", action="store_true", help="also the denoising data passes")
    p.add_argument("--fov-y", type=float, default=0.0,
                   help="degrees: narrow the camera's vertical field of view (0: as imported)")
    p.add_argument("--glint-camera", default="",
                   help="write the scene's camera as a Glint scene.json camera (glTF axes) here")
    p.add_argument("--out", required=True)
    return p.parse_args(argv)


def build(args):
    """The scene of cornell_cycles.py or gltf_cycles.py, sampling settings as theirs."""
    if args.scene == "cornell":
        ns = argparse.Namespace(spp=args.spp, threads=args.threads, max_depth=args.max_depth,
                                width=args.width, height=args.height, seed=args.seed, out="",
                                obj=os.path.join(cornell_cycles.SCENE_DIR, "cornell_box.obj"))
        return cornell_cycles.build_scene(ns)
    ns = argparse.Namespace(asset=args.scene, width=args.width, height=args.height, spp=args.spp,
                            threads=args.threads, max_depth=args.max_depth, seed=args.seed,
                            out="", single_scatter=False, lambert=False)
    scene = gltf_cycles.build_scene(ns)
    for obj in scene.objects:
        for mod in [m for m in obj.modifiers if m.type == "ARMATURE"]:
            obj.modifiers.remove(mod)
    return scene


def write_glint_camera(scene, path):
    """The camera as scene.json's "camera" object: Blender's (x, y, z) is glTF's (x, -z, y)."""
    bpy.context.view_layer.update()  # the matrices of objects made by the script
    cam = scene.camera
    if cam.data.sensor_fit != "VERTICAL":
        sys.exit("race_cycles.py: --glint-camera needs a camera of vertical sensor fit")
    gltf = lambda v: [v[0], v[2], -v[1]]
    rotation = cam.matrix_world.to_quaternion()
    position = cam.matrix_world.translation
    with open(path, "w") as f:
        json.dump({"position": gltf(position),
                   "lookAt": gltf(position + rotation @ Vector((0.0, 0.0, -1.0))),
                   "up": gltf(rotation @ Vector((0.0, 1.0, 0.0))),
                   "fovY": math.degrees(cam.data.angle_y)}, f)


def main():
    args = parse_args()
    started = args.started or time.time()
    scene = build(args)
    if args.fov_y > 0:
        scene.camera.data.sensor_fit = "VERTICAL"
        scene.camera.data.angle_y = math.radians(args.fov_y)
    if args.glint_camera:
        write_glint_camera(scene, args.glint_camera)
    c = scene.cycles
    c.use_adaptive_sampling = args.noise_threshold > 0
    if c.use_adaptive_sampling:
        c.adaptive_threshold = args.noise_threshold
        c.adaptive_min_samples = 0  # Cycles' automatic start
    left = 0.0
    if args.budget > 0:
        # Cycles' time limit counts its own render; what Blender spent so far is taken off. A
        # start-up longer than the budget still renders (Cycles' shortest limit, one sample).
        left = max(args.budget - (time.time() - started), 0.01)
        c.time_limit = left
    scene.view_layers[0].cycles.denoising_store_passes = args.passes
    r = scene.render
    r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    r.image_settings.color_depth = "32"
    r.image_settings.exr_codec = "ZIP"
    r.use_compositing = False
    r.use_sequencer = False
    r.use_file_extension = False
    r.filepath = os.path.abspath(args.out)
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    done = time.time()
    print(json.dumps({"renderer": "cycles", "scene": args.scene, "spp": args.spp,
                      "noiseThreshold": args.noise_threshold, "budget": args.budget,
                      "timeLimit": left, "setupSeconds": t0 - started,
                      "renderSeconds": done - t0, "seconds": done - started,
                      "out": r.filepath}), flush=True)


if __name__ == "__main__":
    main()
