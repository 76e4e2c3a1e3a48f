"""Runs inside Blender for scripts/benchmark --suite ssvp-temporal: SSVP's temporal stability as the viewport sees
it, one native engine rendering a sequence and keeping its k-means clusters from frame to frame (Sec. III-C).

    scripts/blender -b SCENE.blend --python benchmarks/ssvp_temporal.py -- CONFIG.json

CONFIG: {"records": path (one JSON line per frame), "width", "height", "frames", "bounce": {setting: value},
         "orbit_degrees", "light_degrees"}
Motions, each rendered with clusters seeded from the last frame and seeded afresh every frame:
  orbit - the camera turns about the scene's centre, the light stands still. VPLs come from the light's view, so
          nothing real changes on the surfaces: a fixed probe view, rendered by the same engine after every frame,
          should not change at all. Its frame-to-frame change is flicker.
  light - the sun turns slowly, the camera stands still: the Indirect pass changes a little by right, and flicker
          adds to that.
The change of frame f: mean |I_f - I_(f-1)| / mean I_(f-1) over the pixels that see geometry, and over the
'static region' of pixels that no direct light reaches in either frame (lit only indirectly).
"""
import json
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_render import NativeSession, apply_settings, bl_common  # noqa: E402


def relative_changes(previous, current, direct_previous, direct_current, covered):
    """(change over the covered pixels, change over the pixels without direct light) of the Indirect pass."""
    out = []
    dark = covered & (direct_previous.max(axis=-1) <= 1e-6) & (direct_current.max(axis=-1) <= 1e-6)
    for mask in (covered, dark):
        reference = previous[mask].mean() if mask.any() else 0.0
        out.append(float(np.abs(current[mask] - previous[mask]).mean() / reference) if reference > 0 else None)
    return out, int(dark.sum())


def render(session, scene, camera_object, frame):
    seconds = session.render(scene, camera_object, frame)
    native = session.native
    return {"indirect": session.read(native.AOV_INDIRECT), "direct": session.read(native.AOV_DIRECT),
            "covered": session.read(native.AOV_ALBEDO).max(axis=-1) > 0, "seconds": seconds,
            "clusters": session.info.cluster_count}


def scene_centre(scene):
    points = [o.matrix_world @ Vector(corner) for o in scene.objects if o.type == "MESH" for corner in o.bound_box]
    lo = [min(p[i] for p in points) for i in range(3)]
    hi = [max(p[i] for p in points) for i in range(3)]
    return Matrix.Translation([(a + b) / 2 for a, b in zip(lo, hi)])


def run(config, scene, motion, temporal, records):
    apply_settings(scene.bounce, dict(config.get("bounce", {}), method="SSVP", ssvp_temporal_seeding=temporal))
    camera, sun = scene.camera, next(o for o in scene.objects if o.type == "LIGHT" and o.data.type == "SUN")
    camera_start, sun_start = camera.matrix_world.copy(), sun.matrix_world.copy()
    pivot = scene_centre(scene)
    probe = camera.copy()  # the fixed view the orbit is judged in
    scene.collection.objects.link(probe)
    session = NativeSession()
    previous = None
    try:
        for frame in range(config["frames"]):
            t = frame / max(config["frames"] - 1, 1)
            if motion == "orbit":
                turn = Matrix.Rotation(math.radians(config["orbit_degrees"] * t), 4, "Z")
                camera.matrix_world = pivot @ turn @ pivot.inverted() @ camera_start
                shown = render(session, scene, camera, frame)
                judged = render(session, scene, probe, frame)
                seconds = shown["seconds"]
            else:
                turn = Matrix.Rotation(math.radians(config["light_degrees"] * t), 4, "X")
                sun.matrix_world = Matrix.Translation(sun_start.translation) @ turn @ sun_start.to_3x3().to_4x4()
                judged = render(session, scene, camera, frame)
                seconds = judged["seconds"]
            record = {"motion": motion, "seeding": "last frame" if temporal else "fresh", "frame": frame,
                      "seconds": seconds, "clusters": judged["clusters"],
                      "indirect_mean": float(judged["indirect"][judged["covered"]].mean())}
            if previous is not None:
                (record["change"], record["change_static"]), record["static_pixels"] = relative_changes(
                    previous["indirect"], judged["indirect"], previous["direct"], judged["direct"],
                    judged["covered"] & previous["covered"])
            previous = judged
            records.write(json.dumps(record) + "\n")
            records.flush()
        print(f"temporal: {motion}, seeding {record['seeding']}: {config['frames']} frames", flush=True)
    finally:
        session.close()
        camera.matrix_world, sun.matrix_world = camera_start, sun_start
        bpy.data.objects.remove(probe)


def main():
    config = bl_common.load_json(bl_common.args()[0])
    scene = bpy.context.scene
    bl_common.set_resolution(scene, config["width"], config["height"])
    with open(config["records"], "a") as records:
        for motion in ("orbit", "light"):
            for temporal in (True, False):
                run(config, scene, motion, temporal, records)


main()
