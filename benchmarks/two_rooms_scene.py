"""Builds the two-room scenes of scripts/benchmark (suites topology and budget) and saves one as a .blend: the
native topology tests' two rooms (tests/native/topology_scenes.h) as a Blender scene.

    blender -b --factory-startup --python benchmarks/two_rooms_scene.py -- --out R.blend [--wall]

Two closed 10 x 10 x 4 m rooms side by side along x, joined by a doorway 2 m wide and 3 m high in the wall
x = 10, centred in y; thin walls (single faces sharing their vertices, so the box has no cracks), grey diffuse.
A point light hangs in room A (x < 10); the camera "Camera" stands in room B and looks back at the doorway, so
what it sees of room B is lit indirectly, partly through the doorway and partly (without indirect visibility)
through the wall: the case the paper's gates are for. A second camera, "CameraA", stands in room A and looks at
the middle wall, so a benchmark can set the lit room's level beside the other room's.

--wall makes the middle wall solid (no doorway): room B is then closed and gets no light at all, so whatever a
method puts there is light leaking through the wall.
"""
import argparse
import math
import os
import sys

import bpy
from mathutils import Vector

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tests", "blender", "scripts"))
import bl_common  # noqa: E402

SIZE = Vector((20.0, 10.0, 4.0))
DOOR_Y, DOOR_TOP = (4.0, 6.0), 3.0


def rectangle_x(x, y0, y1, z0, z1):
    return [(x, y0, z0), (x, y1, z0), (x, y1, z1), (x, y0, z1)]


def geometry(wall=False):
    """Vertices and quads: the box's six faces and the middle wall, around the doorway or (`wall`) whole.
    Corners that coincide are one vertex."""
    sx, sy, sz = SIZE
    quads = [rectangle_x(0.0, 0.0, sy, 0.0, sz), rectangle_x(sx, 0.0, sy, 0.0, sz),
             [(0, 0, 0), (sx, 0, 0), (sx, 0, sz), (0, 0, sz)], [(0, sy, 0), (sx, sy, 0), (sx, sy, sz), (0, sy, sz)],
             [(0, 0, 0), (sx, 0, 0), (sx, sy, 0), (0, sy, 0)], [(0, 0, sz), (sx, 0, sz), (sx, sy, sz), (0, sy, sz)]]
    if wall:
        quads.append(rectangle_x(10.0, 0.0, sy, 0.0, sz))
    else:
        quads += [rectangle_x(10.0, 0.0, DOOR_Y[0], 0.0, sz), rectangle_x(10.0, DOOR_Y[1], sy, 0.0, sz),
                  rectangle_x(10.0, DOOR_Y[0], DOOR_Y[1], DOOR_TOP, sz)]
    index = {}
    faces = [tuple(index.setdefault(tuple(map(float, v)), len(index)) for v in quad) for quad in quads]
    return list(index), faces


def add_camera(scene, name, location, target):
    camera_data = bpy.data.cameras.new(name)
    camera_data.angle = math.radians(70.0)
    camera = bpy.data.objects.new(name, camera_data)
    camera.location = location
    camera.rotation_euler = (Vector(target) - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    return camera


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("--width", type=int, default=512)
    parser.add_argument("--height", type=int, default=256)
    parser.add_argument("--wall", action="store_true", help="a solid middle wall, no doorway")
    args = parser.parse_args(bl_common.args())
    bl_common.clear_data()
    scene = bpy.context.scene
    verts, faces = geometry(args.wall)
    bl_common.add_mesh(scene, "Rooms", verts, faces, bl_common.diffuse_material("Walls", (0.8, 0.8, 0.8)))

    light_data = bpy.data.lights.new("Lamp", type="POINT")
    light_data.energy = 2000.0  # W
    light_data.shadow_soft_size = 0.1
    light = bpy.data.objects.new("Lamp", light_data)
    light.location = (4.0, 5.0, 3.0)
    scene.collection.objects.link(light)

    scene.camera = add_camera(scene, "Camera", (19.0, 5.0, 2.0), (10.0, 5.0, 1.0))
    # Room A's view mirrors room B's: the same wall from the other side, behind the lamp.
    add_camera(scene, "CameraA", (1.0, 5.0, 2.0), (10.0, 5.0, 1.0))
    bl_common.black_world(scene)
    bl_common.set_resolution(scene, args.width, args.height)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out), compress=False)


main()
