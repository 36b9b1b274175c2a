# Renders a Glint scene.json made of OBJ shapes with scene-level materials (scenes/glossy,
# scenes/envmap) with Blender's Cycles, for the equal-spp comparison of the accuracy-per-sample
# issue (lab/bench/cycles/sampler_compare.sh).
#
#   blender -b -P lab/bench/cycles/scene_cycles.py -- scenes/glossy/scene.json --spp 64 \
#       --threads 2 --out /tmp/cycles.exr
#
# The conversion keeps what the comparison needs and says where Cycles 3.4 has no exact match:
#   diffuse            -> Diffuse BSDF, roughness 0 (Lambertian), same albedo
#   emission           -> Emission shader, strength = max component (radiance as in Glint)
#   conductor          -> Principled BSDF, metallic 1, GGX, same roughness (both use alpha = r^2),
#                         base colour = Glint's normal-incidence reflectance (`specular`, or the
#                         exact conductor Fresnel at 0 degrees from eta/k); Cycles' metallic
#                         Fresnel is its own Schlick-like blend towards white, so gold at grazing
#                         angles differs slightly from Glint's exact complex-IOR Fresnel
#   dielectric         -> Glass BSDF, same IOR, sharp or GGX with the same roughness (Glint tints
#                         transmission only; white here)
#   environment image  -> world Environment Texture, same lat-long orientation (u = 0.5 is -z,
#                         checked against Glint's reference), strength = `scale`
# Smooth-shaded meshes (OBJs with vertex normals) are shaded smooth in Blender (normals
# interpolated from the vertex positions' faces, not the OBJ's). Because of these differences
# each renderer is measured against its own converged reference; only the error per sample at
# equal spp is compared, not the pictures. Camera, film, box pixel filter, depth and the sampling
# tricks are set as in cornell_cycles.py. Only the render call is timed. Prints one JSON line
# starting with {"renderer": "cycles" on stdout.
import argparse
import json
import math
import os
import sys
import time

import bpy
from mathutils import Matrix, Vector


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="scene_cycles.py")
    p.add_argument("scene")
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--max-depth", type=int, default=None, help="default: the scene's maxDepth")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--env-rotate", type=float, default=-90.0,
                   help="degrees about Blender's +z that align Blender's lat-long with Glint's")
    p.add_argument("--out", default="")
    return p.parse_args(argv)


def fail(msg):
    print(f"scene_cycles.py: {msg}", file=sys.stderr, flush=True)
    sys.exit(1)


