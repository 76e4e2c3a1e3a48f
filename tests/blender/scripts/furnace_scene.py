"""The furnace of the Forward Light Cuts issue: a closed diffuse sphere (radius 2, albedo 0.8, Diffuse BSDF) with a
1000 W point light at its centre, seen from the centre by a perspective camera; rendered with Bounce (FLC) once
per sample count into OUT/furnace-<samples>.exr, and OUT/furnace.json lists them.

    blender -b --factory-startup --python furnace_scene.py -- SPEC.json OUT

SPEC: {"resolution": int, "samples": [int, ...], "bounce": {setting: value}}
"""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common as bc  # noqa: E402

RADIUS = 2.0
SEGMENTS, RINGS = 128, 64  # flat facets sit inside the sphere: the wall's irradiance is 0.05 % above 1/R^2


def sphere(scene, material):
    verts = [(0.0, 0.0, RADIUS), (0.0, 0.0, -RADIUS)]
    for j in range(1, RINGS):
        theta = math.pi * j / RINGS
        for i in range(SEGMENTS):
            phi = 2.0 * math.pi * i / SEGMENTS
            verts.append((RADIUS * math.sin(theta) * math.cos(phi), RADIUS * math.sin(theta) * math.sin(phi),
                          RADIUS * math.cos(theta)))
    ring = lambda j, i: 2 + (j - 1) * SEGMENTS + i % SEGMENTS  # noqa: E731
    faces = [(0, ring(1, i), ring(1, i + 1)) for i in range(SEGMENTS)]
    faces += [(1, ring(RINGS - 1, i + 1), ring(RINGS - 1, i)) for i in range(SEGMENTS)]
    for j in range(1, RINGS - 1):
        faces += [(ring(j, i), ring(j + 1, i), ring(j + 1, i + 1), ring(j, i + 1)) for i in range(SEGMENTS)]
    return bc.add_mesh(scene, "Furnace", verts, faces, material=material)


def main():
    spec_path, out = bc.args()[:2]
    spec = bc.load_json(spec_path)
    os.makedirs(out, exist_ok=True)
    bc.clear_data()
    scene = bpy.context.scene
    sphere(scene, bc.diffuse_material("Wall", (0.8, 0.8, 0.8), roughness=0.0))
    light = bpy.data.lights.new("Centre", type="POINT")
    light.energy = 1000.0
    light.shadow_soft_size = 0.0
    light_object = bpy.data.objects.new("Centre", light)
    scene.collection.objects.link(light_object)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.rotation_euler = (math.radians(60.0), 0.0, math.radians(30.0))
    scene.collection.objects.link(camera)
    scene.camera = camera
    bc.black_world(scene)
    bc.set_resolution(scene, spec["resolution"], spec["resolution"])
    bc.linear_output(scene)
    renders = {}
    for samples in spec["samples"]:
        bc.bounce_settings(scene, **dict(spec["bounce"], samples=samples))
        renders[samples] = bc.render_still(scene, os.path.join(out, f"furnace-{samples}"))
    bc.write_json(os.path.join(out, "furnace.json"), {"blender": list(bc.version()), "exr": renders})


main()
