"""Runs inside Blender for scripts/benchmark (benchmarks/bench.py):

    scripts/blender -b [SCENE.blend] --python benchmarks/blender_render.py -- JOBS.json

renders the open scene once per job and repeat, and appends one JSON line per render to JOBS["records"].
Works with the Python APIs of Blender 3.4, 4.x and 5.x.

JOBS: {"records": path, "info": optional path (receives Blender's version, the GL renderer and scene.bounce's
                                                settings with their default values),
       "extra_triangles": optional int (adds a flat grid of that many triangles, for sync throughput),
       "warm_up": true (default) renders one sample before the first job of each engine and method (Bounce's
                  recorded with role "warm-up": its wall time is a first render's, one-off costs included),
       "jobs": [{"engine": "BOUNCE" | "CYCLES" | "CPU_REFERENCE", "width", "height", "repeats",
                 "camera": optional name of the camera object to render from (default: the scene's camera),
                 "sources": optional '+'-joined light source classes that alone light the scene
                            (bl_common.keep_light_sources),
                 "bounce": {setting: value},            # scene.bounce.<setting>; the rest stays at defaults
                 "cycles": {"samples", "seed", "device", "bounces"},  # the oracle of DESIGN.md: exactly `bounces`
                 "exr": optional path (multilayer EXR of the first repeat), "meta": {...copied into records},
                 "cpu_reference": {"scene": path, options of cpu_reference_export.export}}]}
A CPU_REFERENCE job renders nothing: it writes the scene for bounce_reference_render (the CPU model reference).
"""
import importlib
import json
import os
import sys
import time
import types

import bpy

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def load_test_helpers():
    """The test suite's Cycles oracle and linear-output helpers, so benchmarks and tests share one recipe."""
    sys.path.insert(0, os.path.join(REPO, "tests", "blender", "scripts"))
    return importlib.import_module("bl_common"), importlib.import_module("render")


bl_common, oracle = load_test_helpers()


addon_module = bl_common.addon_module


class NativeSession:
    """One native engine rendering the open scene again and again, as one viewport does: the scene syncs
    incrementally and whatever the core caches (SSVP's clusters, the topology) carries over between renders."""

    def __init__(self):
        self.native, self.export = addon_module("native"), addon_module("export")
        self.properties = addon_module("properties")
        self.engine = self.native.Engine()
        self.sync = self.export.SceneSync(self.engine)
        self.info = None

    def render(self, scene, camera_object, frame=0):
        """Renders scene.bounce's final-render settings from `camera_object`; returns the wall seconds of the
        render alone (sync excluded). The frame's info is self.info, its passes self.read(aov)."""
        depsgraph = bpy.context.evaluated_depsgraph_get()
        self.sync.sync(depsgraph, self.export.Reports(), moved=True)
        camera = self.export.final_camera(types.SimpleNamespace(camera_override=camera_object), depsgraph)
        camera.frame = frame
        settings = self.properties.fill_settings(scene.bounce, viewport=False)
        start = time.perf_counter()
        self.engine.render_start(settings, camera)
        self.engine.render_wait(-1)
        seconds = time.perf_counter() - start
        self.info = self.engine.frame_info()
        return seconds

    def read(self, aov, channels=3):
        """A pass of the last frame, (height, width, channels)."""
        width, height = self.info.width, self.info.height
        return self.engine.frame_read(aov, width, height).reshape(height, width, -1)[..., :channels].copy()

    def close(self):
        self.engine.close()


def add_triangle_grid(triangles):
    """A flat grid of about `triangles` triangles far below the scene: it costs sync time, not pixels."""
    side = max(1, int((triangles / 2) ** 0.5))
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=side + 1, y_subdivisions=side + 1, size=1.0,
                                    location=(0, 0, -100))


def gl_renderer():
    native = addon_module("native")
    try:
        with native.Engine() as engine:
            return engine.gl_info()
    except Exception as error:  # the probe is informative only; a render would report the real problem
        return f"unknown ({error})"