def read_obj(path):
    """Positions, triangles (position indices) and whether the OBJ has vertex normals."""
    verts, faces, has_normals = [], [], False
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                verts.append(Vector(tuple(float(x) for x in t[1:4])))
            elif t[0] == "vn":
                has_normals = True
            elif t[0] == "f":
                idx = []
                for tok in t[1:]:
                    i = int(tok.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                for k in range(1, len(idx) - 1):  # fan-triangulate as Glint's loader does
                    faces.append((idx[0], idx[k], idx[k + 1]))
    return verts, faces, has_normals


def transform_matrix(t):
    """Glint's object-to-world transform: T * R * S (docs/scene-format.md)."""
    m = Matrix.Identity(4)
    if not t:
        return m
    s = t.get("scale", 1.0)
    s = [s, s, s] if isinstance(s, (int, float)) else s
    S = Matrix.Diagonal((s[0], s[1], s[2], 1.0))
    R = Matrix.Identity(4)
    if "rotate" in t:
        deg, axis = t["rotate"]
        R = Matrix.Rotation(math.radians(deg), 4, Vector(axis).normalized())
    T = Matrix.Translation(Vector(t.get("translate", [0.0, 0.0, 0.0])))
    return T @ R @ S


def to_blender(p):
    """Glint's frame (+y up) to Blender's (+z up): (x, y, z) -> (x, -z, y), a rotation."""
    return (p[0], -p[2], p[1])


def conductor_f0(eta, k):
    """Reflectance of a conductor at normal incidence from its complex IOR."""
    return [((n - 1) ** 2 + kk ** 2) / ((n + 1) ** 2 + kk ** 2) for n, kk in zip(eta, k)]


def make_material(name, m):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    kind = m.get("type")
    emission = m.get("emission", [0.0, 0.0, 0.0])
    albedo = m.get("albedo", [0.8, 0.8, 0.8] if kind == "diffuse" else [1.0, 1.0, 1.0])
    surface = None
    if kind == "diffuse" and max(albedo) > 0.0:
        surface = nt.nodes.new("ShaderNodeBsdfDiffuse")
        surface.inputs["Color"].default_value = (*albedo, 1.0)
        surface.inputs["Roughness"].default_value = 0.0
    elif kind == "conductor":
        surface = nt.nodes.new("ShaderNodeBsdfPrincipled")
        surface.distribution = "GGX"
        f0 = (conductor_f0(m["eta"], m["k"]) if "eta" in m
              else m.get("specular", [1.0, 1.0, 1.0]))
        surface.inputs["Base Color"].default_value = (*[a * b for a, b in zip(f0, albedo)], 1.0)
        surface.inputs["Metallic"].default_value = 1.0
        surface.inputs["Roughness"].default_value = m.get("roughness", 0.0)
    elif kind == "dielectric":
        surface = nt.nodes.new("ShaderNodeBsdfGlass")
        # Cycles squares Roughness as Glint does (alpha = r^2); below Glint's alpha 1e-3 both
        # are sharp.
        rough = m.get("roughness", 0.0)
        surface.distribution = "GGX" if rough * rough >= 1e-3 else "SHARP"
        surface.inputs["Roughness"].default_value = rough
        surface.inputs["IOR"].default_value = m.get("ior", 1.5)
    elif kind == "mirror":
        surface = nt.nodes.new("ShaderNodeBsdfGlossy")
        surface.distribution = "SHARP"
        surface.inputs["Color"].default_value = (*albedo, 1.0)
    elif kind != "diffuse":
        fail(f"material '{name}': type '{kind}' has no Cycles conversion here")
    if max(emission) > 0.0:
        em = nt.nodes.new("ShaderNodeEmission")
        s = max(emission)
        em.inputs["Color"].default_value = (emission[0] / s, emission[1] / s, emission[2] / s, 1.0)
        em.inputs["Strength"].default_value = s
        if surface is not None:
            add = nt.nodes.new("ShaderNodeAddShader")
            nt.links.new(surface.outputs[0], add.inputs[0])
            nt.links.new(em.outputs[0], add.inputs[1])
            surface = add
        else:
            surface = em
    if surface is None:  # black diffuse: absorbs everything
        surface = nt.nodes.new("ShaderNodeBsdfDiffuse")
        surface.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    nt.links.new(surface.outputs[0], out.inputs["Surface"])
    return mat


def build_scene(args, desc, folder):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    materials = {n: make_material(n, m) for n, m in desc.get("materials", {}).items()}
    for i, shape in enumerate(desc.get("shapes", [])):
        if "obj" not in shape or "material" not in shape:
            fail(f"shapes[{i}]: only OBJ shapes with a scene material are converted")
        if "motion" in shape:
            fail(f"shapes[{i}]: motion blur is not converted")
        verts, faces, smooth = read_obj(os.path.join(folder, shape["obj"]))
        M = transform_matrix(shape.get("transform"))
        mesh = bpy.data.meshes.new(f"shape{i}")
        mesh.from_pydata([to_blender(M @ v) for v in verts], [], faces)
        mesh.materials.append(materials[shape["material"]])
        for poly in mesh.polygons:
            poly.use_smooth = smooth
        mesh.update()
        obj = bpy.data.objects.new(f"shape{i}", mesh)
        scene.collection.objects.link(obj)

    cam_desc = desc["camera"]
    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(cam_desc.get("fovY", 45.0))
    cam_data.clip_start = 1e-3
    cam_data.clip_end = 1e5
    cam = bpy.data.objects.new("camera", cam_data)
    pos = Vector(to_blender(cam_desc["position"]))
    target = Vector(to_blender(cam_desc["lookAt"]))
    cam.location = pos
    cam.rotation_euler = (target - pos).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(cam)
    scene.camera = cam

    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    nt = world.node_tree
    bg = nt.nodes["Background"]
    env = desc.get("environment")
    if env and "image" in env:
        coord = nt.nodes.new("ShaderNodeTexCoord")
        mapping = nt.nodes.new("ShaderNodeMapping")
        mapping.vector_type = "VECTOR"
        mapping.inputs["Rotation"].default_value = (
            0.0, 0.0, math.radians(args.env_rotate + env.get("rotate", 0.0)))
        tex = nt.nodes.new("ShaderNodeTexEnvironment")
        tex.image = bpy.data.images.load(os.path.join(folder, env["image"]))
        tex.interpolation = "Linear"
        nt.links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
        nt.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
        nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
        bg.inputs["Strength"].default_value = env.get("scale", 1.0)
        world.cycles.sampling_method = "AUTOMATIC"
    elif env and "color" in env:
        bg.inputs["Color"].default_value = (*env["color"], 1.0)
        bg.inputs["Strength"].default_value = env.get("scale", 1.0)
    else:
        bg.inputs["Strength"].default_value = 0.0
    scene.world = world

    film = desc.get("film", {})
    render_desc = desc.get("render", {})
    depth = args.max_depth if args.max_depth is not None else render_desc.get("maxDepth", 8)
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y = film.get("width", 256), film.get("height", 256)
    r.resolution_percentage = 100
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
    c.max_bounces = depth
    c.diffuse_bounces = depth
    c.glossy_bounces = depth
    c.transmission_bounces = depth
    c.volume_bounces = 0
    c.transparent_max_bounces = depth
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    return scene, depth


def main():
    args = parse_args()
    try:
        with open(args.scene) as f:
            desc = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{args.scene}: {e}")
    scene, depth = build_scene(args, desc, os.path.dirname(os.path.abspath(args.scene)))
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    seconds = time.perf_counter() - t0
    if args.out:
        bpy.data.images["Render Result"].save_render(filepath=args.out)
    w, h = scene.render.resolution_x, scene.render.resolution_y
    samples = w * h * args.spp
    print(json.dumps({
        "renderer": "cycles",
        "blender": bpy.app.version_string,
        "scene": args.scene,
        "width": w, "height": h, "spp": args.spp,
        "maxDepth": depth, "threads": args.threads,
        "seconds": seconds, "samples": samples,
        "samplesPerSecond": samples / seconds,
        "out": args.out,
    }), flush=True)


if __name__ == "__main__":
    main()
