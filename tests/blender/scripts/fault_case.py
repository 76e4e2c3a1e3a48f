"""What a user sees when the machine fails Bounce: each failure of BOUNCE_INJECT_FAULT (egl: no EGL display,
gl-oom: GPU memory runs out, embree: Embree cannot start; native/common/fault_injection.h) turned on for one
F12-style render, then off for the next, in one Blender session.

    blender -b --factory-startup --python fault_case.py -- OUT_DIR

Prints "fault NAME: begin" and "fault NAME: end" around each failing render, so that its report lines can be
told apart, and writes OUT_DIR/faults.json: {NAME: {"error": what bpy.ops.render.render raised or null,
"after": the EXR of the render after the failure was turned off, or null}}.
"""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common as bc  # noqa: E402

FAULTS = ("egl", "gl-oom", "embree")


def build(scene):
    """A floor under a sun, seen from above: lit wherever the render works."""
    bc.add_plane(scene, 10.0, material=bc.diffuse_material("Floor", (0.8, 0.8, 0.8)), name="Floor")
    bc.add_ortho_camera(scene, (0.0, 0.0), 5.0, 8.0)
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", type="SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = (math.radians(20.0), 0.0, 0.0)
    scene.collection.objects.link(sun)


def render(scene, path):
    try:
        return bc.render_still(scene, path), None
    except RuntimeError as error:  # the engine's error report, raised by the operator
        print(f"render raised: {error}")
        return None, str(error)


def main():
    out = bc.args()[0]
    os.makedirs(out, exist_ok=True)
    bc.clear_data()
    scene = bpy.context.scene
    bc.black_world(scene)
    bc.set_resolution(scene, 32, 32)
    bc.linear_output(scene)
    bc.bounce_settings(scene, method="DIRECT", samples=2)
    build(scene)
    record = {}
    for fault in FAULTS:
        os.environ["BOUNCE_INJECT_FAULT"] = fault
        print(f"fault {fault}: begin", flush=True)
        _exr, error = render(scene, os.path.join(out, fault))
        print(f"fault {fault}: end", flush=True)
        del os.environ["BOUNCE_INJECT_FAULT"]
        after, _error = render(scene, os.path.join(out, fault + "-after"))
        record[fault] = {"error": error, "after": after if after and os.path.isfile(after) else None}
    bc.write_json(os.path.join(out, "faults.json"), record)
    print("faults done")


main()
