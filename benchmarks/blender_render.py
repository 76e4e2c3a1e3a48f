"""Runs inside Blender (scripts/blender -b FILE.blend --python benchmarks/blender_render.py -- ...): renders the
open scene with Bounce several times and writes what each render cost as JSON lines.

Each record: scene, resolution, samples, repeat, sync seconds, triangles, and per-stage GPU/CPU milliseconds
(from the core's GL timer queries, via the add-on's final.last_render).
"""
import argparse
import importlib
import json
import sys
import time

import bpy


def addon_module(name):
    """The add-on's submodule `name`, whether it runs as a legacy add-on or as an extension."""
    for package in ("bounce", "bl_ext.user_default.bounce"):
        if package in sys.modules:
            return importlib.import_module(f"{package}.{name}")
    raise RuntimeError("the Bounce add-on is not enabled (run through scripts/blender)")


def add_triangle_grid(triangles):
    """A flat grid of about `triangles` triangles below the scene, for sync throughput."""
    side = max(1, int((triangles / 2) ** 0.5))
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=side + 1, y_subdivisions=side + 1, size=1.0,
                                    location=(0, 0, -100))
    return side * side * 2


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--label", required=True)
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=720)
    parser.add_argument("--samples", type=int, default=1)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--extra-triangles", type=int, default=0, help="add a grid of this many triangles")
    parser.add_argument("--out", required=True, help="JSON-lines file to append to")
    args = parser.parse_args(argv)

    scene = bpy.context.scene
    if args.extra_triangles:
        add_triangle_grid(args.extra_triangles)
    scene.render.engine = "BOUNCE"
    scene.render.resolution_x, scene.render.resolution_y = args.width, args.height
    scene.render.resolution_percentage = 100
    scene.bounce.method = "DIRECT"
    scene.bounce.samples = args.samples
    final = addon_module("final")

    with open(args.out, "a") as out:
        for repeat in range(args.repeats):
            # A fresh engine each repeat, as F12 makes one: every render syncs the whole scene.
            start = time.perf_counter()
            bpy.ops.render.render()
            wall = time.perf_counter() - start
            info = dict(final.last_render)
            if not info:
                raise RuntimeError("the render produced no frame (see the report above)")
            record = {
                "scene": args.label, "width": info["width"], "height": info["height"], "samples": info["samples"],
                "repeat": repeat, "wall_seconds": wall, "sync_seconds": info["sync_seconds"],
                "render_seconds": info["render_seconds"], "triangles": info["triangles"],
                "stages": {name: {"gpu_ms": gpu, "cpu_ms": cpu} for name, gpu, cpu in info["stages"]},
            }
            out.write(json.dumps(record) + "\n")
            print(f"benchmark: {args.label} repeat {repeat}: sync {record['sync_seconds'] * 1e3:.0f} ms, "
                  f"render {record['render_seconds'] * 1e3:.0f} ms")


main()
