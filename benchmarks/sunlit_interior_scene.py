"""Builds the sunlit-interior scene of scripts/benchmark --suite budget and saves it as a .blend: a furnished room
lit only by a sun shining through a window with blinds, so that most of what the camera sees is lit indirectly.

    blender -b --factory-startup --python benchmarks/sunlit_interior_scene.py -- --out S.blend

A 6 x 5 x 2.8 m room (inside: x 0..6, y 0..5, z 0..2.8) with walls, floor and ceiling 0.2 m thick (closed boxes:
no cracks for light to leak through). The south wall (y = 0) has a window 2 m wide (x 1.5..3.5) from 0.9 to 2.2 m
up, closed by eleven horizontal slats 3 cm thick and 8 cm deep, 12 cm apart, so that the sun (5 W/m^2, 0.5 deg,
40 deg above the horizon, 25 deg east of north-bound) lays thin stripes on the floor and the rug, and nowhere
else. Outside, a 14 x 14 m ground plane. Furniture of boxes: a table and four chairs (one chair mesh, four
objects sharing it), a sofa, a bookshelf with books, a sideboard, a rug whose colour is a checker image made here
and packed into the .blend (its Image Texture feeds the Diffuse BSDF). Every material is one Diffuse BSDF of
roughness 0 with albedos between 0.2 and 0.8; the world is black. The camera stands by the window's wall and
looks into the shaded part of the room (the sofa, the shelf, the back wall), the sunlit stripes in the lower
left of the picture. Nothing here was tuned to suit a method. 480 x 270 by default.
"""
import argparse
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Vector

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tests", "blender", "scripts"))
import bl_common  # noqa: E402

ROOM = Vector((6.0, 5.0, 2.8))
WALL = 0.2
WINDOW_X, WINDOW_Z = (1.5, 3.5), (0.9, 2.2)
SLATS, SLAT_THICKNESS, SLAT_DEPTH = 11, 0.03, 0.08
SUN_ELEVATION, SUN_AZIMUTH = math.radians(40.0), math.radians(25.0)  # azimuth: from +y towards +x
SUN_STRENGTH, SUN_ANGLE = 5.0, math.radians(0.5)  # W/m^2, as Sponza's sun


