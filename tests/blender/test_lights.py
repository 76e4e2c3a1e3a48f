"""(a) Analytic light checks through Blender: validates the add-on's light unit conversion against the closed
forms of DESIGN.md ("Light units", measured against Cycles).

A Lambertian plane (Diffuse BSDF, albedo 0.8, roughness 0) seen straight down by an orthographic camera, one
light per case; Bounce renders with 1 sample at the pixel centres (filter_width 0). Combined must equal
0.8 / pi * E within 1 % at every pixel brighter than 1 % of the case's peak.
"""
import math

import numpy as np
import pytest

import analytic
from conftest import layer_pass, read_exr, record

ALBEDO = 0.8
TOLERANCE = 0.01        # max relative error
MASK_FRACTION = 0.01    # pixels above this fraction of the peak are checked

SPEC = {
    "resolution": 64, "ortho_scale": 6.0, "center": [0.0, 0.0], "camera_height": 20.0, "plane_size": 100.0,
    "albedo": ALBEDO,
    "bounce": {"method": "DIRECT", "samples": 1, "filter_width": 0.0, "shadow_map_size": 512},
    "cases": [
        {"name": "point_r0", "type": "POINT", "energy": 200.0, "location": [0.6, -0.4, 1.5], "radius": 0.0},
        {"name": "point_r040", "type": "POINT", "energy": 200.0, "location": [-0.5, 0.3, 1.2], "radius": 0.4},
        {"name": "spot", "type": "SPOT", "energy": 500.0, "location": [0.3, -0.2, 2.5], "radius": 0.0,
         "rotation_deg": [15.0, -10.0, 0.0], "spot_size_deg": 70.0, "spot_blend": 0.25},
        {"name": "spot_hard", "type": "SPOT", "energy": 300.0, "location": [-0.4, 0.2, 2.0], "radius": 0.0,
         "rotation_deg": [-20.0, 0.0, 0.0], "spot_size_deg": 50.0, "spot_blend": 0.0},
        {"name": "sun", "type": "SUN", "energy": 2.0, "location": [0.0, 0.0, 5.0],
         "rotation_deg": [35.0, 0.0, 25.0], "angle_deg": 0.5},
        {"name": "area_rectangle", "type": "AREA", "shape": "RECTANGLE", "energy": 150.0, "size": 1.0,
         "size_y": 0.6, "scale": [1.5, 0.8, 1.0], "location": [0.4, -0.3, 1.2], "rotation_deg": [15.0, -10.0, 30.0]},
        {"name": "area_square", "type": "AREA", "shape": "SQUARE", "energy": 80.0, "size": 0.8,
         "location": [-0.3, 0.5, 0.9], "rotation_deg": [0.0, 20.0, 0.0]},
        {"name": "area_disk", "type": "AREA", "shape": "DISK", "energy": 100.0, "size": 0.9,
         "location": [0.2, 0.2, 1.0]},
        {"name": "area_ellipse", "type": "AREA", "shape": "ELLIPSE", "energy": 120.0, "size": 1.2, "size_y": 0.5,
         "scale": [0.7, 1.6, 1.0], "location": [-0.2, -0.1, 1.1], "rotation_deg": [10.0, 0.0, -40.0]},
        # Straddles the receiving plane: only the part above the horizon lights the plane's upper side (as in
        # the Cornell box, where the ceiling light straddles the plane of the tall box's front face).
        {"name": "area_horizon", "type": "AREA", "shape": "RECTANGLE", "energy": 60.0, "size": 1.0, "size_y": 0.6,
         "location": [0.0, -1.0, 0.15], "rotation_deg": [70.0, 0.0, 0.0]},
        # The same with soft shadows converged over 64 samples: the plane occludes the part of the light below
        # it from the plane's own upper side, which must not darken what Lambert's formula already clipped.
        {"name": "area_horizon_64spp", "type": "AREA", "shape": "RECTANGLE", "energy": 60.0, "size": 1.0,
         "size_y": 0.6, "location": [0.0, -1.0, 0.15], "rotation_deg": [70.0, 0.0, 0.0],
         "bounce": {"samples": 64}},
    ],
}
CASES = {c["name"]: c for c in SPEC["cases"]}


