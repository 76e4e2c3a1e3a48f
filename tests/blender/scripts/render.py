"""Render the open .blend (or a built-in scene) to a multilayer 32-bit EXR with Bounce or with Cycles as the
oracle of DESIGN.md ("Cycles as an oracle").

    blender -b [SCENE.blend] --python render.py -- CONFIG.json

CONFIG: {"out": "/path/base" (Blender adds .exr), "engine": "BOUNCE" | "CYCLES",
         "scene": optional "demo" (bpy.ops.bounce.demo_scene into a new scene),
         "resolution": optional int (square), "bounce": {setting: value}, "cycles": {"samples": N, "bounces": k},
         "camera": optional {"type": "PERSP" | "ORTHO", "ortho_scale", "sensor_fit", "shift_x", "shift_y",
                             "size": [w, h], "border": [min_x, min_y, max_x, max_y], "crop": bool},
         "info": optional path of a JSON file receiving what was rendered}
"""
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bl_common as bc  # noqa: E402


def cycles_oracle(scene, samples, bounces, seed=0):
    """Exactly `bounces` diffuse bounces, point-sampled pixel centres, no clamping, no denoising, Standard view;
    passes DiffDir, DiffInd, DiffCol (diffuse = DiffCol * (DiffDir + DiffInd))."""
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    if hasattr(c, "use_adaptive_sampling"):
        c.use_adaptive_sampling = False
    c.seed = seed
    c.max_bounces = c.diffuse_bounces = bounces
    c.glossy_bounces = c.transmission_bounces = c.volume_bounces = 0
    c.transparent_max_bounces = 8
    c.filter_width = 0.01
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.caustics_reflective = c.caustics_refractive = False
    c.use_denoising = False
    if hasattr(c, "use_preview_denoising"):
        c.use_preview_denoising = False
    for layer in scene.view_layers:
        layer.use_pass_diffuse_direct = True
        layer.use_pass_diffuse_indirect = True
        layer.use_pass_diffuse_color = True
        if hasattr(layer, "cycles") and hasattr(layer.cycles, "denoising_store_passes"):
            layer.cycles.denoising_store_passes = False
    scene.render.threads_mode = "AUTO"


def apply_camera(scene, camera):
    """Camera and framing options, to check that Bounce frames the image exactly as Cycles does."""
    data = scene.camera.data
    for name in ("type", "ortho_scale", "sensor_fit", "shift_x", "shift_y"):
        if name in camera:
            setattr(data, name, camera[name])
    if "size" in camera:
        scene.render.resolution_x, scene.render.resolution_y = camera["size"]
    if "border" in camera:
        r = scene.render
        r.use_border = True
        r.border_min_x, r.border_min_y, r.border_max_x, r.border_max_y = camera["border"]
        r.use_crop_to_border = camera.get("crop", True)


def main():  # noqa: C901
    config = bc.load_json(bc.args()[0])
    if config.get("scene") == "demo":
        factory = bpy.context.scene
        bpy.ops.bounce.demo_scene(resolution=config.get("resolution", 256))
        scene = next(s for s in bpy.data.scenes if s != factory)
    else:
        scene = bpy.context.scene
    if config.get("resolution"):
        bc.set_resolution(scene, config["resolution"], config["resolution"])
    if config.get("camera"):
        apply_camera(scene, config["camera"])
    bc.linear_output(scene)
    if config["engine"] == "CYCLES":
        cy = config.get("cycles", {})
        cycles_oracle(scene, cy.get("samples", 256), cy.get("bounces", 0), cy.get("seed", 0))
    else:
        bc.bounce_settings(scene, **config.get("bounce", {}))
    start = time.perf_counter()
    path = bc.render_still(scene, config["out"])
    seconds = time.perf_counter() - start
    print(f"rendered {scene.name} with {scene.render.engine} in {seconds:.2f} s -> {path}")
    if config.get("info"):
        bc.write_json(config["info"], {"exr": path, "seconds": seconds, "blender": list(bc.version()),
                                       "scene": scene.name, "engine": scene.render.engine,
                                       "resolution": [scene.render.resolution_x, scene.render.resolution_y]})


if __name__ == "__main__":
    main()
