"""Final renders (F12, `blender -b`) and material previews: sync, render, write the RenderResult."""
import time

import numpy as np

from . import native, session
from .export import Reports, failures_reported, final_camera
from .properties import fill_settings, method_of

# Render passes: native AOV, Blender pass name, channel ids, pass type. Names match bounce_aov_name().
PASSES = (
    (native.AOV_COMBINED, "Combined", "RGBA", "COLOR"),
    (native.AOV_DIRECT, "Direct", "RGB", "COLOR"),
    (native.AOV_INDIRECT, "Indirect", "RGB", "COLOR"),
    (native.AOV_EMISSION, "Emission", "RGB", "COLOR"),
    (native.AOV_ALBEDO, "Albedo", "RGB", "COLOR"),
    (native.AOV_NORMAL, "Normal", "XYZ", "VECTOR"),
    (native.AOV_DEPTH, "Depth", "Z", "VALUE"),
    (native.AOV_VPLS, "VPLs", "RGB", "COLOR"),
    (native.AOV_SECOND_BOUNCE, "Second Bounce", "RGB", "COLOR"),
    (native.AOV_TOPOLOGY, "Topology", "RGBA", "COLOR"),
)
_AOV_BY_PASS = {name: aov for aov, name, _, _ in PASSES}

WAIT_MS = 100

# Summary of the last final render, for the render panel: {"stages": [(name, gpu_ms, cpu_ms)], ...}.
last_render = {}
# Auto's last plan, from the viewport or a final render, for the render panel: {"text", "method", "components",
# "where"}.
last_plan = {}


def register_passes(engine, scene, view_layer):
    """The passes of the scene's method only: an 8192^2 frame holds 268 MB per channel."""
    try:
        written = native.library().method_aovs(method_of(scene.bounce))
    except native.LibraryLoadError:  # the render will report it; the passes do not matter then
        written = 0
    for aov, name, channel_ids, pass_type in PASSES:
        if written & (1 << aov):
            engine.register_pass(scene, view_layer, name, len(channel_ids), channel_ids, pass_type)


def render(engine, depsgraph):
    """RenderEngine.render: every failure ends as a report, never a traceback."""
    reports = Reports()
    with failures_reported(reports, "Bounce render"):
        _render(engine, depsgraph, reports)
    # Material previews render Blender's own preview scenes: their warnings would only be noise.
    reports.emit(engine.report, warnings=not engine.is_preview)


def _render(engine, depsgraph, reports):
    kind = session.PREVIEW if engine.is_preview else session.FINAL
    current = session.get(engine, kind)
    if current is None:
        return
    scene = depsgraph.scene

    engine.update_stats("", "Bounce | Syncing scene")
    current.scene.sync(depsgraph, reports)
    camera = final_camera(engine, depsgraph)
    settings = fill_settings(scene.bounce, viewport=False)
    scene_stats = current.engine.scene_stats()
    _report_scene_stats(scene_stats, reports)

    builds_before = current.engine.topology_info().builds
    start = time.perf_counter()
    current.engine.render_start(settings, camera)
    while not current.engine.render_wait(WAIT_MS):
        if engine.test_break():
            current.engine.render_cancel()
            return
        _show_progress(engine, current.engine.render_progress())
    _show_progress(engine, current.engine.render_progress())
    render_seconds = time.perf_counter() - start

    info = current.engine.frame_info()
    if info is None:
        raise native.InternalError("the render finished without publishing a frame")
    if info.nonfinite_pixels:
        reports.warn(f"Bounce: {info.nonfinite_pixels} pixels were not finite and were set to zero")
    _write_result(engine, depsgraph, current.engine, info)
    _summarize(engine, kind, info, scene_stats, current.scene.stats, render_seconds)
    if info.plan() and kind == session.FINAL:
        print(f"Bounce: {auto_line(info)}: {info.plan()}")
    if info.noise_relmse >= 0.0 and kind == session.FINAL:
        print(f"Bounce: {error_line(last_render['error'], info.bias_relmse)}")
    if info.method == native.METHOD_TOPOLOGY and kind == session.FINAL:
        topology = current.engine.topology_info()
        built = "built" if topology.builds > builds_before else "from the cache"
        last_render["topology"] = f"{built}: {topology.summary()}"
        print(f"Bounce: topology {last_render['topology']}")


def _show_progress(engine, progress):
    engine.update_progress(min(max(progress.progress, 0.0), 1.0))
    engine.update_stats("", progress_text(progress))


def progress_text(progress):
    """The status line of a running render: its precomputation stage, or its samples."""
    if progress.stage_text():
        return f"Bounce | {progress.stage_text()} ({100 * progress.progress:.0f} %)"
    return f"Bounce | Sample {progress.samples_done}/{progress.samples_total}"


# What scene validation left out or changed (native/src/scene_data.cpp, where the numeric range policy lives: what
# float32 rays and shadow maps cannot resolve), one warning per kind.
_SCENE_STATS_WARNINGS = (
    ("dropped_triangles", "{} triangles with non-finite or collinear vertices were dropped"),
    ("skipped_lights", "{} lights with zero or non-finite power were skipped"),
    ("out_of_range_triangles", "{} triangles farther than 1e9 m from the origin were dropped"),
    ("out_of_range_instances", "{} objects reaching farther than 1e9 m from the origin were left out"),
    ("out_of_range_lights", "{} lights farther than 1e9 m from the origin were skipped"),
    ("clamped_lights", "{} lights brighter than 1e15 or larger than 1e9 m were clamped to those limits"),
)


def _report_scene_stats(stats, reports):
    for field, message in _SCENE_STATS_WARNINGS:
        count = getattr(stats, field)
        if count:
            reports.warn("Bounce: " + message.format(count))


