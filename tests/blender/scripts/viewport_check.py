"""Runs inside a GUI Blender (under Xvfb) on a .blend whose scene renders with Bounce.

Puts the largest 3D view in Rendered shading with nothing drawn over it, waits for Bounce's progressive render
to finish, captures the window, and saves the engine's own frame beside it, so the test can check that what
the viewport shows is the engine's picture through Blender's colour management. Then it exercises
incremental sync (moving a light, then an object) and UI responsiveness during a long render, recording the
add-on's sync counters. Writes OUT/result.json, OUT/window.png, OUT/frame.npy; quits Blender.

Arguments after --: OUT CAPTURE, CAPTURE = screenshot (bpy.ops.screen.screenshot) or xwd (an X-level capture,
for Blender versions whose screenshot operator writes black under Xvfb).
"""
import json
import os
import subprocess
import sys
import time
import traceback

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common  # noqa: E402

OUT, CAPTURE = sys.argv[sys.argv.index("--") + 1:][:2]
TICK = 0.02
result = {"steps": []}


def rendered_and_drawn():
    current = bl_common.viewport_session()
    if current is None:
        return False
    progress = current.engine.render_progress()
    native = bl_common.addon_module("native")
    return (progress.state == native.RENDER_DONE and current.texture_serial == progress.frame_serial
            and progress.frame_serial > 0)


def capture(path):
    window, area, _region = bl_common.view_3d()
    if CAPTURE == "xwd":
        display = os.environ["DISPLAY"]
        subprocess.run(f"xwd -root -silent -display {display} | xwdtopnm 2>/dev/null | pnmtopng > {path}",
                       shell=True, check=True)
    else:
        with bpy.context.temp_override(window=window, area=area):
            bpy.ops.screen.screenshot(filepath=path)


def stats():
    return dict(bl_common.addon_module("session").latest_stats["viewport"].as_dict())


# ---- The steps, each run from a timer until it returns True ---------------------------------------------

def step_setup():
    scene = bpy.context.scene
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.render.dither_intensity = 0.0
    _window, area, _region = bl_common.view_3d()
    space = area.spaces.active
    space.shading.type = "RENDERED"
    space.overlay.show_overlays = False
    space.show_gizmo = False
    space.show_region_toolbar = False
    space.show_region_ui = False
    # Headers overlap the drawing region from 4.x on (the frame is drawn under them, as Cycles does).
    space.show_region_header = False
    if hasattr(space, "show_region_tool_header"):
        space.show_region_tool_header = False
    # A free perspective view (the camera view draws a frame line over the picture).
    view = space.region_3d
    view.view_perspective = "PERSP"
    view.view_location = (0.0, 0.0, 1.0)
    view.view_distance = 3.5
    view.view_rotation = (0.7071068, 0.7071068, 0.0, 0.0)  # looking along +Y, z up
    area.tag_redraw()
    return True


def step_first_frame():
    return rendered_and_drawn()


def step_capture():
    window, area, region = bl_common.view_3d()
    current = bl_common.viewport_session()
    info = current.engine.frame_info()
    frame = current.engine.frame_read(bl_common.addon_module("native").AOV_COMBINED, info.width, info.height)
    np.save(os.path.join(OUT, "frame.npy"), np.asarray(frame).reshape(info.height, info.width, -1))
    capture(os.path.join(OUT, "window.png"))
    result["region"] = {"x": region.x, "y": region.y, "width": region.width, "height": region.height}
    result["window"] = {"x": window.x, "y": window.y, "width": window.width, "height": window.height}
    result["frame"] = {"width": info.width, "height": info.height, "samples": info.samples}
    result["stats_first"] = stats()
    result["first_serial"] = info.serial
    result["plan"] = {"method": info.method, "text": info.plan(),
                      "shown": dict(bl_common.addon_module("final").last_plan)}
    return True


def step_move_light():
    light = next(o for o in bpy.context.scene.objects if o.type == "LIGHT")
    light.location.x += 0.3
    result["moved_light"] = light.name
    return True


def step_after_light():
    if not rendered_and_drawn() or bl_common.viewport_session().engine.frame_info().serial == result["first_serial"]:
        return False
    result["stats_after_light"] = stats()
    return True


def step_move_object():
    mesh = next(o for o in bpy.context.scene.objects if o.type == "MESH")
    mesh.location.z += 0.05
    result["moved_object"] = mesh.name
    result["serial_before_object"] = bl_common.viewport_session().engine.frame_info().serial
    return True


def step_after_object():
    if not rendered_and_drawn() or bl_common.viewport_session().engine.frame_info().serial == result["serial_before_object"]:
        return False
    result["stats_after_object"] = stats()
    # A long render next: the UI must keep running timers while it renders.
    bpy.context.scene.bounce.viewport_samples = 400
    result["ticks"] = []
    return True


def step_responsive():
    result["ticks"].append(time.perf_counter())
    current = bl_common.viewport_session()
    progress = current.engine.render_progress()
    native = bl_common.addon_module("native")
    if len(result["ticks"]) < 10:
        return False
    if progress.state == native.RENDER_RUNNING and len(result["ticks"]) < 150:
        result["samples_seen"] = progress.samples_done
        return False
    ticks = result.pop("ticks")
    gaps = [b - a for a, b in zip(ticks, ticks[1:])]
    result["ui_max_gap_seconds"] = max(gaps)
    result["ui_ticks"] = len(ticks)
    result["long_render_state"] = progress.state
    return True


def step_final_render():
    """F12 while the viewport engine lives: two engines (two render threads, two GL contexts) at once."""
    bpy.context.scene.bounce.viewport_samples = 4
    result["serial_before_final"] = bl_common.viewport_session().engine.frame_info().serial
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = 64
    bpy.ops.render.render()
    path = os.path.join(OUT, "final.exr")
    scene.render.image_settings.file_format = "OPEN_EXR"
    bpy.data.images["Render Result"].save_render(path)
    result["final_render"] = path
    return True


def step_viewport_after_final():
    if not rendered_and_drawn() or bl_common.viewport_session().engine.frame_info().serial == result["serial_before_final"]:
        return False
    result["viewport_after_final_serial"] = bl_common.viewport_session().engine.frame_info().serial
    return True


STEPS = [step_setup, step_first_frame, step_capture, step_move_light, step_after_light, step_move_object,
         step_after_object, step_responsive, step_final_render, step_viewport_after_final]
START = time.perf_counter()
DEADLINE = START + 240.0


def run_steps():
    try:
        if time.perf_counter() > DEADLINE:
            result["error"] = f"timed out in {STEPS[0].__name__}"
        elif STEPS[0]():
            result["steps"].append((STEPS.pop(0).__name__, round(time.perf_counter() - START, 2)))
            if STEPS:
                return TICK
        else:
            return TICK
    except Exception:
        result["error"] = traceback.format_exc()
    with open(os.path.join(OUT, "result.json"), "w") as f:
        json.dump(result, f, indent=1)
    bpy.ops.wm.quit_blender()
    return None


bpy.app.timers.register(run_steps, first_interval=1.0)
