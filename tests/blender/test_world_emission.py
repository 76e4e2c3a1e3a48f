"""The world and emissive surfaces light the scene, through Blender (F12 path), with every method: a Lambertian plane
(albedo 0.8) seen straight down, under a uniform sky, under a rotated studio HDRI, and below a square emitter
(scripts/world_scene.py says how each expectation is computed). Closed forms, as Cycles measured them (issue 16):
sky radiance 0.8 x world; emitter 0.8 x 10 x the view factor, 1.9157 below its centre (Cycles 1.9128); an emission
colour from an image texture tints that light. And the benchmark's split of a scene's light by source class
(NAME@SOURCES, bl_common.keep_light_sources): sky, sun and emitter each alone add up to all three at once.
"""
import numpy as np
import pytest

import analytic
from conftest import layer_pass, read_exr, record

# The export of the world and of emission is checked on every Blender version by the direct light; the indirect
# methods render the very scene it makes, so they are the core's numbers, run on the host's Blender.
METHODS = ["DIRECT", *(pytest.param(m, marks=pytest.mark.core) for m in ("FLC", "SSVP", "TOPOLOGY"))]
SOURCE_SHARES = ["sky_sun_emitter@world", "sky_sun_emitter@lamps", "sky_sun_emitter@emission"]
SPLIT = ["sky_sun_emitter", *SOURCE_SHARES]
SPEC = {
    "resolution": 32, "ortho_scale": 4.0, "center": [0.0, 0.0], "camera_height": 20.0, "plane_size": 100.0,
    "cases": ["sky", "hdri", "emitter", "textured_emitter", *SPLIT],
    "bounce": {"samples": 256, "filter_width": 0.0, "shadow_map_size": 512},
}
# The sky and the HDRI are sampled by directions shared by all pixels: 64 samples x 4 directions, stratified in
# elevation and azimuth (HDRI: 0.5 % at 64 samples, 4.3 % when one coordinate drew from the flattened table); the
# emitter's two triangles are exact (Lambert's formula).
TOLERANCE = {"sky": 0.01, "hdri": 0.01, "emitter": 0.01, "textured_emitter": 0.01}


@pytest.fixture(scope="module", params=METHODS)
def world_renders(request, blender, out_root):
    """Every case rendered by one method (one Blender each): (method, the cases' record)."""
    method = request.param
    spec = {**SPEC, "methods": [method]}
    return method, blender.render_cases("world_scene.py", spec, out_root / f"world-{method}", "world.json",
                                        f"world-{method}")


def expected_radiance(name, case):
    n = SPEC["resolution"]
    expected = case["expected"]
    if name in ("emitter", "textured_emitter"):
        pts = analytic.ortho_pixel_centres(n, SPEC["ortho_scale"], SPEC["center"]).reshape(-1, 3)
        h, z = expected["emitter_half"], expected["emitter_height"]
        corners = np.array([[-h, -h, z], [h, -h, z], [h, h, z], [-h, h, z]])
        irradiance = analytic.polygon_irradiance(corners, expected["emission"], np.array([0.0, 0.0, -1.0]),
                                                 np.array([0.0, 0.0, z]), pts)
        radiance = (0.8 / np.pi * irradiance).reshape(n, n)
        return radiance[:, :, None] * np.asarray(expected["tint"])[None, None, :]
    return np.broadcast_to(np.asarray(expected["radiance"], dtype=np.float64), (n, n, 3))


@pytest.mark.parametrize("name", [c for c in SPEC["cases"] if c not in SPLIT])
def test_world_and_emission_light_the_plane(name, world_renders):
    method, renders = world_renders
    case = renders["cases"][name]
    rgb = layer_pass(read_exr(case["exr"][method]), "Combined", "RGB").astype(np.float64)
    assert np.all(np.isfinite(rgb)), "non-finite pixels"
    expected = expected_radiance(name, case)
    n = SPEC["resolution"]
    pts = analytic.ortho_pixel_centres(n, SPEC["ortho_scale"], SPEC["center"]).reshape(n, n, 3)
    # The emitter hides the plane below it (the camera sees its emission): compared outside its footprint.
    mask = np.max(np.abs(pts[:, :, :2]), axis=2) > 0.6 if "emitter" in name else np.ones((n, n), bool)
    ratio = rgb[mask].mean(axis=0) / expected[mask].mean(axis=0)
    record(f"world_{name}_{method}_ratio", [round(float(r), 4) for r in ratio])
    assert np.all(np.abs(ratio - 1.0) < TOLERANCE[name]), f"{name}, {method}: mean ratio {ratio} to the closed form"


def test_light_source_shares_add_up(world_renders):
    method, renders = world_renders

    def combined(name):
        rgb = layer_pass(read_exr(renders["cases"][name]["exr"][method]), "Combined", "RGB").astype(np.float64)
        assert np.all(np.isfinite(rgb)), f"{name}: non-finite pixels"
        return rgb.mean(axis=(0, 1))

    whole = combined(SPLIT[0])
    shares = [combined(name) for name in SOURCE_SHARES]
    ratio = sum(shares) / whole
    record(f"light_source_shares_{method}", {"whole": [round(float(v), 4) for v in whole],
                                             "ratio": [round(float(r), 4) for r in ratio]})
    for name, share in zip(SOURCE_SHARES, shares):
        assert np.all(share > 0.05 * whole), f"{name}, {method}: {share} of {whole}: the source lit nothing"
    assert np.all(np.abs(ratio - 1.0) < 0.02), f"{method}: the sources alone add up to {ratio} of all at once"
