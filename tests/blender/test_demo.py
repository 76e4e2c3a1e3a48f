"""(f) The demo: bpy.ops.bounce.demo_scene() and scripts/demo-scene render a non-black Cornell box."""
import json
import shutil

import numpy as np
import pytest

from conftest import CHROOT, REPO, read_exr, record


def check_cornell_image(path):
    ch = read_exr(path)
    names = sorted(ch)
    r = next(ch[n] for n in names if n.endswith("Combined.R") or n == "R")
    g = next(ch[n] for n in names if n.endswith("Combined.G") or n == "G")
    b = next(ch[n] for n in names if n.endswith("Combined.B") or n == "B")
    rgb = np.stack([r, g, b], axis=-1)
    assert np.all(np.isfinite(rgb))
    assert rgb.mean() > 0.01, f"the demo render is (nearly) black: mean {rgb.mean():.4g}"
    h, w, _ = rgb.shape
    left, right = rgb[h // 4: 3 * h // 4, : w // 8], rgb[h // 4: 3 * h // 4, -w // 8:]
    # the red wall on the left, the green wall on the right
    assert left[..., 0].mean() > 2 * left[..., 1].mean(), "left wall should be red"
    assert right[..., 1].mean() > 1.5 * right[..., 0].mean(), "right wall should be green"
    return rgb


def test_demo_operator_renders(blender, out_dir):
    result = blender.run(["--python-expr", "import bpy; bpy.ops.bounce.demo_scene(resolution=64)",
                          "-o", f"{out_dir}/demo_####", "-F", "OPEN_EXR", "-f", "1"], name="demo-operator")
    assert "Bounce" in result.output
    rgb = check_cornell_image(out_dir / "demo_0001.exr")
    record("demo.operator_mean", round(float(rgb.mean()), 5))
    record("demo.operator_seconds", round(result.seconds, 1))


def test_demo_scene_script_renders(blender, out_dir):
    blend = out_dir / "demo.blend"
    blender.run_command([REPO / "scripts" / "demo-scene", blend, "64"], name="demo-scene", in_chroot=True)
    assert blend.is_file()
    blender.run([blend, "-o", f"{out_dir}/frame_####", "-F", "OPEN_EXR", "-f", "1"], factory=False,
                name="demo-scene-render")
    check_cornell_image(out_dir / "frame_0001.exr")


@pytest.mark.slow
def test_demo_operator_shows_the_box_rendered(blender, out_dir):
    """Render > Bounce Demo turns the 3D view it runs from (or, from another editor such as the top bar, the window's largest one) to the
    demo's camera in Rendered shading: from the default view a new user would see a dark box on a black world."""
    if shutil.which("xvfb-run") is None and not CHROOT:
        pytest.skip("xvfb-run is not installed (package xvfb)")
    blend = out_dir / "start.blend"  # a .blend: without one the splash screen covers the view
    blender.run(["--python-expr", f"import bpy; bpy.ops.wm.save_as_mainfile(filepath={str(blend)!r})"],
                name="demo-view-start")
    capture = "screenshot" if blender.version < (4, 0, 0) else "xwd"
    command = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", str(REPO / "scripts" / "blender"), str(blend),
               "--python", str(REPO / "tests" / "blender" / "scripts" / "demo_view_check.py"), "--", str(out_dir),
               capture]
    result = blender.run_command(command, name="demo-view", in_chroot=True, check=False)
    path = out_dir / "result.json"
    assert path.is_file(), result.describe()
    seen = json.loads(path.read_text())
    assert "error" not in seen, seen["error"]
    rendered_camera = {"shading": "RENDERED", "perspective": "CAMERA"}
    assert seen["from_view"]["largest_view"] == rendered_camera
    assert seen["from_elsewhere"]["largest_view"] == rendered_camera
    assert seen["from_elsewhere"]["scene"].startswith("Bounce Demo")
    assert seen["drawn"], "the Rendered view drew no frame within a minute"
