"""Sponza with and without FLC's divergent pipeline (paper Fig. 7). Usage: /usr/bin/python3 benchmarks/flc_divergent_images.py [--samples 64] [--size 640x360] [--exposure EV] [--indirect-exposure EV]

Run with the host Python (numpy, OpenImageIO, Pillow), it builds Sponza if needed (build/benchmark/scenes/sponza.blend,
as scripts/benchmark does), renders it twice with method FLC through

    scripts/blender -b sponza.blend --python benchmarks/flc_divergent_images.py -- --render OUT_DIR W H SAMPLES

(flc_divergent True, then False; multilayer EXRs, linear), and writes two display-referred PNGs, each with the
divergent pipeline on the left and off on the right: docs/images/flc-sponza-divergent.png (Combined) and
docs/images/flc-sponza-divergent-indirect.png (Indirect). Each pair shares one exposure (clamp, sRGB); the
default exposures are picked from the render with the divergent pipeline so the galleries are visible. Prints the
mean Indirect of both renders and their ratio.
"""
import sys

try:
    import bpy
except ImportError:
    bpy = None


def render_in_blender(argv):
    """Inside Blender: OUT_DIR W H SAMPLES -> OUT_DIR/sponza-flc-divergent-{on,off}.exr."""
    import os
    out, width, height, samples = argv[0], int(argv[1]), int(argv[2]), int(argv[3])
    scene = bpy.context.scene
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    scene.frame_start = scene.frame_end = scene.frame_current = 1
    scene.view_settings.view_transform = "Standard"
    settings = r.image_settings
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    r.use_compositing = r.use_sequencer = False
    r.engine = "BOUNCE"
    scene.bounce.method = "FLC"
    scene.bounce.samples = samples
    for name, divergent in (("on", True), ("off", False)):
        scene.bounce.flc_divergent = divergent
        r.filepath = os.path.join(out, f"sponza-flc-divergent-{name}")
        r.use_file_extension = True
        bpy.ops.render.render(write_still=True)
        print(f"flc_divergent_images: wrote {r.filepath}.exr (flc_divergent={divergent})", flush=True)


def display(linear, exposure):
    """Scene-linear RGB -> 8-bit sRGB after 2^exposure, clamped."""
    import numpy as np
    x = np.clip(linear * 2.0 ** exposure, 0.0, 1.0)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (srgb * 255.0 + 0.5).astype(np.uint8)


def auto_exposure(linear, percentile, target=1.0):
    """The exposure (EV) that maps the `percentile` of the luminance to `target`."""
    import numpy as np
    lum = linear @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)
    level = float(np.percentile(lum[lum > 0], percentile)) if np.any(lum > 0) else 1.0
    return float(np.log2(target / level))


def side_by_side(left, right, labels, path, gap=8):
    import numpy as np
    from PIL import Image, ImageDraw
    h, w = left.shape[:2]
    canvas = np.full((h, 2 * w + gap, 3), 255, dtype=np.uint8)
    canvas[:, :w], canvas[:, w + gap:] = left, right
    image = Image.fromarray(canvas)
    draw = ImageDraw.Draw(image)
    for x, text in ((0, labels[0]), (w + gap, labels[1])):
        box = draw.textbbox((x + 6, 6), text)
        draw.rectangle((box[0] - 3, box[1] - 3, box[2] + 3, box[3] + 3), fill=(0, 0, 0))
        draw.text((x + 6, 6), text, fill=(255, 255, 255))
    path.parent.mkdir(parents=True, exist_ok=True)
    image.save(path)


def main():
    import argparse
    import subprocess
    from pathlib import Path
    import numpy as np
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import images
    import runner

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=64)
    parser.add_argument("--size", default="640x360")
    parser.add_argument("--exposure", type=float, help="EV of the Combined pair (default: automatic)")
    parser.add_argument("--indirect-exposure", type=float, help="EV of the Indirect pair (default: automatic)")
    parser.add_argument("--work", type=Path, default=runner.BUILD / "benchmark" / "flc-divergent")
    parser.add_argument("--images", type=Path, default=runner.REPO / "docs" / "images")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.lower().split("x"))

    runner.ensure_built()
    scene = runner.standard_scene("sponza", runner.BUILD / "benchmark" / "scenes")
    args.work.mkdir(parents=True, exist_ok=True)
    command = [str(runner.REPO / "scripts" / "blender"), "-b", str(scene.blend), "--python-exit-code", "1",
               "--python", str(Path(__file__).resolve()), "--", "--render", str(args.work), str(width),
               str(height), str(args.samples)]
    log = args.work / "render.log"
    with open(log, "w") as out:
        if subprocess.run(command, stdout=out, stderr=subprocess.STDOUT, cwd=runner.REPO).returncode != 0:
            sys.exit(f"flc_divergent_images: Blender failed, see {log}")

    passes = {name: images.read_passes(args.work / f"sponza-flc-divergent-{name}.exr") for name in ("on", "off")}
    combined = {k: p["Combined"][:, :, :3] for k, p in passes.items()}
    indirect = {k: p["Indirect"][:, :, :3] for k, p in passes.items()}
    # Combined: the 85th percentile of the luminance at white, so the sunlit floor clips and the galleries, lit
    # by the bounce, show. Indirect: its 99th percentile at white.
    ev = args.exposure if args.exposure is not None else round(auto_exposure(combined["on"], 85.0) * 2) / 2
    ev_ind = (args.indirect_exposure if args.indirect_exposure is not None
              else round(auto_exposure(indirect["on"], 99.0) * 2) / 2)
    labels = ("with divergent pipeline (flc_divergent on)", "without (flc_divergent off)")
    side_by_side(display(combined["on"], ev), display(combined["off"], ev),
                 [f"Combined, {l}, {ev:+g} EV" for l in labels], args.images / "flc-sponza-divergent.png")
    side_by_side(display(indirect["on"], ev_ind), display(indirect["off"], ev_ind),
                 [f"Indirect, {l}, {ev_ind:+g} EV" for l in labels],
                 args.images / "flc-sponza-divergent-indirect.png")
    means = {k: float(np.mean(v)) for k, v in indirect.items()}
    for k in ("on", "off"):
        print(f"flc_divergent {k:3}: mean Indirect {means[k]:.5g} (RGB {np.mean(indirect[k], axis=(0, 1))}), "
              f"mean Combined {float(np.mean(combined[k])):.5g}")
    ratio = means["on"] / means["off"] if means["off"] > 0 else float("inf")
    print(f"mean Indirect with / without the divergent pipeline: {ratio:.4g}; exposures: Combined {ev:+g} EV, "
          f"Indirect {ev_ind:+g} EV")
    print(f"wrote {args.images / 'flc-sponza-divergent.png'} and {args.images / 'flc-sponza-divergent-indirect.png'}")


if __name__ == "__main__":
    if bpy is not None:
        argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
        if not argv or argv[0] != "--render":
            sys.exit("flc_divergent_images: inside Blender, pass -- --render OUT_DIR W H SAMPLES")
        render_in_blender(argv[1:])
    else:
        main()
