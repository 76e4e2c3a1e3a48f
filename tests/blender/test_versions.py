"""(c) Same image across versions: render the demo Cornell box with fixed settings and store it as
<build>/version-images/<blender version>.exr; compare with the images other Blender versions stored (the
last configuration that runs sees them all; scripts/test also runs version_images.py at the end)."""
import shutil

import pytest

import version_images
from conftest import BUILD, record

SETTINGS = {"method": "FLC", "samples": 16, "seed": 0, "filter_width": 1.0, "shadow_map_size": 1024}
VERSION_DIR = BUILD / "version-images"
DEMO = {"engine": "BOUNCE", "scene": "demo", "resolution": 128, "bounce": SETTINGS}


@pytest.fixture(scope="module")
def version_image(blender, out_root):
    out = out_root / "version-image"
    out.mkdir(parents=True, exist_ok=True)
    info, _ = blender.render(DEMO, out / "demo", name="version-image")
    VERSION_DIR.mkdir(parents=True, exist_ok=True)
    target = VERSION_DIR / f"{blender.version_string}.exr"
    shutil.copyfile(info["exr"], target)
    return target


def test_render_is_repeatable(blender, version_image, out_dir):
    """Same scene + same seed gives the same image on the same machine (DESIGN.md contract)."""
    info, _ = blender.render(DEMO, out_dir / "again", name="version-image-again")
    a = version_images.load(version_image)
    b = version_images.load(info["exr"])
    diff = version_images.compare(a, b)
    print("re-render difference:", diff)
    assert all(mx == 0.0 for mx, _ in diff.values()), diff


def test_compare_with_other_versions(blender, version_image):
    imgs = version_images.images(VERSION_DIR)
    others = [v for v in imgs if v != blender.version_string]
    if not others:
        pytest.skip(f"no image from another Blender version in {VERSION_DIR} yet")
    mine = imgs[blender.version_string]
    failures = []
    for other in others:
        for name, (mx, mn) in version_images.compare(imgs[other], mine).items():
            record(f"versions.{other}_vs_{blender.version_string}.{name}.max_over_peak", mx)
            record(f"versions.{other}_vs_{blender.version_string}.{name}.mean_over_mean", mn)
            print(f"{other} vs {blender.version_string} {name}: max |d| {mx:.3e} of peak, mean |d| {mn:.3e} of mean")
            if name == "Combined" and (mx > version_images.MAX_TOL or mn > version_images.MEAN_TOL):
                failures.append((other, name, mx, mn))
    assert not failures, failures