@pytest.fixture(scope="module")
def light_renders(blender, out_root):
    return blender.render_cases("lights_scene.py", SPEC, out_root / "lights", "lights.json", "lights")


# Cycles' area-light radiance per unit power: P / (4 A) in 3.4 (DESIGN.md), P / (pi A) in 4.3 and 5.2 (measured
# here with test_closed_forms_match_cycles: 4/pi = 1.273 brighter for the same power; loading a 3.x file scales
# its area lights' energy by pi/4). Between 3.4 and 4.3 the switch version is not measured; 4.0 is assumed.
AREA_PI_SINCE = (4, 0, 0)


def expected_irradiance(case, matrix, pts, blender_version):
    kind = case["type"]
    if kind == "AREA" and blender_version >= AREA_PI_SINCE:
        return 4.0 / math.pi * expected_irradiance(case, matrix, pts, (3, 4, 0))
    if kind == "POINT":
        return analytic.point(case["energy"], matrix, case["radius"], pts)
    if kind == "SPOT":
        return analytic.spot(case["energy"], matrix, math.radians(case["spot_size_deg"]), case["spot_blend"],
                             case["radius"], pts, cos_falloff=blender_version < (4, 0, 0))
    if kind == "SUN":
        return analytic.sun(case["energy"], matrix, pts)
    if kind == "AREA":
        return analytic.area(case["energy"], case["shape"], case["size"], case.get("size_y", case["size"]),
                             matrix, pts)
    raise ValueError(kind)


# Soft shadows from a light whose plane the receiver's tangent plane cuts: light samples behind the horizon are
# left out of the visibility estimate (shaders/direct/direct.frag), but samples just above it see the receiver
# at a grazing angle in the shadow map. Measured here at 64 samples, with nothing occluding: 3.1 % mean, 5.7 % max
# too dark at the default 0.5-texel normal offset; 2.5 % / 4.4 % at 1.5 texels, which lit Sponza's shaded arcades
# (mean direct light +14 % against Cycles, +7.5 % at 0.5); 3.9 % / 6.5 % before samples behind the horizon were
# left out. A trade-off of normal-offset shadows at grazing angles, both sides measured.
SOFT_SHADOW_HORIZON_TOLERANCE = {"area_horizon_64spp": (0.035, 0.065)}  # mean, max relative error


