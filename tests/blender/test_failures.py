"""(issue 18) Failure injection in Blender: no EGL display, GPU memory running out, Embree that cannot start.
Each ends the render with an error report that says what failed (no crash, no traceback, no silent black
image), and the next render in the same Blender works (tests/blender/scripts/fault_case.py).
"""
import json
import re

import numpy as np

from conftest import layer_pass, read_exr

REPORTS = {
    "egl": r"Error: Bounce: no EGL display for platform",
    "gl-oom": r"Error: Bounce: allocating a \d+x\d+ texture: out of GPU memory \(lower the resolution",
    "embree": r"Error: Bounce: Embree could not start \(rtcNewDevice failed.*Shadow Method: Shadow Maps",
}


def test_failures_are_reported_and_the_next_render_works(blender, out_dir):
    result = blender.script("fault_case.py", [out_dir], name="faults")
    assert "Traceback" not in result.output, result.describe()
    record = json.loads((out_dir / "faults.json").read_text())
    for fault, pattern in REPORTS.items():
        during = result.output.split(f"fault {fault}: begin")[1].split(f"fault {fault}: end")[0]
        print(f"{fault}: {[line for line in during.splitlines() if line.startswith('Error')]}")
        assert re.search(pattern, during), f"{fault}: no report matching {pattern!r}\n{during}"
        assert record[fault]["after"], f"{fault}: the render after the failure wrote no image\n{result.describe()}"
        combined = layer_pass(read_exr(record[fault]["after"]), "Combined", "RGBA")[..., :3]
        assert np.all(np.isfinite(combined)) and combined.mean() > 0.1, \
            f"{fault}: the render after the failure is black or not finite (mean {combined.mean()})"
