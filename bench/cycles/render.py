# Renders a glTF file with Cycles, as an independent reference for bumprad: Blender's own glTF
# importer reads the file (or, for a bumprad scene file, bumprad_scene.py builds it), Cycles
# path-traces it (no denoising, no clamping, no adaptive
# sampling, a box filter one pixel wide, black world) and the image is written as linear EXR:
# radiance, as bumprad's images are.
#   blender -b --factory-startup --python bench/cycles/render.py -- MODEL.(glb|json) OUT.exr \
#       [--spp 1024] [--size 256] [--seed 1] [--materials lambert|principled]
# --materials lambert (the default) renders each metallic-0 Principled BSDF as the Lambert
# surface bumprad reads it as (docs/import.md: a dielectric's specular coat is not modelled),
# keeping its base colour, normal map and emission; principled keeps Cycles' Principled BSDF,
# which measures what that reading leaves out.
import os
import sys

import bpy
import numpy

# Debian's Blender 3.4 glTF importer still says np.bool, which Debian's numpy 1.24 removed.
if not hasattr(numpy, "bool"):
    numpy.bool = bool


def option(name, default):
    return type(default)(args[args.index(name) + 1]) if name in args else default


args = sys.argv[sys.argv.index("--") + 1:]
model, out = args[0], args[1]
spp, size, seed = option("--spp", 1024), option("--size", 256), option("--seed", 1)
materials = option("--materials", "lambert")

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
height = size
if model.endswith(".json"):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import bumprad_scene

    height = bumprad_scene.build(model, size)
else:
    bpy.ops.import_scene.gltf(filepath=model)
    scene.camera = next(o for o in scene.objects if o.type == "CAMERA")


def as_lambert(m):
    nodes, links = m.node_tree.nodes, m.node_tree.links
    p = next((n for n in nodes if n.type == "BSDF_PRINCIPLED"), None)
    if p is None or p.inputs["Metallic"].default_value > 0 or p.inputs["Metallic"].is_linked:
        return
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    for name in ("Color", "Normal"):
        source = p.inputs["Base Color" if name == "Color" else name]
        if source.is_linked:
            links.new(source.links[0].from_socket, diffuse.inputs[name])
        elif name == "Color":
            diffuse.inputs[name].default_value = source.default_value
    emission = nodes.new("ShaderNodeEmission")
    source = p.inputs["Emission"]
    if source.is_linked:
        links.new(source.links[0].from_socket, emission.inputs["Color"])
    else:
        emission.inputs["Color"].default_value = source.default_value
    emission.inputs["Strength"].default_value = p.inputs["Emission Strength"].default_value
    add = nodes.new("ShaderNodeAddShader")
    links.new(diffuse.outputs[0], add.inputs[0])
    links.new(emission.outputs[0], add.inputs[1])
    output = next(n for n in nodes if n.type == "OUTPUT_MATERIAL")
    links.new(add.outputs[0], output.inputs["Surface"])


if materials == "lambert" and not model.endswith(".json"):
    for m in bpy.data.materials:
        if m.use_nodes:
            as_lambert(m)

world = bpy.data.worlds.new("black")
world.color = (0, 0, 0)
scene.world = world

cycles = scene.cycles
scene.render.engine = "CYCLES"
cycles.device = "CPU"
cycles.samples = spp
cycles.seed = seed
cycles.use_adaptive_sampling = False
cycles.use_denoising = False
cycles.max_bounces = cycles.diffuse_bounces = cycles.glossy_bounces = 128
cycles.transmission_bounces = cycles.transparent_max_bounces = 128
cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0
cycles.pixel_filter_type = "BOX"
cycles.filter_width = 1.0

scene.render.resolution_x, scene.render.resolution_y = size, height
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
