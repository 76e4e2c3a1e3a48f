"""Auto (the default method) in F12-style renders: it simulates the bounces a scene's albedo calls for and the
light sources that matter, says what it chose in the `blender -b` output, and writes Indirect and Second Bounce
passes (black where the plan has no bounce). The analysis itself is checked against closed forms in
tests/native/auto_plan_test.cpp."""
import re

import numpy as np
import pytest

from conftest import layer_pass, read_exr, record
from test_hard_inputs import run_case

# case: (method Auto chose, what its plan must say, Indirect's mean over Direct's: (low, high))
CASES = {
    # Each bounce adds 0.8 of the last: the bounces bring more light than the lamp directly.
    "auto_white_room": ("Topology", r"First bounce \d+ % and second \d+ %", (0.8, 3.0)),
    "auto_grey_room": ("Topology", r"Second bounce 0\.\d %: skipped \(below 1\.0 %\)",
                       (0.03, 0.15)),
    "auto_black_room": ("Direct", r"Bounces 0\.\d %: skipped \(below 1\.0 %\)", (0.0, 0.0)),
    "auto_dim_world": (None, r"World 0\.0 %: skipped \(below 1\.0 %\)", None),
}


@pytest.mark.parametrize("case", CASES)
def test_auto_plans_what_the_scene_calls_for(case, blender, out_dir):
    method, pattern, indirect_range = CASES[case]
    result, info = run_case(blender, case, out_dir, "AUTO")
    plans = re.findall(r"^Bounce: Auto: (.+?): (.+)$", result.output, re.M)
    assert len(plans) == 1, f"one plan line expected\n{result.describe()}"
    chosen, plan = plans[0]
    print(f"{case}: {chosen}: {plan}")
    record(f"auto.{case}.plan", plan)
    if method:
        assert chosen == method, plan
    assert re.search(pattern, plan), plan
    error = re.findall(r"^Bounce: error relMSE (\S+) \(estimated: noise (\S+), bias (\S+)\) after 4 samples; 16 samples",
                       result.output, re.M)
    assert len(error) == 1, f"one error line expected\n{result.describe()}"
    total, noise, bias = (float(v) for v in error[0])
    assert total >= 0.0 and noise >= 0.0 and bias >= 0.0
    record(f"auto.{case}.estimated_relmse", total)
    record(f"auto.{case}.bias_relmse", bias)
    channels = read_exr(info["exr"])
    for name in ("Indirect", "Second Bounce"):
        assert np.all(np.isfinite(layer_pass(channels, name))), f"{name} is not finite"
    if indirect_range is None:
        return
    direct = float(layer_pass(channels, "Direct").mean())
    indirect = float(layer_pass(channels, "Indirect").mean())
    record(f"auto.{case}.indirect_over_direct", round(indirect / direct, 4))
    low, high = indirect_range
    assert low <= indirect / direct <= high, f"Indirect {indirect:.4g} over Direct {direct:.4g}; {plan}"


def test_time_limit_ends_a_final_render(blender, out_dir):
    """65,536 samples under a Time Limit of 2 s: the render stops after the samples the limit holds, says how many,
    and Auto fits its samples into 2 s / 65,536 (below any plan's cost: direct light once the cost is known)."""
    result, info = run_case(blender, "auto_time_limit", out_dir, "AUTO")
    plan = re.findall(r"^Bounce: Auto: .+?: (.+)$", result.output, re.M)[0]
    assert "Budget 0 ms per sample" in plan, plan
    samples = re.findall(r"^Bounce: error relMSE \S+ \(estimated: .+?\) after (\d+) samples", result.output, re.M)
    assert len(samples) == 1, result.describe()
    record("auto.time_limit.samples", int(samples[0]))
    assert 1 < int(samples[0]) < 65536
    assert np.all(np.isfinite(layer_pass(read_exr(info["exr"]), "Combined")))


def test_cost_model_is_kept_between_runs(blender, out_dir):
    """A farm renders each frame in a new `blender -b`: with a directory to keep it in (BOUNCE_COST_MODEL_DIR; by
    default the user's cache), Auto's second run plans from the costs the first one measured, where the first had
    to render a plan it had not measured."""
    kept = out_dir / "cost-model"
    plans = []
    for run in range(2):
        result = blender.script("scene_case.py", ["auto_time_limit", out_dir / f"run{run}", "AUTO"],
                                name=f"cost-model-{run}", env={"BOUNCE_COST_MODEL_DIR": str(kept)})
        plans.append(re.findall(r"^Bounce: Auto: .+?: (.+)$", result.output, re.M)[0])
        print(f"run {run}: {plans[-1]}")
    # The first run knows no cost; the second starts from the measured cost of the first run's plan (here the two
    # bounces, over the budget: it drops one).
    assert re.search(r"per sample: cost not measured yet", plans[0]), plans[0]
    assert re.search(r"per sample: (?!cost not measured).*\d+ ms", plans[1]), plans[1]
    assert len(list(kept.glob("cost-model-*.txt"))) == 1, sorted(kept.iterdir())


@pytest.mark.parametrize("method", ["FLC", "SSVP", "TOPOLOGY"])
def test_explicit_methods_estimate_their_bias(method, blender, out_dir):
    """An explicit method's error estimate holds its bias too: its bias class on the bounces it simulates and, for
    FLC's one bounce, the second bounce whole (the grey room's second bounce is under 1 % of the image: small)."""
    result, _ = run_case(blender, "auto_grey_room", out_dir, method)
    error = re.findall(r"^Bounce: error relMSE (\S+) \(estimated: noise (\S+), bias (\S+)\) after \d+ samples",
                       result.output, re.M)
    assert len(error) == 1, f"one error line with a bias expected\n{result.describe()}"
    total, noise, bias = (float(v) for v in error[0])
    record(f"auto.explicit_{method.lower()}.bias_relmse", bias)
    assert bias > 0.0 and noise >= 0.0 and total >= bias