class Boxes:
    """Axis-aligned boxes gathered into one mesh; every box is closed, its quads facing out."""

    def __init__(self):
        self.verts, self.faces = [], []

    def add(self, lo, hi):
        base = len(self.verts)
        corners = [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
        self.verts += corners
        centre = (Vector(lo) + Vector(hi)) / 2
        for axis in range(3):
            for side in (0, 1):
                quad = [i for i in range(8) if (i >> (2 - axis)) & 1 == side]
                quad[2], quad[3] = quad[3], quad[2]  # bit order -> a loop around the face
                a, b, c = (Vector(corners[i]) for i in quad[:3])
                if (b - a).cross(c - a).dot(a - centre) < 0:
                    quad.reverse()
                self.faces.append(tuple(base + i for i in quad))
        return self

    def mesh(self, name):
        me = bpy.data.meshes.new(name)
        me.from_pydata(self.verts, [], self.faces)
        me.update()
        return me


def add_object(scene, name, mesh, material, location=(0.0, 0.0, 0.0), rotation_z=0.0):
    if material is not None and not mesh.materials:
        mesh.materials.append(material)
    ob = bpy.data.objects.new(name, mesh)
    ob.location = location
    ob.rotation_euler = (0.0, 0.0, rotation_z)
    scene.collection.objects.link(ob)
    return ob


def shell():
    """Floor, ceiling and walls, the south wall around the window opening."""
    (sx, sy, sz), w = ROOM, WALL
    (x0, x1), (z0, z1) = WINDOW_X, WINDOW_Z
    boxes = Boxes()
    boxes.add((-w, -w, -w), (sx + w, sy + w, 0.0))            # floor slab
    boxes.add((-w, -w, sz), (sx + w, sy + w, sz + w))         # ceiling slab
    boxes.add((-w, -w, 0.0), (0.0, sy + w, sz))               # west
    boxes.add((sx, -w, 0.0), (sx + w, sy + w, sz))            # east
    boxes.add((0.0, sy, 0.0), (sx, sy + w, sz))               # north
    boxes.add((0.0, -w, 0.0), (x0, 0.0, sz))                  # south, left of the window
    boxes.add((x1, -w, 0.0), (sx, 0.0, sz))                   # south, right of the window
    boxes.add((x0, -w, 0.0), (x1, 0.0, z0))                   # under the window (the sill)
    boxes.add((x0, -w, z1), (x1, 0.0, sz))                    # over the window (the lintel)
    return boxes


def slats():
    """The blinds: horizontal slats across the opening, in the middle of the wall's depth."""
    boxes = Boxes()
    (x0, x1), (z0, z1) = WINDOW_X, WINDOW_Z
    pitch = (z1 - z0) / SLATS
    y = -WALL / 2
    for i in range(SLATS):
        z = z0 + (i + 0.5) * pitch
        boxes.add((x0, y - SLAT_DEPTH / 2, z - SLAT_THICKNESS / 2), (x1, y + SLAT_DEPTH / 2, z + SLAT_THICKNESS / 2))
    return boxes


def table(cx, cy, length, depth, height=0.75, top=0.04, leg=0.06):
    boxes = Boxes().add((cx - length / 2, cy - depth / 2, height - top), (cx + length / 2, cy + depth / 2, height))
    for sx in (-1, 1):
        for sy in (-1, 1):
            x, y = cx + sx * (length / 2 - 0.08), cy + sy * (depth / 2 - 0.08)
            boxes.add((x - leg / 2, y - leg / 2, 0.0), (x + leg / 2, y + leg / 2, height - top))
    return boxes


def chair():
    """A chair around its own origin (seat centre on the floor), facing +y: the back stands at -y."""
    size, seat, leg = 0.44, 0.45, 0.04
    h = size / 2
    boxes = Boxes().add((-h, -h, seat - 0.04), (h, h, seat))
    for x in (-h + leg / 2, h - leg / 2):
        for y in (-h + leg / 2, h - leg / 2):
            boxes.add((x - leg / 2, y - leg / 2, 0.0), (x + leg / 2, y + leg / 2, seat - 0.04))
    boxes.add((-h, -h, seat), (h, -h + 0.04, 0.92))  # back
    return boxes


def sofa(x0, y0, x1, y1):
    """Along the west wall, facing +x: base, back, two arms, three seat cushions."""
    boxes = Boxes()
    boxes.add((x0, y0, 0.05), (x1, y1, 0.25))                         # base
    boxes.add((x0, y0, 0.25), (x0 + 0.2, y1, 0.85))                   # back
    boxes.add((x0 + 0.2, y0, 0.25), (x1, y0 + 0.18, 0.6))             # arms
    boxes.add((x0 + 0.2, y1 - 0.18, 0.25), (x1, y1, 0.6))
    cushion = (y1 - y0 - 0.36) / 3
    for i in range(3):
        y = y0 + 0.18 + i * cushion
        boxes.add((x0 + 0.2, y + 0.01, 0.25), (x1 - 0.02, y + cushion - 0.01, 0.42))
    for y in (y0 + 0.02, y1 - 0.2):                                   # feet
        for x in (x0 + 0.05, x1 - 0.1):
            boxes.add((x, y, 0.0), (x + 0.05, y + 0.18, 0.05))
    return boxes


def shelf(x0, x1, y0, y1, height=2.0, boards=5, board=0.03):
    boxes = Boxes()
    boxes.add((x0, y0, 0.0), (x0 + board, y1, height))
    boxes.add((x1 - board, y0, 0.0), (x1, y1, height))
    for i in range(boards):
        z = i * (height - board) / (boards - 1)
        boxes.add((x0 + board, y0, z), (x1 - board, y1, z + board))
    return boxes


def books(x0, x1, y0, y1, height=2.0, boards=5, board=0.03, seed=3):
    """Upright books of four colours on each board but the top one: one mesh per colour."""
    rng = np.random.default_rng(seed)
    groups = [Boxes() for _ in range(4)]
    for i in range(boards - 1):
        z = i * (height - board) / (boards - 1) + board
        x = x0 + board + 0.02
        while True:
            width, tall = rng.uniform(0.03, 0.07), rng.uniform(0.2, 0.32)
            if x + width > x1 - board - 0.02:
                break
            if rng.uniform() > 0.15:  # gaps between some books
                groups[int(rng.integers(4))].add((x, y0 + rng.uniform(0.0, 0.04), z), (x + width, y1 - 0.01, z + tall))
            x += width + 0.004
    return groups


def checker_image(name, size=256, tiles=8):
    """A byte (sRGB) checker image, packed so the .blend needs no file beside it. Its two colours decode to the
    linear albedos (0.68, 0.58, 0.35) and (0.46, 0.20, 0.19)."""
    image = bpy.data.images.new(name, size, size, alpha=False)
    light, dark = np.array([215, 200, 160, 255]) / 255, np.array([180, 125, 120, 255]) / 255
    cell = np.arange(size) * tiles // size
    pattern = ((cell[:, None] + cell[None, :]) % 2).astype(bool)
    pixels = np.where(pattern[..., None], dark, light).astype(np.float32)
    image.pixels.foreach_set(pixels.ravel())
    image.pack()
    return image


def textured_material(name, image):
    material = bl_common.diffuse_material(name, (0.8, 0.8, 0.8))
    nodes = material.node_tree.nodes
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    diffuse = next(n for n in nodes if n.type == "BSDF_DIFFUSE")
    material.node_tree.links.new(texture.outputs["Color"], diffuse.inputs["Color"])
    return material


def planar_uvs(mesh, lo, hi):
    """UVs from x and y over the box lo..hi (the rug's top shows the whole image once)."""
    layer = mesh.uv_layers.new(name="UVMap")
    for loop in mesh.loops:
        co = mesh.vertices[loop.vertex_index].co
        layer.data[loop.index].uv = ((co.x - lo[0]) / (hi[0] - lo[0]), (co.y - lo[1]) / (hi[1] - lo[1]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("--width", type=int, default=480)
    parser.add_argument("--height", type=int, default=270)
    args = parser.parse_args(bl_common.args())
    bl_common.clear_data()
    scene = bpy.context.scene
    material = bl_common.diffuse_material
    walls = material("Plaster", (0.7, 0.68, 0.62))
    wood = material("Oak", (0.45, 0.32, 0.2))
    dark_wood = material("Walnut", (0.3, 0.22, 0.2))
    fabric = material("Fabric", (0.2, 0.3, 0.5))
    painted = material("Painted", (0.75, 0.75, 0.72))
    lawn = material("Lawn", (0.22, 0.3, 0.2))
    book_colours = [material(f"Book{i}", c) for i, c in enumerate(
        [(0.6, 0.2, 0.2), (0.2, 0.4, 0.25), (0.25, 0.3, 0.6), (0.7, 0.6, 0.3)])]
    rug_texture = textured_material("Rug", checker_image("RugChecker"))

    add_object(scene, "Shell", shell().mesh("Shell"), walls)
    add_object(scene, "Blinds", slats().mesh("Blinds"), painted)
    half = 7.0
    centre = ROOM / 2
    ground = bl_common.add_mesh(scene, "Ground", [(centre.x - half, centre.y - half, -0.05),
                                                  (centre.x + half, centre.y - half, -0.05),
                                                  (centre.x + half, centre.y + half, -0.05),
                                                  (centre.x - half, centre.y + half, -0.05)], [(0, 1, 2, 3)], lawn)

    rug_lo, rug_hi = (1.3, 1.5, 0.0), (3.6, 3.6, 0.01)
    rug = Boxes().add(rug_lo, rug_hi).mesh("Rug")
    planar_uvs(rug, rug_lo, rug_hi)
    add_object(scene, "Rug", rug, rug_texture)
    add_object(scene, "Table", table(4.6, 3.4, 1.4, 0.8).mesh("Table"), dark_wood)
    chair_mesh = chair().mesh("Chair")  # one mesh, four objects: the chairs are instances
    for i, (x, y, turn) in enumerate(((4.25, 2.75, 0.0), (4.95, 2.75, 0.0), (4.25, 4.05, math.pi),
                                      (4.95, 4.05, math.pi))):
        add_object(scene, f"Chair.{i}", chair_mesh, wood, location=(x, y, 0.0), rotation_z=turn)
    add_object(scene, "Sofa", sofa(0.05, 1.4, 0.95, 3.7).mesh("Sofa"), fabric)
    shelf_box = (1.6, 3.1, 4.62, 4.98)
    add_object(scene, "Shelf", shelf(*shelf_box).mesh("Shelf"), wood)
    for i, (group, colour) in enumerate(zip(books(*shelf_box), book_colours)):
        add_object(scene, f"Books.{i}", group.mesh(f"Books.{i}"), colour)
    sideboard = Boxes().add((5.55, 0.6, 0.1), (5.98, 2.2, 0.8))
    for y in (0.65, 2.1):
        sideboard.add((5.6, y, 0.0), (5.65, y + 0.05, 0.1))
        sideboard.add((5.88, y, 0.0), (5.93, y + 0.05, 0.1))
    add_object(scene, "Sideboard", sideboard.mesh("Sideboard"), painted)
    add_object(scene, "Picture", Boxes().add((0.0, 2.0, 1.3), (0.03, 3.1, 2.0)).mesh("Picture"), book_colours[2])

    sun_data = bpy.data.lights.new("Sun", type="SUN")
    sun_data.energy = SUN_STRENGTH
    sun_data.angle = SUN_ANGLE
    sun = bpy.data.objects.new("Sun", sun_data)
    direction = Vector((math.sin(SUN_AZIMUTH) * math.cos(SUN_ELEVATION),
                        math.cos(SUN_AZIMUTH) * math.cos(SUN_ELEVATION), -math.sin(SUN_ELEVATION)))
    sun.location = centre - 10.0 * direction  # irrelevant for a sun; visible in the viewport
    sun.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()  # light travels along local -Z
    scene.collection.objects.link(sun)

    camera_data = bpy.data.cameras.new("Camera")
    camera_data.angle = math.radians(75.0)
    camera_data.clip_start = 0.05
    camera = bpy.data.objects.new("Camera", camera_data)
    camera.location = (5.6, 0.35, 1.55)
    camera.rotation_euler = (Vector((1.6, 4.0, 0.75)) - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    scene.camera = camera
    bl_common.black_world(scene)
    bl_common.set_resolution(scene, args.width, args.height)
    triangles = sum(len(p.vertices) - 2 for ob in scene.objects if ob.type == "MESH" for p in ob.data.polygons)
    print(f"sunlit interior: {triangles} triangles, ground {ground.name}, sun direction "
          f"{tuple(round(c, 3) for c in direction)}")
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out), compress=False)


main()