def use_cycles_gpu():
    """Picks the first GPU backend Cycles finds; stays on the CPU (and says so) when there is none."""
    prefs = bpy.context.preferences.addons["cycles"].preferences
    for backend in ("OPTIX", "CUDA", "HIP", "ONEAPI", "METAL"):
        try:
            prefs.compute_device_type = backend
        except TypeError:
            continue
        prefs.get_devices()
        gpus = [d for d in prefs.devices if d.type == backend]
        if gpus:
            for device in prefs.devices:
                device.use = device.type == backend
            return "GPU"
    print("benchmark: no GPU backend for Cycles, rendering the references on the CPU", flush=True)
    return "CPU"


def configure(scene, job):
    bl_common.set_resolution(scene, job["width"], job["height"])
    if job.get("camera"):
        scene.camera = bpy.data.objects[job["camera"]]
    if job.get("sources"):
        bl_common.keep_light_sources(scene, job["sources"])
    bl_common.linear_output(scene)
    if job["engine"] == "CYCLES":
        cycles = job.get("cycles", {})
        oracle.cycles_oracle(scene, cycles.get("samples", 1024), bounces=cycles.get("bounces", 1),
                             seed=cycles.get("seed", 0))
        if cycles.get("device") == "GPU":
            scene.cycles.device = use_cycles_gpu()
        for layer in scene.view_layers:
            layer.use_pass_emit = True
        # Alpha marks the pixels that see geometry: the error is measured over those only.
        scene.render.film_transparent = True
        # Bounce draws no light geometry; a camera-visible area light would be an error neither method shares.
        for ob in scene.objects:
            if ob.type == "LIGHT" and hasattr(ob, "visible_camera"):
                ob.visible_camera = False
    else:
        scene.render.engine = "BOUNCE"
        # Pixel centres, as the Cycles oracle samples them (its filter width 0.01): a 1 px box filter against
        # point samples measures the filter at every high-contrast edge (a lit doorway seen from a dark room gives
        # a relMSE that grows with the samples), not the light.
        apply_settings(scene.bounce, {"filter_width": 0.0, **job.get("bounce", {})})


def setting_defaults(props):
    """{setting: default value} of scene.bounce (a PropertyGroup), so the driver knows which settings this build
    has."""
    defaults = {}
    for prop in props.bl_rna.properties:
        if prop.identifier == "rna_type":
            continue
        value = getattr(prop, "default", None)
        if getattr(prop, "is_array", False):
            value = list(prop.default_array)
        defaults[prop.identifier] = value if isinstance(value, (bool, int, float, str)) else None
    return defaults


def apply_settings(props, values):
    """scene.bounce at its defaults, then `values` ({setting: value}): a job's result does not depend on the jobs
    before it."""
    for prop in props.bl_rna.properties:
        if prop.identifier != "rna_type" and not prop.is_readonly:
            props.property_unset(prop.identifier)
    for name, value in values.items():
        if not hasattr(props, name):
            raise ValueError(f"scene.bounce has no setting '{name}'")
        setattr(props, name, value)


