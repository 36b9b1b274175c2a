"""Builds a small lookdev scene in Blender and exports it as glTF 2.0 (.glb), so that Glint is
tested on an asset written by Blender's own exporter rather than by Glint's tests.

    blender -b --factory-startup --python scenes/assets/blender_export.py -- scenes/assets/blender_scene.glb

The scene (Blender's +z up; the exporter converts to glTF's +y up): a ground plane, a gold
sphere and a linked duplicate of it (one mesh, two nodes), a cube with a generated checker
base-colour texture and an emissive strip, a camera, a point light and a sun.
"""
import sys

import numpy

numpy.bool = bool  # Debian's Blender 3.4 glTF add-on still uses numpy.bool (removed in 1.24)

import bpy  # noqa: E402

out = sys.argv[sys.argv.index("--") + 1]

bpy.ops.wm.read_factory_settings(use_empty=True)


def principled(name, base, metallic=0.0, roughness=0.5):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    return mat, bsdf


bpy.ops.mesh.primitive_plane_add(size=8, location=(0, 0, 0))
ground = bpy.context.object
ground.name = "ground"
ground.data.materials.append(principled("ground", (0.6, 0.6, 0.6), 0.0, 0.8)[0])

bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=0.7, location=(-1.2, 0, 0.7))
sphere = bpy.context.object
sphere.name = "gold_sphere"
bpy.ops.object.shade_smooth()
sphere.data.materials.append(principled("gold", (1.0, 0.77, 0.34), 1.0, 0.3)[0])
twin = sphere.copy()  # linked duplicate: the same mesh data
twin.name = "gold_sphere_twin"
twin.location = (-1.2, 2.0, 0.7)
bpy.context.collection.objects.link(twin)

bpy.ops.mesh.primitive_cube_add(size=1.2, location=(1.2, 0, 0.6))
cube = bpy.context.object
cube.name = "checker_cube"
mat, bsdf = principled("checker_paint", (1, 1, 1), 0.0, 0.4)
image = bpy.data.images.new("checker", 64, 64)
image.generated_type = "COLOR_GRID"
image.pack()
tex = mat.node_tree.nodes.new("ShaderNodeTexImage")
tex.image = image
mat.node_tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
cube.data.materials.append(mat)

bpy.ops.mesh.primitive_plane_add(size=0.6, location=(0, -1.5, 1.2), rotation=(1.5708, 0, 0))
strip = bpy.context.object
strip.name = "lamp_panel"
lamp, lamp_bsdf = principled("lamp_panel", (0.1, 0.1, 0.1), 0.0, 0.9)
lamp_bsdf.inputs["Emission"].default_value = (1.0, 0.9, 0.7, 1.0)
lamp_bsdf.inputs["Emission Strength"].default_value = 5.0
strip.data.materials.append(lamp)

bpy.ops.object.camera_add(location=(0, -7, 3.5))
camera = bpy.context.object
camera.name = "main_camera"
constraint = camera.constraints.new("TRACK_TO")
constraint.target = sphere
bpy.context.view_layer.update()
camera.matrix_world = camera.matrix_world.copy()  # bake the constraint
camera.constraints.remove(constraint)
camera.data.lens = 35
bpy.context.scene.camera = camera
bpy.context.scene.render.resolution_x = 320
bpy.context.scene.render.resolution_y = 240

bpy.ops.object.light_add(type="POINT", location=(2, -2, 4))
bpy.context.object.name = "key_light"
bpy.context.object.data.energy = 500.0
bpy.ops.object.light_add(type="SUN", location=(0, 0, 10), rotation=(0.6, 0.2, 0.4))
bpy.context.object.name = "sun"
bpy.context.object.data.energy = 2.0

bpy.ops.export_scene.gltf(
    filepath=out,
    export_format="GLB",
    export_cameras=True,
    export_lights=True,
    export_yup=True,
    export_apply=True,
)
print("wrote", out)
