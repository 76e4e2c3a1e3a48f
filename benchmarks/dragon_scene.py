"""Builds the triangle-count scene of scripts/benchmark: N instanced copies of the Stanford dragon (100k
triangles each) on a floor under a sun, and saves it as a .blend.

    blender -b --factory-startup --python benchmarks/dragon_scene.py -- --out D.blend --copies 20 \
        [--instancing collection|linked] [--ply PATH]

The copies stand on a k x k grid (k = ceil(sqrt(N))) that always covers the same square, each scaled by 1/k,
so the frame covers about the same pixels at every count and the frame time follows the triangle count.
Instancing keeps one mesh in memory however many copies there are, which is the path the core's instancing
(geometry uploaded once per mesh) has to handle: `collection` makes collection-instance empties,
`linked` makes linked duplicates (objects sharing one mesh datablock).
Runs on Blender 3.4 and later (the C++ PLY importer wm.ply_import arrived in 3.6; the Python one left in 4.0).
"""
import argparse
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tests", "blender", "scripts"))
import bl_common  # noqa: E402

DEFAULT_PLY = os.path.join(REPO, "..", "shared", "scenes", "stanford_dragon", "dragon_100k.ply")
FIELD = 4.0  # side of the square the copies share, in metres


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("--copies", type=int, required=True)
    parser.add_argument("--instancing", choices=("collection", "linked"), default="collection")
    parser.add_argument("--ply", default=os.environ.get("BOUNCE_DRAGON_PLY", DEFAULT_PLY))
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=720)
    return parser.parse_args(bl_common.args())


def import_dragon(path):
    """The dragon standing up (the PLY is y-up), one unit across its longest horizontal side, feet at z=0."""
    before = set(bpy.data.objects)
    if bpy.app.version >= (3, 6, 0):  # hasattr() cannot tell: bpy.ops answers every name
        bpy.ops.wm.ply_import(filepath=path)
    else:
        bpy.ops.import_mesh.ply(filepath=path)
    dragon = next(ob for ob in bpy.data.objects if ob not in before)
    mesh = dragon.data
    mesh.transform(dragon.matrix_world)
    dragon.matrix_world.identity()
    # y-up to z-up, then normalise size and put the feet on the floor, all baked into the mesh so every
    # instance carries only its grid placement.
    mesh.transform(Matrix.Rotation(math.pi / 2, 4, "X"))
    xs, ys, zs = ([v.co[i] for v in mesh.vertices] for i in range(3))
    scale = 1.0 / max(max(xs) - min(xs), max(ys) - min(ys))
    centre = Vector(((max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2, min(zs)))
    mesh.transform(Matrix.Scale(scale, 4) @ Matrix.Translation(-centre))
    mesh.materials.append(bl_common.diffuse_material("Dragon", (0.8, 0.75, 0.6)))
    dragon.name = "Dragon"
    return dragon


def triangle_count(mesh):
    return sum(len(p.vertices) - 2 for p in mesh.polygons)


def place_copies(scene, dragon, copies, instancing):
    k = math.ceil(math.sqrt(copies))
    cell = FIELD / k
    scale = 0.8 * cell
    positions = [Vector(((i % k + 0.5) * cell - FIELD / 2, (i // k + 0.5) * cell - FIELD / 2, 0.0))
                 for i in range(copies)]
    if instancing == "collection":
        source = bpy.data.collections.new("DragonSource")
        source.objects.link(dragon)
        # The source collection is not linked to the scene: only its instances render.
        for i, position in enumerate(positions):
            empty = bpy.data.objects.new(f"Dragon.{i:03d}", None)
            empty.instance_type = "COLLECTION"
            empty.instance_collection = source
            empty.location = position
            empty.scale = (scale, scale, scale)
            scene.collection.objects.link(empty)
    else:
        for i, position in enumerate(positions):
            ob = dragon if i == 0 else bpy.data.objects.new(f"Dragon.{i:03d}", dragon.data)
            if i:
                scene.collection.objects.link(ob)
            ob.location = position
            ob.scale = (scale, scale, scale)
    return k


def main():
    args = parse_args()
    bl_common.clear_data()
    scene = bpy.context.scene
    dragon = import_dragon(args.ply)
    for collection in list(dragon.users_collection):
        collection.objects.unlink(dragon)
    if args.instancing == "linked":
        scene.collection.objects.link(dragon)
    place_copies(scene, dragon, args.copies, args.instancing)

    floor = bl_common.add_plane(scene, FIELD * 1.5, z=0.0,
                                material=bl_common.diffuse_material("Floor", (0.5, 0.5, 0.5)), name="Floor")
    sun_data = bpy.data.lights.new("Sun", type="SUN")
    sun_data.energy = 3.0
    sun_data.angle = math.radians(1.0)
    sun = bpy.data.objects.new("Sun", sun_data)
    scene.collection.objects.link(sun)
    sun.rotation_euler = Vector((0.4, -0.6, -1.0)).normalized().to_track_quat("-Z", "Y").to_euler()

    camera_data = bpy.data.cameras.new("Camera")
    camera_data.angle = math.radians(50.0)
    camera = bpy.data.objects.new("Camera", camera_data)
    scene.collection.objects.link(camera)
    camera.location = (0.0, -FIELD * 1.15, FIELD * 0.75)
    camera.rotation_euler = (-camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.camera = camera
    bl_common.black_world(scene)
    bl_common.set_resolution(scene, args.width, args.height)

    triangles = triangle_count(dragon.data) * args.copies + triangle_count(floor.data)
    print(f"dragons: {args.copies} copies ({args.instancing}), {triangles} triangles")
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out), compress=False)


main()