def save_exr(scene, path):
    """The Render Result as a multilayer EXR, written after the timed render; atomically, since it may be a
    cached reference."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    partial = path + ".partial.exr"
    bpy.data.images["Render Result"].save_render(filepath=partial, scene=scene)
    os.replace(partial, path)


def export_cpu_reference(scene, job):
    sys.path.insert(0, os.path.join(REPO, "benchmarks"))
    cpu_reference_export = importlib.import_module("cpu_reference_export")
    bl_common.set_resolution(scene, job["width"], job["height"])
    options = dict(job["cpu_reference"])
    path = options.pop("scene")
    start = time.perf_counter()
    triangles, lights = cpu_reference_export.export(bpy.context.evaluated_depsgraph_get(), path, addon_module,
                                                    **options)
    print(f"benchmark: CPU reference scene {os.path.basename(path)}: {triangles} triangles, {lights} lights, "
          f"{time.perf_counter() - start:.1f} s", flush=True)


def render_job(scene, job, records, index, count, warmed):
    if job["engine"] == "CPU_REFERENCE":
        export_cpu_reference(scene, job)
        return
    configure(scene, job)
    method = (job["engine"], job.get("bounce", {}).get("method"))
    meta = job.get("meta", {})
    name = meta.get("label", job["engine"])
    if warmed is not None and method not in warmed:
        # The first render of a method in a Blender process also creates the GL context and compiles its
        # shaders, loads Cycles' kernels, builds what the core caches (the topology): one-off costs that are not
        # the frame's, so a render pays them first. Bounce's is recorded, as role "warm-up".
        # One sample pays it.
        warmed.add(method)
        settings = scene.cycles if job["engine"] == "CYCLES" else scene.bounce
        samples, settings.samples = settings.samples, 1
        if job["engine"] == "CYCLES":
            bpy.ops.render.render()
        else:
            render_once(scene, job, records, dict(meta, role="warm-up"), f"[{index}/{count}] {name} warm-up")
        settings.samples = samples
    for repeat in range(job.get("repeats", 1)):
        render_once(scene, job, records, dict(meta, repeat=repeat),
                    f"[{index}/{count}] {name} repeat {repeat + 1}/{job.get('repeats', 1)}",
                    exr=job.get("exr") if repeat == 0 else None)


def render_once(scene, job, records, meta, progress, exr=None):
    """Renders the configured scene once and appends its record (`meta` plus what the render measured)."""
    final = addon_module("final")
    final.last_render.clear()
    # A fresh engine each render, as F12 makes one: every render syncs the whole scene.
    start = time.perf_counter()
    bpy.ops.render.render()
    wall = time.perf_counter() - start
    record = dict(meta, engine=job["engine"], width=job["width"], height=job["height"], wall_seconds=wall,
                  blender=bpy.app.version_string)
    if job["engine"] == "CYCLES":
        record["samples"] = scene.cycles.samples
    else:
        info = dict(final.last_render)
        if not info:
            raise RuntimeError("the render produced no frame (see the report above)")
        record.update(samples=info["samples"], bounces_simulated=info["bounces"], sync_seconds=info["sync_seconds"],
                      render_seconds=info["render_seconds"], triangles=info["triangles"],
                      instances=info.get("instances"),
                      stages={stage: {"gpu_ms": gpu, "cpu_ms": cpu} for stage, gpu, cpu in info["stages"]})
        if "topology" in info:  # whether this render built the topology or found it cached
            record["topology"] = info["topology"]
        if info.get("plan"):
            record.update(plan=info["plan"], analysis_ms=info["analysis_ms"])
        if info.get("error"):  # the render's own estimate of its error, checked against the oracle's
            record.update(estimated_relmse=info["error"][0][2], noise_relmse=info["noise_relmse"],
                          bias_relmse=info["bias_relmse"])
    if exr:
        save_exr(scene, exr)
        record["exr"] = exr
    records.write(json.dumps(record) + "\n")
    records.flush()
    print(f"benchmark: {progress}: wall {wall:.2f} s" + (f", sync {record['sync_seconds'] * 1e3:.0f} ms, render "
                                                        f"{record['render_seconds'] * 1e3:.0f} ms"
                                                        if "sync_seconds" in record else ""), flush=True)


def main():
    config = bl_common.load_json(bl_common.args()[0])
    scene = bpy.context.scene
    if config.get("info"):
        bl_common.write_json(config["info"], {"blender": bpy.app.version_string, "gl": gl_renderer(),
                                              "settings": setting_defaults(scene.bounce)})
    if config.get("extra_triangles"):
        add_triangle_grid(config["extra_triangles"])
    jobs = config.get("jobs", [])
    warmed = set() if config.get("warm_up", True) else None
    with open(config["records"], "a") as records:
        for index, job in enumerate(jobs, 1):
            render_job(scene, job, records, index, len(jobs), warmed)


if __name__ == "__main__":  # ssvp_temporal.py imports the helpers above
    main()