@pytest.mark.parametrize("name", list(CASES))
def test_light_matches_closed_form(name, blender, light_renders):
    case = CASES[name]
    info = light_renders["cases"][name]
    rgb = layer_pass(read_exr(info["exr"]), "Combined", "RGB")
    assert np.all(np.isfinite(rgb)), "non-finite pixels"
    n = SPEC["resolution"]
    pts = analytic.ortho_pixel_centres(n, SPEC["ortho_scale"], SPEC["center"]).reshape(-1, 3)
    expected = (ALBEDO / math.pi * expected_irradiance(case, info["matrix_world"], pts, blender.version)).reshape(n, n)
    measured = rgb[:, :, 0].astype(np.float64)
    # white light: the three channels agree
    assert np.allclose(rgb[:, :, 1], rgb[:, :, 0], rtol=1e-4, atol=1e-7)
    assert np.allclose(rgb[:, :, 2], rgb[:, :, 0], rtol=1e-4, atol=1e-7)
    peak = expected.max()
    assert peak > 0.0
    mask = expected > MASK_FRACTION * peak
    rel = np.abs(measured - expected)[mask] / expected[mask]
    max_rel = float(rel.max())
    mean_rel = float(rel.mean())
    worst = np.unravel_index(np.argmax(np.where(mask, np.abs(measured - expected) / np.maximum(expected, 1e-30), 0)),
                             expected.shape)
    # dark pixels (below the mask) must be dark in Bounce too: absolute error relative to the peak
    dark_abs = float(np.abs(measured - expected)[~mask].max() / peak) if (~mask).any() else 0.0
    record(f"lights.{name}.max_rel_err", max_rel)
    record(f"lights.{name}.mean_rel_err", mean_rel)
    record(f"lights.{name}.dark_abs_err_over_peak", dark_abs)
    print(f"{name}: max rel err {max_rel:.4%}, mean {mean_rel:.4%} over {mask.sum()} px; "
          f"peak expected {peak:.5g}, measured {measured.max():.5g}; worst px (row, col) {worst}: "
          f"measured {measured[worst]:.5g} expected {expected[worst]:.5g}; dark-pixel error {dark_abs:.3%} of peak")
    mean_tolerance, max_tolerance = SOFT_SHADOW_HORIZON_TOLERANCE.get(name, (TOLERANCE, TOLERANCE))
    assert mean_rel <= mean_tolerance, f"{name}: mean relative error {mean_rel:.3%} > {mean_tolerance:.0%}"
    assert max_rel <= max_tolerance, (f"{name}: max relative error {max_rel:.3%} > {max_tolerance:.0%} "
                                  f"(worst pixel {worst}: {measured[worst]:.5g} vs {expected[worst]:.5g}; "
                                  f"ratio of peaks {measured.max() / peak:.4f})")
    assert dark_abs <= TOLERANCE, f"{name}: pixels below 1 % of the peak are off by {dark_abs:.3%} of the peak"


def test_area_formula_matches_quadrature():
    """The pytest-side reference itself: Lambert's polygon formula against brute-force quadrature."""
    pts = np.array([[0.0, 0.0, 0.0], [0.7, -0.5, 0.0], [-1.5, 1.0, 0.0], [2.5, 2.0, 0.0]])
    for case in (CASES["area_rectangle"], CASES["area_ellipse"], CASES["area_disk"], CASES["area_horizon"]):
        m = analytic.matrix_world(case["location"], case.get("rotation_deg", (0, 0, 0)), case.get("scale", (1, 1, 1)))
        size_y = case.get("size_y", case["size"])
        e1 = analytic.area(case["energy"], case["shape"], case["size"], size_y, m, pts)
        e2 = analytic.area_brute_force(case["energy"], case["shape"], case["size"], size_y, m, pts, n=300)
        np.testing.assert_allclose(e1, e2, rtol=2e-3, err_msg=case["name"])


def test_closed_forms_match_cycles(blender, out_root):
    """The closed forms above against Cycles of the same Blender (the oracle): mean ratio over the lit pixels."""
    spec = dict(SPEC, engine="CYCLES", cycles_samples=64, resolution=32,
                cases=[c for c in SPEC["cases"] if "bounce" not in c])
    record_ = blender.render_cases("lights_scene.py", spec, out_root / "lights-cycles", "lights.json", "lights-cycles")
    n = spec["resolution"]
    pts = analytic.ortho_pixel_centres(n, spec["ortho_scale"], spec["center"]).reshape(-1, 3)
    bad = []
    for case in spec["cases"]:
        info = record_["cases"][case["name"]]
        measured = layer_pass(read_exr(info["exr"]), "Combined", "RGB")[..., 0].astype(np.float64)
        expected = (ALBEDO / math.pi * expected_irradiance(case, info["matrix_world"], pts, blender.version)
                    ).reshape(n, n)
        mask = expected > 0.05 * expected.max()
        ratio = float(measured[mask].sum() / expected[mask].sum())
        record(f"lights.cycles_over_closed_form.{case['name']}", round(ratio, 4))
        print(f"Cycles {blender.version_string} {case['name']}: Cycles / closed form = {ratio:.4f}")
        if abs(ratio - 1.0) > 0.01:
            bad.append((case["name"], ratio))
    assert not bad, f"closed forms disagree with Cycles {blender.version_string}: {bad}"
