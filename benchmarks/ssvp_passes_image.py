"""The README's picture of SSVP's passes on the built-in demo scene. Usage (host Python: numpy, OpenImageIO,
matplotlib): /usr/bin/python3 benchmarks/ssvp_passes_image.py [--size 320] [--samples 16] [--out PNG]

Renders the demo Cornell box with method SSVP through scripts/blender and tests/blender/scripts/render.py twice
(`samples` samples, and one sample for the debug view, whose dots would blur over samples), then writes
Combined, Indirect (x2), Second Bounce (x4) and the VPLs pass over the dimmed image (default
docs/images/ssvp-passes.png), sRGB-clamped.
"""
import argparse
import json
import subprocess
import tempfile
from pathlib import Path

import numpy as np

import images
from display import srgb
import report

REPO = Path(__file__).resolve().parent.parent


def render(out, name, size, samples):
    config = {"out": str(out / name), "engine": "BOUNCE", "scene": "demo", "info": str(out / f"{name}.json"),
              "resolution": size, "bounce": {"method": "SSVP", "samples": samples}}
    (out / f"{name}.cfg.json").write_text(json.dumps(config))
    subprocess.run([str(REPO / "scripts" / "blender"), "-b", "--python-exit-code", "1", "--python",
                    str(REPO / "tests" / "blender" / "scripts" / "render.py"), "--", str(out / f"{name}.cfg.json")],
                   check=True, stdout=subprocess.DEVNULL)
    return images.read_passes(json.loads((out / f"{name}.json").read_text())["exr"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=320)
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--out", type=Path, default=REPO / "docs" / "images" / "ssvp-passes.png")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        converged = render(Path(folder), "converged", args.size, args.samples)
        one = render(Path(folder), "one", args.size, 1)
    dots = one["VPLs"][..., :3]
    debug = np.where(dots.max(axis=-1, keepdims=True) > 0, dots, 0.35 * one["Combined"][..., :3])
    panels = [(converged["Combined"][..., :3], f"Combined ({args.samples} samples)"),
              (2 * converged["Indirect"], "Indirect, both bounces (x2)"),
              (4 * converged["Second Bounce"], "Second Bounce (x4)"),
              (debug, "VPLs by cluster, centres large (1 sample)")]
    plt = report.pyplot()
    fig, axes = plt.subplots(1, len(panels), figsize=(4 * len(panels), 4.3))
    for ax, (image, title) in zip(axes, panels):
        ax.imshow(srgb(image))
        ax.set_title(title, fontsize=11)
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(args.out, dpi=80)
    print(f"wrote {args.out}: mean Indirect {converged['Indirect'].mean():.4f}, "
          f"Second Bounce {converged['Second Bounce'].mean():.4f}")


if __name__ == "__main__":
    main()
