"""(e) Render passes of an F12-equivalent render (bpy.ops.render.render(write_still=True), OPEN_EXR_MULTILAYER):
Combined, Direct, Emission, Albedo, Normal, Depth, with sane values, and nothing else for a direct-light method
(Indirect, VPLs and Second Bounce are registered for the methods that write them: tests/blender/test_ssvp.py)."""
import json

import numpy as np
import pytest

from conftest import layer_pass, read_exr, record

PASSES = {"Combined": "RGBA", "Direct": "RGB", "Emission": "RGB", "Albedo": "RGB", "Normal": "XYZ", "Depth": "Z"}

# OBJ Kd of the Cornell walls and the normals (Blender axes) of their visible sides.
WALLS = {
    "leftWall (red)": ((0.63, 0.065, 0.05), (1.0, 0.0, 0.0)),
    "rightWall (green)": ((0.14, 0.45, 0.091), (-1.0, 0.0, 0.0)),
    "floor + box tops (white)": ((0.725, 0.71, 0.68), (0.0, 0.0, 1.0)),
    "backWall (white)": ((0.725, 0.71, 0.68), (0.0, -1.0, 0.0)),
    "ceiling (white)": ((0.725, 0.71, 0.68), (0.0, 0.0, -1.0)),
}


def erode(mask):
    out = mask.copy()
    out[1:, :] &= mask[:-1, :]
    out[:-1, :] &= mask[1:, :]
    out[:, 1:] &= mask[:, :-1]
    out[:, :-1] &= mask[:, 1:]
    return out


@pytest.fixture(scope="module")
def cornell_passes(blender, cornell_blend, out_root):
    out = out_root / "passes"
    out.mkdir(parents=True, exist_ok=True)
    config = {"engine": "BOUNCE",
              "bounce": {"method": "DIRECT", "samples": 8, "shadow_map_size": 512}}  # else the add-on's defaults
    info, _ = blender.render(config, out / "cornell", cornell_blend, "passes-cornell")
    return read_exr(info["exr"])


def test_all_passes_present_and_finite(cornell_passes):
    for name, comps in PASSES.items():
        p = layer_pass(cornell_passes, name, comps)
        assert np.all(np.isfinite(p)), f"{name} has non-finite values"
    extra = sorted(c for c in cornell_passes if c.split(".")[1] not in PASSES)
    print("channels:", sorted(cornell_passes))
    assert not extra, f"unexpected channels {extra}"


def test_pass_values(cornell_passes):
    ch = cornell_passes
    combined = layer_pass(ch, "Combined", "RGBA")
    direct = layer_pass(ch, "Direct")
    emission = layer_pass(ch, "Emission")
    normal = layer_pass(ch, "Normal", "XYZ")
    depth = layer_pass(ch, "Depth", "Z")[..., 0]
    assert np.all(combined[..., 3] == 1.0), "alpha 1 everywhere (opaque world)"
    assert np.all(emission == 0.0), "no emissive surface in the Cornell box"
    # The default method (Auto) renders direct light only, for now.
    np.testing.assert_allclose(combined[..., :3], direct + emission, atol=1e-5)
    assert np.all(depth > 0.0), "Depth must be positive"
    geometry = depth < 1e9
    assert geometry.mean() > 0.95, "the box fills the frame"
    # camera at y = -6.8 looking +Y: the box spans y in [-1.04, 0.99] -> depth ~5.8 .. 7.9 m
    assert depth[geometry].min() > 5.5 and depth[geometry].max() < 8.0, (depth[geometry].min(), depth[geometry].max())
    # unit length, except at edges where the pixel filter (default width 1 px) averages normals
    lengths = np.linalg.norm(normal[geometry], axis=-1)
    assert lengths.max() < 1.0 + 1e-3
    assert np.mean(np.abs(lengths - 1.0) < 1e-3) > 0.9, "normals are unit length inside faces"
    record("passes.depth_range_m", [round(float(depth[geometry].min()), 3), round(float(depth[geometry].max()), 3)])


def test_albedo_equals_obj_kd(cornell_passes):
    albedo = layer_pass(cornell_passes, "Albedo")
    normal = layer_pass(cornell_passes, "Normal", "XYZ")
    worst = 0.0
    for wall, (kd, n) in WALLS.items():
        mask = erode(normal @ np.array(n) > 0.999)
        assert mask.sum() > 20, f"{wall}: too few pixels ({mask.sum()})"
        err = float(np.abs(albedo[mask] - np.array(kd)).max())
        worst = max(worst, err)
        print(f"{wall}: {mask.sum()} px, max |Albedo - Kd| = {err:.2e}")
        assert err <= 1e-3, f"{wall}: Albedo differs from Kd {kd} by {err:.2e}"
    record("passes.albedo_max_abs_err", worst)


def test_emission_pass(blender, out_dir):
    """An Emission shader (colour (1, 0.5, 0.25), strength 2) appears in Emission and adds to Combined."""
    blender.script("scene_case.py", ["emission", out_dir], name="passes-emission")
    ch = read_exr(json.loads((out_dir / "emission.json").read_text())["exr"])
    emission = layer_pass(ch, "Emission")
    combined = layer_pass(ch, "Combined")
    direct = layer_pass(ch, "Direct")
    glowing = np.all(np.abs(emission - [2.0, 1.0, 0.5]) < 1e-3, axis=-1)
    assert glowing.sum() > 10, "the emissive quad should show radiance (2, 1, 0.5) in Emission"
    assert np.all((emission == 0.0).all(axis=-1) | glowing), "Emission elsewhere should be 0"
    np.testing.assert_allclose(combined, direct + emission, atol=1e-5)
    assert direct.max() > 0.0
