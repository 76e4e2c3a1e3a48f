"""Rendered shading in the 3D viewport.

view_update syncs the scene incrementally; view_draw (re)starts a render when the view, the settings or the
scene changed (bounce_render_start returns at once: the render runs on the native render thread) and draws the
latest published frame, even one of an older view (stale is better than blank). While a render runs, a
bpy.app.timers callback watches the frame serial and redraws the 3D views when a new frame is published.

`gpu` is imported inside view_draw only: importing it in `blender -b` crashes Blender 3.4.
"""
import bpy

from . import final, native, session
from .export import Reports, failures_reported, viewport_camera
from .properties import fill_settings

POLL_SECONDS = 0.05


def view_update(engine, context, depsgraph):
    reports = Reports()
    with failures_reported(reports, "Bounce viewport"):
        current = session.get(engine, session.VIEWPORT)
        if current is not None and current.scene.sync(depsgraph, reports):
            current.scene_serial += 1
    _emit(engine, reports)


def view_draw(engine, context, depsgraph):
    reports = Reports()
    with failures_reported(reports, "Bounce viewport"):
        _draw(engine, context)
    _emit(engine, reports)


def _draw(engine, context):
    current = session.get(engine, session.VIEWPORT)
    if current is None:
        return
    camera = viewport_camera(context)
    settings = fill_settings(context.scene.bounce, viewport=True)
    if not context.scene.bounce.topology_overlay:
        # Nothing shows the Topology pass then: the core skips drawing it (about a primary-ray pass per restart).
        settings.topology_show_clusters = settings.topology_show_skeleton = settings.topology_show_gates = 0
    signature = (bytes(camera), bytes(settings), current.scene_serial)
    if signature != current.render_signature:
        current.render_signature = signature
        current.engine.render_start(settings, camera)
        _start_polling()
    _draw_latest_frame(engine, context, current)
    if current.engine.render_progress().state == native.RENDER_FAILED:
        current.engine.render_wait(0)  # raises the render's own failure, reported once


def _draw_latest_frame(engine, context, current):
    import gpu
    from gpu_extras.presets import draw_texture_2d

    progress = current.engine.render_progress()
    if progress.stage_text():
        engine.update_stats("", final.progress_text(progress))
    info = current.engine.frame_info()
    if info is not None and info.serial != current.texture_serial:
        # frame_read reads the frame `info` describes, even if a newer one (another size) is published meanwhile.
        current.pixels = current.engine.frame_read(native.AOV_COMBINED, info.width, info.height, out=current.pixels)
        props = context.scene.bounce
        if props.method == "TOPOLOGY" and props.topology_overlay:
            _blend_overlay(current.pixels, current.engine.frame_read(native.AOV_TOPOLOGY, info.width, info.height))
        flat = current.pixels.reshape(-1)
        buffer = gpu.types.Buffer("FLOAT", flat.size, flat)  # wraps the numpy memory, no copy
        current.texture = gpu.types.GPUTexture((info.width, info.height), format="RGBA16F", data=buffer)
        current.texture_serial = info.serial
        indirect = final.indirect_summary(info, current.scene.stats.last_light_names)
        engine.update_stats("", f"Bounce | Sample {info.samples}{final.method_text(info, indirect)}")
        final.remember_plan(info, "viewport")
    if current.texture is None:
        return

    # The frame is scaled to the region: after a resize the previous frame stays visible until the new one.
    gpu.state.blend_set("ALPHA_PREMULT")
    engine.bind_display_space_shader(context.scene)
    try:
        draw_texture_2d(current.texture, (0, 0), context.region.width, context.region.height)
    finally:
        engine.unbind_display_space_shader()
        gpu.state.blend_set("NONE")


OVERLAY_OPACITY = 0.6


def _blend_overlay(image, overlay):
    """The Topology pass over the image (both (pixels, 4) float arrays), in place, at OVERLAY_OPACITY."""
    weight = OVERLAY_OPACITY * overlay[:, 3:4]
    image[:, :3] = image[:, :3] * (1.0 - weight) + overlay[:, :3] * weight


def _emit(engine, reports):
    current = session.find(engine)
    reports.emit(engine.report, current.shown_reports if current is not None else None)


# ---- Progressive redraws --------------------------------------------------------------------------------


def _poll_renders():
    """Timer callback: redraw the 3D views when a running viewport render published a new frame."""
    running = redraw = False
    for current in session.viewport_sessions():
        try:
            progress = current.engine.render_progress()
        except native.BounceError:
            continue
        running |= progress.state == native.RENDER_RUNNING
        if progress.stage_text():  # the precomputation's status line moves on without frames
            redraw = True
        if progress.frame_serial != current.texture_serial and progress.frame_serial != current.redraw_serial:
            current.redraw_serial = progress.frame_serial
            redraw = True
    if redraw:
        _tag_redraw_3d_views()
    return POLL_SECONDS if running or redraw else None


def _tag_redraw_3d_views():
    # Tagging areas (not RenderEngine.tag_redraw) needs no reference to an engine Blender may have freed.
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def _start_polling():
    if not bpy.app.timers.is_registered(_poll_renders):
        bpy.app.timers.register(_poll_renders, first_interval=POLL_SECONDS)


def stop_polling():
    if bpy.app.timers.is_registered(_poll_renders):
        bpy.app.timers.unregister(_poll_renders)
