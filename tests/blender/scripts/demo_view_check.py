"""Runs inside a GUI Blender (under Xvfb): Render > Bounce Demo from a 3D view and from another editor.

Run from a 3D view, the operator must turn that view to the demo's camera in Rendered shading; run from another
editor (as from the top bar's Render menu), the window's largest 3D view. After the render has drawn, the window is captured. Writes
OUT/result.json and OUT/window.png; quits Blender.

Arguments after --: OUT CAPTURE (screenshot or xwd, as viewport_check.py).
"""
import json
import os
import subprocess
import sys
import time
import traceback

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common  # noqa: E402

OUT, CAPTURE = sys.argv[sys.argv.index("--") + 1:][:2]
result = {}


def areas(kind):
    window = bpy.context.window_manager.windows[0]
    return window, [a for a in window.screen.areas if a.type == kind]


def view_state(area):
    space = area.spaces.active
    return {"shading": space.shading.type, "perspective": space.region_3d.view_perspective}


def reset_views():
    _window, views = areas("VIEW_3D")
    for area in views:
        area.spaces.active.shading.type = "SOLID"
        area.spaces.active.region_3d.view_perspective = "PERSP"


def run_demo(area_kind):
    window, found = areas(area_kind)
    area = max(found, key=lambda a: a.width * a.height)
    with bpy.context.temp_override(window=window, area=area, region=area.regions[-1]):
        bpy.ops.bounce.demo_scene(resolution=128)
    _window, views = areas("VIEW_3D")
    largest = max(views, key=lambda a: a.width * a.height)
    return {"scene": window.scene.name, "largest_view": view_state(largest),
            "views": [view_state(a) for a in views]}


def finish():
    try:
        path = os.path.join(OUT, "window.png")
        if CAPTURE == "xwd":
            subprocess.run(f"xwd -root -silent -display {os.environ['DISPLAY']} | xwdtopnm 2>/dev/null"
                           f" | pnmtopng > {path}", shell=True, check=True)
        else:
            window, views = areas("VIEW_3D")
            with bpy.context.temp_override(window=window, area=views[0]):
                bpy.ops.screen.screenshot(filepath=path)
    except Exception:
        result["capture_error"] = traceback.format_exc()
    with open(os.path.join(OUT, "result.json"), "w") as f:
        json.dump(result, f, indent=1)
    bpy.ops.wm.quit_blender()


def main():
    try:
        result["from_view"] = run_demo("VIEW_3D")
        reset_views()
        result["from_elsewhere"] = run_demo("PROPERTIES")
    except Exception:
        result["error"] = traceback.format_exc()
        finish()
        return None
    started = time.perf_counter()

    def wait_for_frame():  # until the Rendered view has drawn a frame of the engine's (or a minute has passed)
        sessions = bl_common.addon_module("session").viewport_sessions()
        drawn = bool(sessions) and (sessions[0].texture_serial or 0) > 0
        if not drawn and time.perf_counter() - started < 60.0:
            return 0.25
        result["drawn"] = drawn
        finish()
        return None
    bpy.app.timers.register(wait_for_frame, first_interval=0.5)
    return None


bpy.app.timers.register(main, first_interval=1.0)
