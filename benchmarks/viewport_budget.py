"""Auto's Sample Budget in a real viewport: a GUI Blender (under Xvfb, scripts/benchmark --suite viewport-budget)
renders the scene in a 3D view in Rendered shading, one progressive render per budget, and times every sample the
viewport shows.

    xvfb-run scripts/blender SCENE.blend --python benchmarks/viewport_budget.py -- JOBS.json

JOBS.json: {"records": PATH, "budgets": [ms, ...], "samples": N, "width": W, "height": H}. The 3D view fills the
window (W x H, the Xvfb screen); it looks through the scene's camera. Each budget renders twice, as a viewport
restarts whenever the view moves: the first ("warm-up") teaches the cost model the plans it had not measured yet
(which render as they are), the second ("measured") is what the budget gives once they are. Each record:
the budget, the region's size, and per published frame seen its samples and the plan it rendered, whose "Used N
ms" is the render thread's own time per sample so far (what the report's times come from).
"""
import json
import os
import sys
import time
import traceback

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "blender", "scripts"))
import bl_common  # noqa: E402

CONFIG = bl_common.load_json(bl_common.args()[0])
TICK = 0.05  # a timer much more frequent starves the viewport's redraws under Xvfb
DEADLINE = time.perf_counter() + 60.0 + 30.0 * len(CONFIG["budgets"]) * CONFIG["samples"]
state = {"renders": [(render, b) for b in CONFIG["budgets"] for render in ("warm-up", "measured")]}


def setup():
    window, area, _region = bl_common.view_3d()
    with bpy.context.temp_override(window=window, area=area):
        bpy.ops.screen.screen_full_area(use_hide_panels=True)
    _window, area, _region = bl_common.view_3d()
    space = area.spaces.active
    space.overlay.show_overlays = False
    space.show_gizmo = False
    space.region_3d.view_perspective = "CAMERA"
    space.shading.type = "RENDERED"
    area.tag_redraw()
    bpy.context.scene.render.engine = "BOUNCE"
    settings = bpy.context.scene.bounce
    settings.method = "AUTO"
    settings.viewport_samples = CONFIG["samples"]


def start(render, budget):
    """A new progressive render: a setting changed restarts the viewport's (the seed too, as a budget may repeat)."""
    settings = bpy.context.scene.bounce
    settings.viewport_sample_budget = budget
    settings.seed += 1
    _window, area, region = bl_common.view_3d()
    area.tag_redraw()
    state["current"] = {"render": render, "budget_ms": budget, "region_width": region.width,
                        "region_height": region.height, "frames": [], "serial": None}
    print(f"benchmark: viewport, budget {budget} ms ({render}), {region.width}x{region.height}", flush=True)


def poll():
    """Records each new frame of the current render; True once it has all its samples."""
    current, render = bl_common.viewport_session(), state["current"]
    if current is None:
        return False
    native = bl_common.addon_module("native")
    progress = current.engine.render_progress()
    info = current.engine.frame_info()
    # The last render's last frame (all its samples) shows until the new render publishes.
    if info is None or info.serial == render["serial"] or (not render["frames"] and info.samples >= CONFIG["samples"]):
        return False
    render["serial"] = info.serial
    render["frames"].append({"samples": info.samples, "plan": info.plan(), "method": info.method})
    return progress.state == native.RENDER_DONE and info.samples >= CONFIG["samples"]


def step():
    try:
        if time.perf_counter() > DEADLINE:
            raise TimeoutError("the viewport did not finish its renders in time")
        if "current" not in state:
            setup()
            start(*state["renders"].pop(0))
        elif poll():
            render = state.pop("current")
            with open(CONFIG["records"], "a") as f:
                f.write(json.dumps({k: v for k, v in render.items() if k != "serial"}) + "\n")
            if not state["renders"]:
                bpy.ops.wm.quit_blender()
                return None
            start(*state["renders"].pop(0))
        return TICK
    except Exception:
        traceback.print_exc()
        print("benchmark: viewport Error", flush=True)
        os._exit(1)


bpy.app.timers.register(step, first_interval=1.0)
