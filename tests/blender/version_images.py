#!/usr/bin/python3
"""(c) Same image across Blender versions: compare the Bounce renders of the demo Cornell box that
test_versions.py stored under <build>/version-images/<blender version>.exr (one per Blender: host 3.4, trixie
4.3, sid 5.2).

    /usr/bin/python3 tests/blender/version_images.py [DIR]     prints a table; exit 1 beyond the tolerance

Differences come only from the exported scene (Blender's own data and the add-on's code paths per version) and
from llvmpipe (Mesa 22.3 / 25.0 / 26.2 compile the shaders with different LLVMs); the native core is the same
build. Tolerance: mean |difference| <= 0.1 % of the image mean, max <= 2 % of the image's peak.
"""
import itertools
import os
import sys
from pathlib import Path

import numpy as np

MEAN_TOL = 1e-3
MAX_TOL = 2e-2
PASSES = ("Combined", "Albedo", "Normal", "Depth")


def load(path):
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise RuntimeError(f"cannot open {path}")
    spec = inp.spec()
    pixels = np.asarray(inp.read_image(oiio.FLOAT)).reshape(spec.height, spec.width, spec.nchannels)
    inp.close()
    return {name: pixels[:, :, i] for i, name in enumerate(spec.channelnames)}


def images(directory):
    return {p.stem: load(p) for p in sorted(Path(directory).glob("*.exr"))}


def compare(a, b):
    """{pass: (max abs diff / peak, mean abs diff / mean)} over the channels both images have."""
    out = {}
    for name in PASSES:
        chans = sorted(c for c in a if c.split(".")[-2] == name and c in b and not c.endswith(".A"))
        if not chans:
            continue
        x = np.stack([a[c] for c in chans], axis=-1).astype(np.float64)
        y = np.stack([b[c] for c in chans], axis=-1).astype(np.float64)
        if name == "Depth":  # background depth is 1e10
            keep = (x < 1e9) & (y < 1e9)
            x, y = x[keep], y[keep]
        d = np.abs(x - y)
        peak = max(np.abs(x).max(), 1e-30)
        mean = max(np.abs(x).mean(), 1e-30)
        out[name] = (float(d.max() / peak), float(d.mean() / mean))
    return out


def table(imgs):
    rows = []
    for (va, a), (vb, b) in itertools.combinations(sorted(imgs.items()), 2):
        for name, (mx, mn) in compare(a, b).items():
            rows.append((va, vb, name, mx, mn))
    return rows


def main():
    directory = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.environ.get("BOUNCE_BUILD_DIR") or Path(__file__).resolve().parents[2] / "build", "version-images")
    imgs = images(directory)
    print(f"version images in {directory}: {', '.join(imgs) or 'none'}")
    if len(imgs) < 2:
        print("fewer than two versions: nothing to compare")
        return 0
    failed = 0
    print(f"{'A':>8} {'B':>8} {'pass':>9} {'max|d|/peak':>12} {'mean|d|/mean':>13}")
    for va, vb, name, mx, mn in table(imgs):
        bad = name == "Combined" and (mx > MAX_TOL or mn > MEAN_TOL)
        failed += bad
        print(f"{va:>8} {vb:>8} {name:>9} {mx:12.3e} {mn:13.3e}{'  TOO DIFFERENT' if bad else ''}")
    print(f"cross-version comparison: {'FAILED' if failed else 'ok'} (tolerance mean {MEAN_TOL:.1%}, "
          f"max {MAX_TOL:.0%} of peak, Combined)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