def _write_result(engine, depsgraph, native_engine, info):
    result = engine.begin_result(0, 0, info.width, info.height, layer=depsgraph.view_layer.name)
    try:
        width, height = result.resolution_x, result.resolution_y
        for render_pass in result.layers[0].passes:
            aov = _AOV_BY_PASS.get(render_pass.name)
            if aov is None:
                continue
            pixels = native_engine.frame_read(aov, info.width, info.height)
            _set_rect(render_pass.rect, _fit(pixels, info.width, info.height, width, height, render_pass.channels))
    finally:
        engine.end_result(result)


def _set_rect(rect, pixels):
    """Blender 3.x's RenderPass.rect takes a (pixels, channels) array, 4.x+ a flat one."""
    try:
        rect.foreach_set(pixels)
    except TypeError:
        rect.foreach_set(pixels.reshape(-1))


def _fit(pixels, src_width, src_height, width, height, channels):
    """`pixels` (src_height*src_width, C) as (height*width, channels): the usual case returns it unchanged; a
    size or channel mismatch keeps the overlap and zero-fills the rest."""
    if (src_width, src_height, pixels.shape[1]) == (width, height, channels):
        return pixels
    out = np.zeros((height, width, channels), dtype=np.float32)
    rows, cols, chans = min(height, src_height), min(width, src_width), min(channels, pixels.shape[1])
    out[:rows, :cols, :chans] = pixels.reshape(src_height, src_width, -1)[:rows, :cols, :chans]
    return out.reshape(-1, channels)


def indirect_summary(info, light_names):
    """What the indirect method did in the frame's last sample, in a few words ('' when none ran)."""
    if info.method == native.METHOD_TOPOLOGY:
        return f"Topology: {info.vpl_count:,} VPLs, {info.cluster_count} visibility clusters"
    if info.main_light >= 0:
        name = light_names[info.main_light] if info.main_light < len(light_names) else "?"
        return (f"SSVP: last sample bounced '{name}', {info.vpl_count:,} VPLs, {info.cluster_count} clusters")
    if info.vpl_count:
        return f"FLC: {info.vpl_count:,} VPLs, {info.divergent_triangles:,} triangles subdivided"
    return ""


def auto_line(info):
    """Auto's choice in a few words, e.g. "Auto: Screen-Space VPL Propagation"."""
    method = native.METHOD_NAMES[info.method] if 0 <= info.method < len(native.METHOD_NAMES) else "?"
    return f"Auto: {method}"


def method_text(info, indirect):
    """The status line's part on the method: " | Auto: ... | <indirect summary>", each part when there is one."""
    return "".join(f" | {text}" for text in (auto_line(info) if info.plan() else "", indirect) if text)


def error_forecast(info, seconds, factors=(1, 2, 4, 8)):
    """[(samples, seconds, relMSE), ...] for `factors` times the samples of a render of `seconds` whose frame info
    `info` holds its estimated noise (native/src/noise_estimate.h) and the bias its settings accept (below 0:
    unknown, counted as none): the Direct pass's noise falls as samples^-rate (its rays are stratified over each
    pixel's samples), the rest as 1 / samples, the bias stays, time grows with the samples."""
    bias = max(info.bias_relmse, 0.0)
    direct = min(max(info.noise_direct_relmse, 0.0), info.noise_relmse)
    rest = info.noise_relmse - direct
    return [(info.samples * k, seconds * k, rest / k + direct / k ** info.noise_direct_rate + bias) for k in factors]


def error_line(forecast, bias_relmse):
    """One line on the error a render is estimated to have and what 4 times its samples would buy."""
    samples, relmse = forecast[0][0], forecast[0][2]
    more, more_seconds, less = forecast[2]
    parts = f"noise {relmse - bias_relmse:.2g}, bias {bias_relmse:.2g}" if bias_relmse >= 0.0 else "noise only"
    return (f"error relMSE {relmse:.2g} (estimated: {parts}) after {samples} samples; {more} samples "
            f"(about {more_seconds:.3g} s): {less:.2g}")


def remember_plan(info, where):
    """Keeps Auto's plan of a frame for the render panel (nothing for an explicit method)."""
    if not info.plan():
        return
    last_plan.clear()
    last_plan.update(text=info.plan(), method=auto_line(info), components=info.shares.components(),
                     analysis_ms=info.shares.analysis_ms, where=where)


def _summarize(engine, kind, info, scene_stats, sync_stats, render_seconds):
    stages = info.stage_list()
    # CPU stages (the topology method's) have no GPU time: their wall time stands in.
    stage_text = ", ".join(f"{name} {gpu_ms or cpu_ms:.1f} ms" for name, gpu_ms, cpu_ms in stages)
    indirect = indirect_summary(info, sync_stats.last_light_names)
    engine.update_stats("", f"Bounce | {info.samples} samples{method_text(info, indirect)} | {stage_text}")
    if kind != session.FINAL:
        return
    remember_plan(info, "final render")
    last_render.clear()
    last_render.update(
        stages=stages, samples=info.samples, bounces=info.bounces, width=info.width, height=info.height,
        render_seconds=render_seconds, sync_seconds=sync_stats.last_sync_seconds,
        triangles=scene_stats.triangle_count, dropped_triangles=scene_stats.dropped_triangles,
        lights=scene_stats.light_count, skipped_lights=scene_stats.skipped_lights,
        meshes=scene_stats.mesh_count, instances=scene_stats.instance_count, gpu_bytes=scene_stats.gpu_bytes,
        indirect=indirect, plan=info.plan(), analysis_ms=info.shares.analysis_ms,
        error=(error_forecast(info, render_seconds)
               if info.noise_relmse >= 0.0 else None),
        noise_relmse=info.noise_relmse, bias_relmse=info.bias_relmse)
