# Builds, in Blender, the room that bumprad is measured against Cycles on, and exports it as
# glTF 2.0 binary through Blender's own exporter: a model from a modelling tool, as a user
# brings one. A Cornell-like box (red and green side walls, open front), a floor with a
# base-colour texture (a checker), a back wall with a tangent-space normal map (a grid of
# domes), two blocks, and an emissive panel set into a hole in the ceiling (so the panel's
# back faces the void above: Cycles' emission shader emits from both sides, bumprad's
# emitters from the front). Materials are glTF's metallic 0, roughness 1.
#   blender -b --factory-startup --python bench/cycles/room.py -- OUT.glb [--size 512]
import math
import os
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
out = os.path.abspath(args[0])
size = int(args[args.index("--size") + 1]) if "--size" in args else 512
work = os.path.dirname(out)

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene


def material(name, colour, texture=None, normal_map=None, emission=0.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    m.use_backface_culling = True  # exported as doubleSided false: rooms are one-sided
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*colour, 1)
    p.inputs["Metallic"].default_value = 0
    p.inputs["Roughness"].default_value = 1
    links = m.node_tree.links
    if texture:
        t = m.node_tree.nodes.new("ShaderNodeTexImage")
        t.image = texture
        links.new(t.outputs["Color"], p.inputs["Base Color"])
    if normal_map:
        t = m.node_tree.nodes.new("ShaderNodeTexImage")
        t.image = normal_map
        n = m.node_tree.nodes.new("ShaderNodeNormalMap")
        links.new(t.outputs["Color"], n.inputs["Color"])
        links.new(n.outputs["Normal"], p.inputs["Normal"])
    if emission:
        p.inputs["Emission"].default_value = (1, 1, 1, 1)
        p.inputs["Emission Strength"].default_value = emission
    return m


def image(name, n, texel, colourspace):
    img = bpy.data.images.new(name, n, n, alpha=False)
    img.colorspace_settings.name = colourspace
    pixels = []
    for row in range(n):  # Blender's rows run from the bottom up
        for col in range(n):
            pixels.extend((*texel((col + 0.5) / n, (row + 0.5) / n), 1.0))
    img.pixels = pixels
    img.filepath_raw = os.path.join(work, name + ".png")
    img.file_format = "PNG"
    img.save()
    return img


def checker(x, y):
    on = (int(x * 8) + int(y * 8)) % 2
    return (0.85, 0.8, 0.7) if on else (0.35, 0.4, 0.55)  # sRGB values, as a painter picks


def domes(x, y):
    # Height h = sqrt(r0^2 - r^2) capped domes on a 6 x 6 grid; the normal (-dh/dx, -dh/dy,
    # 1) in tangent space, x along u and y up the image (glTF's OpenGL convention).
    cx, cy = (x * 6) % 1 - 0.5, (y * 6) % 1 - 0.5
    r2, r0 = cx * cx + cy * cy, 0.42
    if r2 >= r0 * r0 * 0.64:  # outside the cap: flat
        return (0.5, 0.5, 1.0)
    h = math.sqrt(r0 * r0 - r2)
    nx, ny, nz = cx / h, cy / h, 1.0
    length = math.sqrt(nx * nx + ny * ny + nz * nz)
    return tuple(0.5 + 0.5 * c / length for c in (nx, ny, nz))


def quads(name, faces, mat):
    # faces: corner lists, each counter-clockwise seen from the side it faces; UVs (0,0),
    # (1,0), (1,1), (0,1) at the four corners.
    verts, polys = [], []
    for f in faces:
        polys.append(tuple(range(len(verts), len(verts) + 4)))
        verts.extend(f)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], polys)
    uv = mesh.uv_layers.new(name="UVMap")
    for poly in mesh.polygons:
        for k, loop in enumerate(poly.loop_indices):
            uv.data[loop].uv = ((0, 0), (1, 0), (1, 1), (0, 1))[k]
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def ceiling_rect(x0, x1, y0, y1):
    return [(x0, y0, 2), (x0, y1, 2), (x1, y1, 2), (x1, y0, 2)]  # faces down


def block(name, cx, cy, w, h, turn_deg, mat):
    c, s = math.cos(math.radians(turn_deg)), math.sin(math.radians(turn_deg))

    def p(x, y, z):
        return (cx + c * x - s * y, cy + s * x + c * y, z)

    a = w / 2
    faces = [
        [p(-a, -a, h), p(a, -a, h), p(a, a, h), p(-a, a, h)],  # top
        [p(-a, -a, 0), p(a, -a, 0), p(a, -a, h), p(-a, -a, h)],  # front (-y)
        [p(a, -a, 0), p(a, a, 0), p(a, a, h), p(a, -a, h)],  # +x
        [p(a, a, 0), p(-a, a, 0), p(-a, a, h), p(a, a, h)],  # back (+y)
        [p(-a, a, 0), p(-a, -a, 0), p(-a, -a, h), p(-a, a, h)],  # -x
    ]
    return quads(name, faces, mat)


white = material("white", (0.73, 0.73, 0.73))
red = material("red", (0.63, 0.065, 0.05))
green = material("green", (0.14, 0.45, 0.09))
floor = material("floor", (1, 1, 1), texture=image("checker", 256, checker, "sRGB"))
wall = material("back_wall", (0.73, 0.73, 0.73),
                normal_map=image("domes", 384, domes, "Non-Color"))
lamp = material("lamp", (0, 0, 0), emission=12.0)

quads("floor", [[(-1, 0, 0), (1, 0, 0), (1, 2, 0), (-1, 2, 0)]], floor)
quads("back_wall", [[(-1, 2, 0), (1, 2, 0), (1, 2, 2), (-1, 2, 2)]], wall)
quads("left_wall", [[(-1, 0, 0), (-1, 2, 0), (-1, 2, 2), (-1, 0, 2)]], red)
quads("right_wall", [[(1, 2, 0), (1, 0, 0), (1, 0, 2), (1, 2, 2)]], green)
quads("ceiling", [ceiling_rect(-1, 1, 0, 0.75), ceiling_rect(-1, 1, 1.25, 2),
                  ceiling_rect(-1, -0.25, 0.75, 1.25), ceiling_rect(0.25, 1, 0.75, 1.25)], white)
quads("lamp", [ceiling_rect(-0.25, 0.25, 0.75, 1.25)], lamp)
block("tall_block", -0.33, 1.25, 0.6, 1.2, 18, white)
block("short_block", 0.35, 0.65, 0.6, 0.6, -17, white)

cam = bpy.data.cameras.new("camera")
cam.sensor_fit = "VERTICAL"
cam.angle = math.radians(37)
camera = bpy.data.objects.new("camera", cam)
camera.location = (0, -2.1, 1)
camera.rotation_euler = (math.radians(90), 0, 0)  # looks along +y
scene.collection.objects.link(camera)
scene.camera = camera
scene.render.resolution_x = scene.render.resolution_y = size

bpy.ops.export_scene.gltf(filepath=out, export_format="GLB", export_cameras=True,
                          export_yup=True)
print("wrote", out)
