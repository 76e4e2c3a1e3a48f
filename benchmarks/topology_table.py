"""Runs inside Blender for scripts/benchmark --suite topology: the topology method (Noel and Biri 2014) on the open
scene, in one native engine, so the process-wide topology cache behaves as in a Blender session.

    scripts/blender -b SCENE.blend --python benchmarks/topology_table.py -- CONFIG.json

CONFIG: {"records": path (JSON lines), "images": folder, "width", "height", "bounce": {setting: value} (all parts),
         "resolutions": [grid resolutions whose precomputation is timed],
         "accuracy": {"topology_resolution", "topology_vpls"},
         "preview": {"width", "height", "vpls": [...], "repeats"}}
Records, by "part":
  precompute - the first render at each grid resolution builds the topology: the time of each stage (Sec. IV).
  accuracy   - Table II: one render per indirect visibility (shadow rays, none, clusters and gates) with the same
               VPLs (same seed, count and bounces); mean squared error of Combined against the shadow-ray render
               for direct light only (its Direct pass), no visibility and the method, in linear radiance and in
               8-bit sRGB units (the paper's). The images go to IMAGES/<blend name>-table2.npz for the report's picture.
  preview    - the render time of one sample with the topology cached, per VPL count: what a viewport restart costs.
"""
import json
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_render import NativeSession, apply_settings, bl_common  # noqa: E402
from display import srgb  # noqa: E402

COLUMNS = ("direct only", "no visibility", "clusters and gates")


def srgb8(linear):
    """Blender's Standard view in 8-bit units (0..255, kept as floats)."""
    return 255.0 * srgb(linear)


def stage_columns(info, prefix=""):
    """The frame's stage times (CPU wall time: the method runs on the CPU) as '<prefix><stage> ms' columns."""
    return {f"{prefix}{name} ms": cpu for name, _gpu, cpu in info.stage_list()}


def precompute(session, scene, config, write):
    for resolution in config["resolutions"]:
        apply_settings(scene.bounce, dict(config["bounce"], topology_resolution=resolution, topology_vpls=64))
        builds = session.engine.topology_info().builds
        seconds = session.render(scene, scene.camera)
        topology = session.engine.topology_info()
        record = {"part": "precompute", "topology_resolution": resolution, "built": topology.builds > builds,
                  "grid": "x".join(str(d) for d in topology.grid), "skeleton_nodes": topology.skeleton_nodes,
                  "segmented_nodes": topology.segmented_nodes, "clusters": topology.clusters,
                  "gates": topology.gates, "render_seconds": seconds,
                  **{f"{name} s": ms / 1e3 for name, ms in topology.stage_list()}}
        record["precomputation s"] = sum(ms for _name, ms in topology.stage_list()) / 1e3
        write(record)
        print(f"benchmark: precomputation at {resolution}: {topology.summary()}", flush=True)


def accuracy(session, scene, config, write):
    native = session.native
    renders = {}
    for visibility in ("SHADOW_RAYS", "NONE", "CLUSTERS"):
        apply_settings(scene.bounce, dict(config["bounce"], **config["accuracy"], topology_visibility=visibility))
        seconds = session.render(scene, scene.camera)
        renders[visibility] = {"combined": session.read(native.AOV_COMBINED),
                               "direct": session.read(native.AOV_DIRECT), "seconds": seconds,
                               "vpls": session.info.vpl_count}
        print(f"benchmark: accuracy, indirect visibility {visibility}: {seconds:.2f} s", flush=True)
    reference = renders["SHADOW_RAYS"]["combined"]
    images = {"direct only": renders["SHADOW_RAYS"]["direct"], "no visibility": renders["NONE"]["combined"],
              "clusters and gates": renders["CLUSTERS"]["combined"]}
    record = {"part": "accuracy", **config["accuracy"], "vpls": renders["CLUSTERS"]["vpls"],
              "reference_mean": float(reference.mean()),
              **{f"{k} render s": v["seconds"] for k, v in renders.items()}}
    for column, image in images.items():
        if not np.all(np.isfinite(image)):
            raise RuntimeError(f"{column}: the render has non-finite pixels")
        record[f"mse {column}"] = float(np.mean((image - reference) ** 2))
        record[f"mse8 {column}"] = float(np.mean((srgb8(image) - srgb8(reference)) ** 2))
    os.makedirs(config["images"], exist_ok=True)
    stem = os.path.splitext(os.path.basename(bpy.data.filepath))[0] or "scene"
    record["images"] = os.path.join(config["images"], f"{stem}-table2.npz")
    shown = dict(images, reference=reference)
    np.savez_compressed(record["images"], topology=session.read(native.AOV_TOPOLOGY, 4),
                        **{column.replace(" ", "_"): image for column, image in shown.items()},
                        **{column.replace(" ", "_") + "_8bit": np.round(srgb8(image)).astype(np.uint8)
                           for column, image in shown.items()})
    write(record)


def preview(session, scene, config, write):
    settings = config["preview"]
    bl_common.set_resolution(scene, settings["width"], settings["height"])
    for vpls in settings["vpls"]:
        apply_settings(scene.bounce, dict(config["bounce"], topology_vpls=vpls, topology_show_clusters=False,
                                          topology_show_gates=False, topology_show_skeleton=False))
        session.render(scene, scene.camera)  # traces the VPLs and builds the topology if it is not cached
        for repeat in range(settings["repeats"]):
            # Another seed traces new VPLs, as the viewport does when the light moves.
            scene.bounce.seed = repeat + 1
            seconds = session.render(scene, scene.camera)
            write({"part": "preview", "vpls": vpls, "repeat": repeat, "width": settings["width"],
                   "height": settings["height"], "render ms": 1e3 * seconds, **stage_columns(session.info)})
            print(f"benchmark: preview {settings['width']}x{settings['height']}, {vpls} VPLs: "
                  f"{1e3 * seconds:.0f} ms", flush=True)


def main():
    config = bl_common.load_json(bl_common.args()[0])
    scene = bpy.context.scene
    bl_common.set_resolution(scene, config["width"], config["height"])
    session = NativeSession()
    try:
        with open(config["records"], "a") as records:
            def write(record):
                records.write(json.dumps(record) + "\n")
                records.flush()
            precompute(session, scene, config, write)
            accuracy(session, scene, config, write)
            preview(session, scene, config, write)
    finally:
        session.close()


main()
