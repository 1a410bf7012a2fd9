# Builds a bumprad scene file in Blender for Cycles to render, so that a built-in scene is
# measured against an independent renderer as it stands, not through an export: each quad
# object as one face (its winding kept, so its normal is bumprad's front), a Lambert surface
# of the material's reflectance and an emitter of its emission (bumprad's emission is a
# radiosity, pi times the radiance Cycles' emission strength gives), one-sided as bumprad's
# are (a back face is black and emits nothing: Cycles' emission shader emits from both
# sides, and a lamp set 0.1 mm under a ceiling would light the ceiling through the gap), and
# the pinhole camera. Other shapes are refused by name.
import json
import math

import bpy
import mathutils


def _rgb(value):
    return tuple(value) if isinstance(value, list) else (value, value, value)


def _material(name, m):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*_rgb(m.get("reflectance", 0.5)), 1)
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (
        *(c / math.pi for c in _rgb(m.get("emission", 0))), 1)
    front = nodes.new("ShaderNodeAddShader")
    links.new(diffuse.outputs[0], front.inputs[0])
    links.new(emission.outputs[0], front.inputs[1])
    black = nodes.new("ShaderNodeBsdfDiffuse")
    black.inputs["Color"].default_value = (0, 0, 0, 1)
    side = nodes.new("ShaderNodeNewGeometry")
    mix = nodes.new("ShaderNodeMixShader")
    links.new(side.outputs["Backfacing"], mix.inputs["Fac"])
    links.new(front.outputs[0], mix.inputs[1])
    links.new(black.outputs[0], mix.inputs[2])
    output = nodes.new("ShaderNodeOutputMaterial")
    links.new(mix.outputs[0], output.inputs["Surface"])
    return mat


def build(path, width):
    """Adds the scene's objects, materials and camera to the current Blender scene, the image
    `width` pixels across (the camera's aspect kept); returns the image's height."""
    with open(path) as f:
        s = json.load(f)
    materials = {name: _material(name, m) for name, m in s["materials"].items()}
    extent = 0.0
    for o in s["objects"]:
        if o.get("type") != "quad":
            raise SystemExit(f"{path}: object {o.get('name')!r} is a {o.get('type')!r}: "
                             "only quads are built")
        mesh = bpy.data.meshes.new(o.get("name", "quad"))
        mesh.from_pydata([tuple(v) for v in o["vertices"]], [], [(0, 1, 2, 3)])
        mesh.materials.append(materials[o["material"]])
        bpy.context.scene.collection.objects.link(bpy.data.objects.new(mesh.name, mesh))
        extent = max([extent] + [abs(c) for v in o["vertices"] for c in v])
    c = s["camera"]
    position = mathutils.Vector(c["position"])
    forward = (mathutils.Vector(c["look_at"]) - position).normalized()
    right = forward.cross(mathutils.Vector(c.get("up", [0, 1, 0]))).normalized()
    up = right.cross(forward)
    camera = bpy.data.cameras.new("camera")
    camera.sensor_fit = "VERTICAL"
    camera.angle_y = math.radians(c.get("fov_deg", 40))
    camera.clip_start = 1e-4 * extent
    camera.clip_end = 1e3 * extent
    rig = bpy.data.objects.new("camera", camera)
    rotation = mathutils.Matrix((right, up, -forward)).transposed()  # columns: x, y, -view
    rig.matrix_world = mathutils.Matrix.Translation(position) @ rotation.to_4x4()
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.scene.camera = rig
    return round(width * c.get("height", 512) / c.get("width", 512))
