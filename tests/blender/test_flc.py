"""Forward Light Cuts through Blender (F12 path, bpy.ops.render.render): the furnace against its closed form,
seeded determinism on the Cornell box, the quality presets."""
import json

import numpy as np
import pytest

from conftest import assert_ray_checks_reach_every_pair, layer_pass, read_exr, record, thirds_over

# Closed sphere R = 2, albedo 0.8, 1000 W point light at the centre: E0 = P / (4 pi R^2), the first-bounce
# irradiance is rho E0 (a uniformly radiating enclosure), and the outgoing first-bounce radiance, which the
# Indirect pass holds (albedo included), is rho * rho E0 / pi. Eq. 6's cosine-lobe VPLs are exact in
# expectation inside a sphere.
FIRST_BOUNCE = 0.8 * 0.8 * 1000.0 / (4.0 * np.pi * 4.0) / np.pi  # 4.0528
FURNACE_SAMPLES = (1, 16, 256)


@pytest.fixture(scope="module")
def furnace(blender, out_root):
    out = out_root / "flc-furnace"
    out.mkdir(parents=True, exist_ok=True)
    spec = {"resolution": 32, "samples": list(FURNACE_SAMPLES),
            "bounce": {"method": "FLC", "filter_width": 0.0, "shadow_map_size": 512}}
    (out / "spec.json").write_text(json.dumps(spec))
    blender.script("furnace_scene.py", [out / "spec.json", out], name="flc-furnace", timeout=1200)
    exrs = json.loads((out / "furnace.json").read_text())["exr"]
    return {int(samples): read_exr(path) for samples, path in exrs.items()}


@pytest.mark.core
def test_furnace_converges_to_the_first_bounce(furnace):
    errors = {}
    for samples in FURNACE_SAMPLES:
        indirect = layer_pass(furnace[samples], "Indirect")
        assert np.all(np.isfinite(indirect))
        errors[samples] = float(indirect.mean() / FIRST_BOUNCE - 1.0)
        print(f"{samples:4d} samples: Indirect mean {indirect.mean():.4f} vs {FIRST_BOUNCE:.4f}: "
              f"{100 * errors[samples]:+.2f} %, pixel spread {100 * indirect.std() / indirect.mean():.1f} %")
    record("flc.furnace_relative_error", {str(k): round(v, 5) for k, v in errors.items()})
    assert abs(errors[256]) < 0.01, errors
    direct = layer_pass(furnace[256], "Direct")
    np.testing.assert_allclose(direct.mean(), 0.8 / np.pi * 1000.0 / (16.0 * np.pi), rtol=2e-3)


@pytest.fixture(scope="module")
def cornell_seeds(blender, cornell_blend, out_root):
    out = out_root / "flc-seeds"
    out.mkdir(parents=True, exist_ok=True)
    images = {}
    for name, seed in (("a", 3), ("b", 3), ("c", 4)):
        config = {"engine": "BOUNCE", "resolution": 48,
                  "bounce": {"method": "FLC", "samples": 2, "seed": seed, "shadow_map_size": 256}}
        info, _ = blender.render(config, out / name, cornell_blend, f"flc-seed-{name}")
        images[name] = layer_pass(read_exr(info["exr"]), "Indirect")
    return images


@pytest.mark.core
def test_same_seed_same_image_other_seed_other_image(cornell_seeds):
    a, b, c = cornell_seeds["a"], cornell_seeds["b"], cornell_seeds["c"]
    assert a.mean() > 0.0, "the Cornell box has indirect light"
    assert np.array_equal(a, b), "the same seed must give the same image"
    difference = float(np.abs(a - c).mean() / a.mean())
    record("flc.other_seed_mean_difference", round(difference, 4))
    assert difference > 1e-3, "another seed must give another image"


def test_presets_set_the_flc_settings(blender, out_dir):
    code = (
        "import bpy, json\n"
        "props = bpy.context.scene.bounce\n"
        "values = {}\n"
        "for preset in ('DRAFT', 'PREVIEW', 'FINAL'):\n"
        "    bpy.ops.bounce.apply_preset(preset=preset)\n"
        "    values[preset] = {n: getattr(props, n) for n in ('flc_vpls_per_pixel', 'flc_tiling', 'samples',\n"
        "                                                    'viewport_samples', 'flc_blur_radius')}\n"
        f"open({str(out_dir / 'presets.json')!r}, 'w').write(json.dumps(values))\n"
    )
    blender.run(["--python-expr", code], name="flc-presets")
    values = json.loads((out_dir / "presets.json").read_text())
    assert values["DRAFT"]["flc_vpls_per_pixel"] < values["PREVIEW"]["flc_vpls_per_pixel"] < \
        values["FINAL"]["flc_vpls_per_pixel"]
    assert values["DRAFT"]["samples"] < values["FINAL"]["samples"]
    assert values["PREVIEW"] == {"flc_vpls_per_pixel": 256, "flc_tiling": 2, "samples": 64, "viewport_samples": 32,
                                 "flc_blur_radius": 3}


@pytest.mark.slow
def test_sponza_court_lights_its_far_wall_through_the_arcades(blender, sponza_blend, out_dir):
    """Sponza's galleries meet the court through rows of arches, one of which holds a pair's skeleton gate and the
    others are second openings (topology::Gate::needs_ray). The Topology method confirms a crossing through those
    with a shadow ray; Indirect Shadows, with no ray on the GPU, left them out, and the middle third of the view (the
    court's far wall and its galleries) kept 0.85 of the first bounce that shadow rays give it. A march through the
    grid's solid voxels confirms them now (visibility.glsl, topology_voxels_clear): 0.92 on Blender 3.4. Held above
    0.88, which the old rule fails, with room for the other versions' glTF importers. Ray Checks (the default) take
    the rule to FLC with a shadow ray per pair in every third, where the rule alone is 12 % over in the dark lower
    gallery (the left third)."""
    def indirect(name, bounce):
        config = {"engine": "BOUNCE", "bounce": dict(bounce, samples=8, seed=1, bounces=1)}
        info, _ = blender.render(config, out_dir / name, sponza_blend)
        return layer_pass(read_exr(info["exr"]), "Indirect")

    rule = indirect("flc", {"method": "FLC", "flc_visibility": True, "flc_ray_checks": 0.0})
    rays = indirect("rays", {"method": "TOPOLOGY", "topology_visibility": "SHADOW_RAYS"})
    assert np.all(np.isfinite(rule))
    rule_thirds = thirds_over(rule, rays)
    print("Sponza's first bounce, Indirect Shadows over shadow rays, left / middle / right third: "
          + " / ".join(f"{t:.3f}" for t in rule_thirds))
    record("flc.sponza_indirect_shadows_over_shadow_rays_thirds", [round(t, 4) for t in rule_thirds])
    assert rule_thirds[1] > 0.88
    checked = indirect("flc-checked", {"method": "FLC", "flc_visibility": True})
    every_pair = indirect("flc-every-pair", {"method": "FLC", "flc_visibility": True, "flc_ray_checks": 1.0})
    assert_ray_checks_reach_every_pair("Sponza's FLC first bounce", rule, checked, every_pair,
                                       "flc.sponza_ray_checks_over_every_pair_thirds")
