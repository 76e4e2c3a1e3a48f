"""The Blender-level fuzz stage (issue 18): random scenes through the add-on (scripts/fuzz_scenes.py), all in one
Blender. Passes when Blender exits normally, prints no Python traceback, every case either writes an image with
no NaN/Inf in any pass or is refused with a message, no frame is silently black where a sun casting no shadow
faces a visible surface (the native fuzzer's rule), and every case ran.

BOUNCE_BLENDER_FUZZ_SEED (default 1) and BOUNCE_BLENDER_FUZZ_CASES (default 40: bounded for CI, about a minute)
choose the cases; a long run sets more, e.g. `BOUNCE_BLENDER_FUZZ_CASES=500 scripts/test --quick -- -k fuzz`.
A failing case replays alone with
`scripts/blender -b --factory-startup --python tests/blender/scripts/fuzz_scenes.py -- SEED CASE 1 OUT_DIR`.
"""
import json
import os
import re

import numpy as np
import pytest

from conftest import read_exr, record

SEED = int(os.environ.get("BOUNCE_BLENDER_FUZZ_SEED", "1"))
CASES = int(os.environ.get("BOUNCE_BLENDER_FUZZ_CASES", "40"))


def sun_must_light(suns, channels):
    """The silent-black-frame rule of the native fuzzer (tests/native/scene_fuzz.h, sun_must_light): a sun of
    positive finite power and colour that casts no shadow adds to every surface whose normal faces it, whatever
    else the scene holds, so a pixel of albedo > 0.01 whose Normal is within 84 degrees of it must get Direct
    light."""
    albedo = np.stack([channels[f"ViewLayer.Albedo.{c}"] for c in "RGB"], axis=-1)
    normal = np.stack([channels[f"ViewLayer.Normal.{c}"] for c in "XYZ"], axis=-1)
    for towards, energy, colour in suns:
        if not (np.isfinite(energy) and energy > 0.0 and min(colour) > 0.0 and np.linalg.norm(towards) > 1e-3):
            continue
        facing = normal @ (np.asarray(towards) / np.linalg.norm(towards)) > 0.1
        if np.any((albedo.max(axis=-1) > 0.01) & facing):
            return True
    return False


def test_random_scenes_render_finite_or_say_why(blender, out_dir):
    result = blender.script("fuzz_scenes.py", [SEED, 0, CASES, out_dir], name="fuzz", check=False,
                            python_exit_code=False, timeout=60 + 30 * CASES)
    started = [int(n) for n in re.findall(r"^case (\d+) start$", result.output, re.M)]
    done = set(int(n) for n in re.findall(r"^case (\d+) done$", result.output, re.M))
    unfinished = [n for n in started if n not in done]
    replay = (f"replay: scripts/blender -b --factory-startup --python tests/blender/scripts/fuzz_scenes.py -- "
              f"{SEED} {unfinished[0] if unfinished else 0} 1 /tmp/fuzz")
    if result.returncode != 0 or unfinished:
        pytest.fail(f"Blender exited with {result.returncode} in case {unfinished}\n{replay}\n{result.describe()}",
                    pytrace=False)
    assert "Traceback" not in result.output, f"a Python traceback in the output\n{result.describe()}"

    records = [json.loads(line) for line in (out_dir / "cases.jsonl").read_text().splitlines()]
    assert [r["case"] for r in records] == list(range(CASES))
    refused, black_direct, judged, methods = [], 0, 0, {}
    for r in records:
        methods[r["method"]] = methods.get(r["method"], 0) + 1
        if r["exr"] is None:
            assert r["render_error"], f"case {r['case']}: no image and no message\n{replay}"
            refused.append(r["render_error"])
            continue
        channels = read_exr(r["exr"])
        bad = {name: int((~np.isfinite(a)).sum()) for name, a in channels.items() if not np.all(np.isfinite(a))}
        assert not bad, f"case {r['case']}: non-finite values {bad}"
        direct = [a for name, a in channels.items() if ".Direct." in name]
        must_light = sun_must_light(r["unshadowed_suns"], channels)
        judged += must_light
        if direct and all(np.all(a == 0.0) for a in direct):
            black_direct += 1
            assert not must_light, \
                f"case {r['case']}: silent black frame: a sun casting no shadow faces a visible surface\n{replay}"
    print(f"seed {SEED}: {CASES} cases in {result.seconds:.1f} s; methods {methods}; {len(refused)} refused "
          f"({sorted(set(refused))}); {black_direct} with an all-zero Direct pass, {judged} judged (an unshadowed "
          "sun faces a visible surface: shadows, ranges and black lights make the others legitimate)")
    record("blender_fuzz", {"seed": SEED, "cases": CASES, "seconds": round(result.seconds, 1),
                            "refused": len(refused), "black_direct": black_direct, "judged": judged})
