"""(f) The demo: bpy.ops.bounce.demo_scene() and scripts/demo-scene render a non-black Cornell box."""
import numpy as np

from conftest import REPO, read_exr, record


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
