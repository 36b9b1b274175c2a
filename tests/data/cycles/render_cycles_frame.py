# Renders scenes/cornell with Blender's Cycles into a multilayer EXR like an artist's: Combined
# plus Cycles' denoising data passes (Denoising Albedo/Normal/Depth), no variance, no half buffers,
# no denoiser applied. The test frames of tests/data/cycles/ (README.md there) come from it:
#
#   blender -b -P tests/data/cycles/render_cycles_frame.py -- --spp 8 --seed 1 --size 128 \
#       --out tests/data/cycles/cornell_8spp_seed1.exr
#   blender -b -P tests/data/cycles/render_cycles_frame.py -- --spp 4096 --seed 99 --size 128 \
#       --no-passes --out tests/data/cycles/cornell_reference.exr
#
# The scene (geometry, camera, materials, sampling settings) is lab/bench/cycles/cornell_cycles.py's
# build_scene; this script only sets the size, the passes and the file format (half float, ZIP).
import argparse
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.normpath(os.path.join(HERE, "..", "..", "..", "lab", "bench", "cycles")))
import cornell_cycles  # noqa: E402  (needs the path above)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="render_cycles_frame.py")
    p.add_argument("--spp", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--size", type=int, default=96)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--no-passes", action="store_true",
                   help="Combined only (the reference)")
    p.add_argument("--out", required=True)
    return p.parse_args(argv)


def main():
    args = parse_args()
    build = argparse.Namespace(spp=args.spp, threads=args.threads, max_depth=8, width=args.size,
                               height=args.size, seed=args.seed, out="",
                               obj=os.path.join(cornell_cycles.SCENE_DIR, "cornell_box.obj"))
    scene = cornell_cycles.build_scene(build)
    view_layer = scene.view_layers[0]
    view_layer.cycles.denoising_store_passes = not args.no_passes
    r = scene.render
    r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    r.image_settings.color_depth = "16"
    r.image_settings.exr_codec = "ZIP"
    r.use_compositing = False
    r.use_sequencer = False
    r.filepath = os.path.abspath(args.out)
    r.use_file_extension = False
    bpy.ops.render.render(write_still=True)
    print("wrote", r.filepath, flush=True)


if __name__ == "__main__":
    main()
