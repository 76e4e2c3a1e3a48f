"""Analytic light checks, Blender side: a big Lambertian plane (Diffuse BSDF, albedo 0.8, roughness 0) seen
straight down by an orthographic camera, lit by one light per case; each case is rendered with Bounce into
OUT/<case>.exr (multilayer, 32-bit) and OUT/lights.json records every light's matrix_world as Blender built it.

    blender -b --factory-startup --python lights_scene.py -- CASES.json OUT
"""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common as bc  # noqa: E402


def make_light(scene, case):
    kind = case["type"]
    light = bpy.data.lights.new(case["name"], type=kind)
    light.color = tuple(case.get("color", (1.0, 1.0, 1.0)))
    light.energy = case["energy"]
    if kind in {"POINT", "SPOT"}:
        light.shadow_soft_size = case.get("radius", 0.0)
    if kind == "SPOT":
        light.spot_size = math.radians(case["spot_size_deg"])
        light.spot_blend = case["spot_blend"]
        light.show_cone = False
    if kind == "SUN":
        light.angle = math.radians(case["angle_deg"])
    if kind == "AREA":
        light.shape = case["shape"]
        light.size = case["size"]
        if case["shape"] in {"RECTANGLE", "ELLIPSE"}:
            light.size_y = case["size_y"]
    ob = bpy.data.objects.new(case["name"], light)
    ob.location = case["location"]
    ob.rotation_euler = [math.radians(a) for a in case.get("rotation_deg", (0.0, 0.0, 0.0))]
    ob.scale = case.get("scale", (1.0, 1.0, 1.0))
    scene.collection.objects.link(ob)
    return ob


def main():
    cases_path, out = bc.args()[:2]
    spec = bc.load_json(cases_path)
    os.makedirs(out, exist_ok=True)
    bc.clear_data()
    scene = bpy.context.scene
    plane_mat = bc.diffuse_material("Plane", (spec["albedo"],) * 3, roughness=0.0)
    bc.add_plane(scene, spec["plane_size"], material=plane_mat)
    bc.add_ortho_camera(scene, spec["center"], spec["camera_height"], spec["ortho_scale"])
    bc.black_world(scene)
    bc.set_resolution(scene, spec["resolution"], spec["resolution"])
    bc.linear_output(scene)
    bc.bounce_settings(scene, **spec["bounce"])

    record = {"blender": list(bc.version()), "cases": {}}
    for case in spec["cases"]:
        ob = make_light(scene, case)
        if spec.get("engine") == "CYCLES":  # the same scene through Cycles: checks the closed forms themselves
            import render
            render.cycles_oracle(scene, spec.get("cycles_samples", 256), 0)
        else:
            bc.bounce_settings(scene, **dict(spec["bounce"], **case.get("bounce", {})))
        bpy.context.view_layer.update()
        path = bc.render_still(scene, os.path.join(out, case["name"]))
        record["cases"][case["name"]] = {"matrix_world": [list(row) for row in ob.matrix_world], "exr": path}
        bpy.data.objects.remove(ob, do_unlink=True)
        print(f"rendered light case {case['name']} -> {path}")
    bc.write_json(os.path.join(out, "lights.json"), record)


main()
