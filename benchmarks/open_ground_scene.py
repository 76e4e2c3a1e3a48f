"""Builds the open-ground scene of scripts/benchmark (suites budget and budget-time) and saves it as a .blend.

    blender -b --factory-startup --python benchmarks/open_ground_scene.py -- --out R.blend

A grey ground (albedo 0.5, 200 m square) under one sun at 40 degrees elevation, a black world, and a few boxes
and a sphere (albedo 0.6) standing on it, seen from a person's height: nearly every path from what the camera
sees escapes to the sky, so the bounces are a few per cent of the image (the ground's light on the objects' shaded
sides, the objects' on the ground near them) and an engine that simulates them spends its time on little.
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

# (centre, half size) of the boxes standing on the ground
BOXES = [((0.0, 0.0, 1.0), (1.0, 1.0, 1.0)), ((3.5, 2.0, 0.5), (0.5, 1.5, 0.5)), ((-3.0, 3.0, 2.0), (0.6, 0.6, 2.0))]
SPHERE = ((1.5, -3.0, 1.2), 1.2)


def box(centre, half):
    c, h = Vector(centre), Vector(half)
    verts = [tuple(c + Vector((sx * h.x, sy * h.y, sz * h.z))) for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return verts, faces


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True)
    args = parser.parse_args(bl_common.args())
    bl_common.clear_data()
    scene = bpy.context.scene
    bl_common.add_plane(scene, 200.0, material=bl_common.diffuse_material("Ground", (0.5, 0.5, 0.5)), name="Ground")
    objects = bl_common.diffuse_material("Objects", (0.6, 0.6, 0.6))
    for i, (centre, half) in enumerate(BOXES):
        verts, faces = box(centre, half)
        bl_common.add_mesh(scene, f"Box {i}", verts, faces, objects)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=SPHERE[1], location=SPHERE[0])
    sphere = bpy.context.active_object
    sphere.data.materials.append(objects)
    bpy.ops.object.shade_smooth()

    sun_data = bpy.data.lights.new("Sun", type="SUN")
    sun_data.energy = 3.0  # W/m^2
    sun_data.angle = math.radians(1.0)
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.rotation_euler = (math.radians(50.0), 0.0, math.radians(-30.0))  # 40 degrees above the horizon
    scene.collection.objects.link(sun)

    camera_data = bpy.data.cameras.new("Camera")
    camera_data.angle = math.radians(60.0)
    camera = bpy.data.objects.new("Camera", camera_data)
    camera.location = (-9.0, -11.0, 4.0)
    camera.rotation_euler = (Vector((0.5, 0.0, 0.8)) - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    scene.camera = camera
    bl_common.black_world(scene)
    bl_common.set_resolution(scene, 480, 270)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out), compress=False)


main()
