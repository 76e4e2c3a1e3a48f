"""The error budget of scripts/benchmark (suites budget and budget-time): how far each of Bounce's methods is from
the Cycles oracle in each light path, and what error each buys in how much time.

budget: per scene and configuration, each component of the render against its part of the Cycles references
with one and two diffuse bounces (images.py; the combined against as many bounces as the method simulates):
the ratio of means over the image and its thirds, relMSE per pixel and after a 4x4 box downsample; a picture
of the signed error per component; a bias check; for the closed room of two-rooms-wall, the light that leaks
into it through the wall.
budget-time: the downsampled relMSE of Combined against the two-bounce oracle over render wall time, for each
configuration at 1-64 samples and Cycles at 1-256; which method is best within 1 s and 2 s and whether it beats
Cycles there; and each method's convergence (the Indirect's relMSE over samples, with its log-log slope).
"""
import math
import statistics

import numpy as np

import display
import images
import report

COMPONENTS = ("direct", "first", "second", "indirect", "combined")
PICTURE_COMPONENTS = ("direct", "first", "second", "combined")
BIAS_RANGE = (0.9, 1.1)
BUDGETS_S = (1.0, 2.0)
# Configurations: each a method and its settings (all others at their defaults). FLC with and without its
# Indirect Shadows (flc_visibility, on by default); the Topology method also with exact shadow rays for its VPLs
# (a quarter of them, as each costs one ray per pixel), which splits its error between the VPLs and its
# visibility rule. A configuration whose setting the build lacks is skipped and said so.
PAPER_FLC = {"method": "FLC", "flc_visibility": False, "flc_cosine_lobe": True,  # as printed: Eq. 6, no visibility,
             "flc_vpl_candidates": 1}  # VPLs by area alone
CONFIGS = [{"method": "AUTO"}, {"method": "DIRECT"}, PAPER_FLC, {"method": "FLC", "flc_visibility": True},
           {"method": "SSVP", "bounces": 2}, {"method": "TOPOLOGY", "bounces": 2}, {"method": "TOPOLOGY", "bounces": 1},
           {"method": "TOPOLOGY", "bounces": 1, "topology_visibility": "SHADOW_RAYS", "topology_vpls": 256}]
# The closed room of two-rooms-wall (its default camera) and the same scene from the lit room.
CLOSED_ROOM, LIT_ROOM = "two-rooms-wall", "two-rooms-wall:CameraA"


def _config_rows(ctx, records):
    """Summary rows of the measured renders, each with its configuration's label ('config')."""
    keys = ["scene", "engine", "width", "height", "method", *[k for k in ctx.swept if k != "samples"], "samples"]
    rows = ctx.summarise(records, keys)
    for row in rows:
        row["config"] = "Cycles" if row["engine"] == "CYCLES" else report.config_label(
            {k: row.get(k) for k in keys[4:-1]})
    return rows


def _scenes(rows):
    return list(dict.fromkeys(r["scene"] for r in rows))


def _skipped_lines(ctx):
    return ["Configurations not run: " + "; ".join(ctx.skipped) + ".", ""] if ctx.skipped else []


def _exempt(config):
    """FLC without indirect visibility leaks light by design (the paper's model): reported, not held to the rule."""
    return config == report.config_label(PAPER_FLC)


def _cell(row, part, fields):
    values = [row.get(f"{part}_{f}") for f in fields]
    if all(v is None or (isinstance(v, float) and math.isnan(v)) for v in values):
        return "-"
    return " / ".join(report.fmt(v) if v is not None else "-" for v in values)


def budget_report(ctx, records, _stages):
    """Per scene a table of each component's ratio and relMSE per configuration, a picture of the signed errors;
    then the bias check and the closed room's leak."""
    rows = _config_rows(ctx, records)
    lines = _skipped_lines(ctx)
    columns = ["config", "oracle k"]
    for part in COMPONENTS:
        columns += [f"{part} ratio", f"{part} L / M / R", f"{part} relMSE / 4x4"]
    columns += ["combined rel. RMSE", "indirect rel. RMSE"]
    flags = []
    for scene in _scenes(rows):
        mine = [r for r in rows if r["scene"] == scene]
        table = []
        for row in mine:
            out = {"config": row["config"], "oracle k": row.get("oracle_bounces"),
                   "combined rel. RMSE": row.get("combined_rel_rmse"),
                   "indirect rel. RMSE": row.get("indirect_rel_rmse")}
            for part in COMPONENTS:
                out[f"{part} ratio"] = _cell(row, part, ["ratio"])
                out[f"{part} L / M / R"] = _cell(row, part, [f"ratio_{t}" for t in images.THIRDS])
                out[f"{part} relMSE / 4x4"] = _cell(row, part, ["rel_mse", "rel_mse_4x4"])
                flags += _bias_flags(scene, row, part)
            table.append(out)
        size = f"{mine[0]['width']}x{mine[0]['height']}"
        picture = f"{ctx.suite.name}-{scene.replace(':', '-')}.png"
        lines += [f"### {scene} ({size}, {report.fmt(mine[0].get('samples'))} samples)", "",
                  report.markdown(table, columns), "", f"Signed error per component: {picture}", ""]
        _signed_error_picture([r for r in records if r.get("role") == "measure" and r["scene"] == scene and
                               r.get("exr") and r.get("reference_exrs")], ctx.out / picture,
                              f"{scene}: Bounce - Cycles per component ({ctx.title})")
    lines += ["### Bias check", "",
              f"Every (scene, configuration, component) whose ratio of means, overall or in a third of the image, "
              f"lies outside [{BIAS_RANGE[0]}, {BIAS_RANGE[1]}], or that is not black where Cycles is "
              "(FLC without indirect visibility is listed but not held to the rule):", ""]
    lines += flags or ["- none"]
    lines += ["", *_leak_lines(rows)]
    _ratio_overview(rows, ctx.out / f"{ctx.suite.name}.png", ctx.title)
    return "\n".join(lines) + _NOTE


def _ratio_overview(rows, path, title):
    """Per scene, each configuration's ratio of means per component (dots, log scale) with the range over the
    image thirds (lines) and the bias check's band; ratios that are inf or nan (black references) are left out."""
    plt = report.pyplot()
    scenes = [s for s in _scenes(rows) if any(math.isfinite(r.get(f"{p}_ratio", math.nan)) for r in rows
                                              if r["scene"] == s for p in COMPONENTS)]
    if not scenes:
        return
    configs = list(dict.fromkeys(r["config"] for r in rows))
    columns = min(3, len(scenes))
    rows_of_panels = -(-len(scenes) // columns)
    fig, axes = plt.subplots(rows_of_panels, columns, figsize=(5.5 * columns, 4.2 * rows_of_panels), squeeze=False)
    for ax in axes.flat[len(scenes):]:
        ax.axis("off")
    width = 0.8 / len(configs)
    for ax, scene in zip(axes.flat, scenes):
        for i, config in enumerate(configs):
            row = next((r for r in rows if r["scene"] == scene and r["config"] == config), {})
            for j, part in enumerate(COMPONENTS):
                ratio = row.get(f"{part}_ratio", math.nan)
                if not math.isfinite(ratio):
                    continue
                x = j + (i - (len(configs) - 1) / 2) * width
                ax.plot(x, ratio, marker="o", color=f"C{i}", label=config)
                thirds = [row.get(f"{part}_ratio_{t}", math.nan) for t in images.THIRDS]
                thirds = [t for t in thirds if math.isfinite(t) and t > 0]
                if thirds:
                    ax.plot([x, x], [min(thirds), max(thirds)], color=f"C{i}", linewidth=1.5)
        ax.axhspan(*BIAS_RANGE, color="tab:green", alpha=0.15)
        ax.axhline(1.0, color="k", linewidth=0.8)
        ax.set_yscale("log")
        ax.set_xticks(range(len(COMPONENTS)), COMPONENTS, fontsize=8)
        ax.set_ylabel("mean(Bounce) / mean(Cycles)")
        ax.set_title(scene, fontsize=10)
        handles, labels = ax.get_legend_handles_labels()
        unique = dict(zip(labels, handles))
        ax.legend(unique.values(), unique.keys(), fontsize=7)
    report.save(fig, path, title)


_NOTE = """

Components against the Cycles oracle (references with one and two diffuse bounces; DESIGN.md, "Cycles as an
oracle"): direct = Direct vs DiffCol x DiffDir; first = Indirect - Second Bounce (Indirect alone for a
one-bounce method) vs DiffCol x DiffInd(1); second = Second Bounce vs DiffCol x (DiffInd(2) - DiffInd(1));
indirect = Indirect vs DiffCol x DiffInd(k); combined = Combined vs DiffCol x (DiffDir + DiffInd(k)) + Emit, with
k ('oracle k') the bounces the method simulates (0 for DIRECT, 1 for FLC, the bounces setting otherwise). A
method without a Second Bounce pass and two bounces (Topology today) has its bounces measured together only
(indirect). ratio = mean(Bounce) / mean(Cycles) over the pixels that see geometry (L / M / R: left, middle and
right third of the columns; inf where Cycles is black and Bounce is not, '-' where both are); relMSE =
mean((x - r)^2 / (r^2 + 0.01)) per pixel / after a 4x4 box downsample of both images; rel. RMSE as the other
suites. A scene NAME@SOURCES is NAME lit by those light source classes alone (lamps, world, emission), in both
renderers: light adds up, so its components are their share of NAME's (NAME@world's direct is the world's direct
light, its first bounce the world's share of the first bounce)."""


def _bias_flags(scene, row, part):
    """The bias-check lines of one component of one row (none when it holds)."""
    if f"{part}_ratio" not in row:
        return []
    config, note = row["config"], " (not held to the rule)" if _exempt(row["config"]) else ""
    ratios = {"overall": row[f"{part}_ratio"], **{t: row.get(f"{part}_ratio_{t}") for t in images.THIRDS}}
    if math.isinf(ratios["overall"]):  # Cycles is black: any light is a leak
        return [f"- {scene}, {config}, {part}: Cycles is black here, Bounce's mean is "
                f"{report.fmt(row.get(f'{part}_mean'))}{note}"]
    outside = {k: v for k, v in ratios.items() if v is not None and not math.isnan(v)
               and not BIAS_RANGE[0] <= v <= BIAS_RANGE[1]}
    if not outside:
        return []
    where = ", ".join(f"{k} {v:.3g}" for k, v in outside.items())
    return [f"- {scene}, {config}, {part}: ratio {where}{note}"]


def _leak_lines(rows):
    """The closed room's mean Indirect over the lit room's, per configuration and for Cycles."""
    closed = {r["config"]: r for r in rows if r["scene"] == CLOSED_ROOM}
    lit = {r["config"]: r for r in rows if r["scene"] == LIT_ROOM}
    table = []
    for config in [c for c in closed if c in lit and "indirect_mean" in closed[c]]:
        b, a = closed[config]["indirect_mean"], lit[config]["indirect_mean"]
        table.append({"": config, "room B (closed)": b, "room A (lit)": a, "B / A": b / a if a > 0 else float("nan")})
    # Cycles' values: the two-bounce reference's, which any configuration measured with two bounces carries.
    both = [(closed[c], lit[c]) for c in closed if c in lit and closed[c].get("oracle_bounces") == 2
            and "indirect_reference_mean" in closed[c]]
    if both:
        b, a = both[0][0]["indirect_reference_mean"], both[0][1]["indirect_reference_mean"]
        table.append({"": "Cycles, 2 bounces", "room B (closed)": b, "room A (lit)": a,
                      "B / A": b / a if a > 0 else float("nan")})
    if not table:
        return []
    return ["### Light through the wall (two-rooms-wall)", "",
            "Mean Indirect over the pixels that see geometry, room B seen from its camera over room A seen from "
            "CameraA; no path joins the rooms, so Cycles' room B is black and all of Bounce's is leak:", "",
            report.markdown(table, ["", "room B (closed)", "room A (lit)", "B / A"])]


def _signed_error_picture(records, path, title):
    """Rows: Cycles' components (display-referred, one exposure for the row), then each configuration's
    Bounce - Cycles per component, averaged over RGB (red: too bright), one symmetric scale per column."""
    if not records:
        return
    plt = report.pyplot()
    reference = _reference(records[0])
    diffs = []
    for record in records:
        k = record["oracle_bounces"]
        image, oracle = _measured(record), images.up_to(reference, k)
        diffs.append({part: (image[part] - oracle[part]).mean(axis=-1) for part in PICTURE_COMPONENTS
                      if part in image and part in oracle})
    scales = {part: max([float(np.percentile(np.abs(d[part]), 99)) for d in diffs if part in d] + [1e-6])
              for part in PICTURE_COMPONENTS}
    fig, axes = plt.subplots(len(records) + 1, len(PICTURE_COMPONENTS),
                             figsize=(3.6 * len(PICTURE_COMPONENTS), 2.3 * (len(records) + 1) + 0.5), squeeze=False)
    for ax, part in zip(axes[0], PICTURE_COMPONENTS):
        # Each its own exposure (in the title, from its lit pixels): the bounces are much darker than the direct
        # light, which may light only a few pixels.
        lit = reference[part][reference[part] > 0]
        level = float(np.percentile(lit, 98)) if reference[part].mean() > images.BLACK_LEVEL else 0.0
        exposure = 1.0 / level if level > 0 else 1.0
        ax.imshow(display.srgb(reference[part] * exposure))
        ax.set_title(f"Cycles {part}" + (", 2 bounces" if part == "combined" else "") +
                     (f" (x{exposure:.3g})" if level > 0 else " (black)"), fontsize=8)
    for row_axes, record, diff in zip(axes[1:], records, diffs):
        label = report.config_label(record.get("params") or {})
        for ax, part in zip(row_axes, PICTURE_COMPONENTS):
            if part not in diff:
                why = "bounces not apart:\nno Second Bounce pass" if record["oracle_bounces"] >= 2 else \
                    f"no {part} bounce simulated"
                ax.text(0.5, 0.5, f"{label}:\n{why}", ha="center", va="center", fontsize=8)
                continue
            shown = ax.imshow(diff[part], cmap="RdBu_r", vmin=-scales[part], vmax=scales[part])
            ax.set_title(f"{label}: {part}, ratio {report.fmt(record.get(f'{part}_ratio'))}", fontsize=8)
            fig.colorbar(shown, ax=ax, fraction=0.046, pad=0.02)
    for ax in axes.flat:
        ax.set_xticks([])
        ax.set_yticks([])
    report.save(fig, path, title)


def _reference(record):
    """The Cycles reference a record was measured against, from its reference EXRs."""
    return images.reference_from([images.load(p) for p in record["reference_exrs"]])


def _measured(record):
    """A render's components as the budget measured them."""
    return images.bounces_apart(images.load(record["exr"]), record["oracle_bounces"])


# budget-time: combined against the two-bounce oracle (what every method and Cycles are compared by), indirect
# against the method's own number of bounces (its convergence).
TIME_ERROR, CONVERGENCE_ERROR = "full_combined_rel_mse_4x4", "indirect_rel_mse_4x4"


def budget_time_report(ctx, records, _stages):
    """Per scene: the error of each configuration and sample count against its wall time beside Cycles' curve; the
    best method within each budget; the first render's one-off cost; the convergence of each method."""
    rows = [r for r in _config_rows(ctx, records) if TIME_ERROR in r]
    lines = _skipped_lines(ctx)
    plt = report.pyplot()
    scenes = _scenes(rows)
    fig, axes = plt.subplots(2, len(scenes), figsize=(5.5 * len(scenes), 15.0), squeeze=False)
    colours = {config: f"C{i}" for i, config in enumerate(dict.fromkeys(r["config"] for r in rows
                                                                        if r["config"] != "Cycles"))}
    for column, scene in enumerate(scenes):
        mine = sorted((r for r in rows if r["scene"] == scene), key=lambda r: (r["config"] != "Cycles", r["config"],
                                                                             r["samples"]))
        lines += [f"### {scene} ({mine[0]['width']}x{mine[0]['height']})", "",
                  report.markdown(mine, ["config", "samples", "wall_seconds", "render_seconds", TIME_ERROR,
                                         "full_combined_rel_rmse", CONVERGENCE_ERROR, "indirect_ratio"],
                                  {"wall_seconds": "wall s", "render_seconds": "render s",
                                   TIME_ERROR: "combined relMSE 4x4 (k=2)", "full_combined_rel_rmse":
                                   "combined rel. RMSE (k=2)", CONVERGENCE_ERROR: "indirect relMSE 4x4 (own k)",
                                   "indirect_ratio": "indirect ratio (own k)"}), ""]
        cycles = [(r["wall_seconds"], r[TIME_ERROR]) for r in mine if r["config"] == "Cycles"]
        lines += _budget_lines(scene, mine, cycles) + _first_render_lines(ctx, records, scene, mine)
        convergence = _convergence(scene, mine, records)
        lines += _convergence_lines(scene, convergence)
        time_ax, samples_ax = axes[0][column], axes[1][column]
        if cycles:
            time_ax.plot(*zip(*cycles), marker="o", color="tab:gray", label="Cycles (2 bounces)")
        for config in dict.fromkeys(r["config"] for r in mine if r["config"] != "Cycles"):
            curve = [r for r in mine if r["config"] == config]
            time_ax.plot([r["wall_seconds"] for r in curve], [r[TIME_ERROR] for r in curve], marker="s",
                         color=colours[config], label=config)
            if config in convergence:
                points, own = convergence[config]
                samples_ax.plot(*zip(*points), marker="s", color=colours[config],
                                label=f"{config} (slope {report.fmt(_slope(points))})")
                if own:
                    samples_ax.plot(*zip(*own[1]), linestyle="--", marker=".", color=colours[config],
                                    label=f"{config} vs its {own[0]} samples (slope {report.fmt(_slope(own[1]))})")
        for budget in BUDGETS_S:
            time_ax.axvline(budget, color="k", linestyle=":", linewidth=1)
        time_ax.set(xscale="log", yscale="log", xlabel="render wall time (s)",
                    ylabel="combined relMSE, 4x4 downsampled (vs 2 bounces)", title=scene)
        samples_ax.set_xscale("log", base=2)
        samples_ax.set(yscale="log", xlabel="samples", ylabel="indirect relMSE, 4x4 downsampled")
        samples_ax.set_title(f"{scene}: convergence (solid: vs Cycles, own bounces;\ndashed: vs its own render with "
                             "the most samples)", fontsize=9)
        for ax in (time_ax, samples_ax):
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.14))  # below: the curves stay clear
    report.save(fig, ctx.out / f"{ctx.suite.name}.png", ctx.title)
    return "\n".join(_auto_lines(rows, records) + _estimate_lines(rows) + _bias_class_lines(rows) + lines) + \
        _TIME_NOTE


# Auto's goal (issue 17): within 10 % of the best fixed choice at the same wall time, and never above direct light.
AUTO_TOLERANCE = 1.10
# The measure a render's own error estimate is checked against: full size, as the estimate is.
ESTIMATE_CHECK = "full_combined_rel_mse"
FULLEST_FIXED = report.config_label({"method": "TOPOLOGY", "bounces": 2})


def _auto_lines(rows, records):
    """Per scene, Auto at its most samples against every fixed configuration and sample count that took no longer:
    what it planned, its error, the best fixed one's, direct light's, and the time it took against the fullest
    fixed plan at the same samples (what skipping effects saved)."""
    table = []
    for scene in _scenes(rows):
        mine = [r for r in rows if r["scene"] == scene and r["config"] != "Cycles"]
        autos = [r for r in mine if r["method"] == "AUTO"]
        if not autos:
            continue
        auto = max(autos, key=lambda r: r["samples"])
        fixed = [r for r in mine if r["method"] != "AUTO" and r["wall_seconds"] <= auto["wall_seconds"]]
        best = min(fixed, key=lambda r: r[TIME_ERROR], default=None)
        direct = min((r for r in fixed if r["method"] == "DIRECT"), key=lambda r: r[TIME_ERROR], default=None)
        fullest = next((r for r in mine if r["config"] == FULLEST_FIXED and r["samples"] == auto["samples"]), None)
        record = next((r for r in records if r.get("role") == "measure" and r["scene"] == scene and
                       (r.get("params") or {}).get("method") == "AUTO" and r.get("samples") == auto["samples"]), {})
        ratio = auto[TIME_ERROR] / best[TIME_ERROR] if best else math.nan
        verdict = ("no fixed render as fast" if best is None else
                   "within 10 %" if ratio <= AUTO_TOLERANCE else "NOT within 10 %")
        if direct and auto[TIME_ERROR] > direct[TIME_ERROR]:
            verdict += ", above direct light"
        table.append({"scene": scene, "Auto planned": record.get("plan", ""), "samples": auto["samples"],
                      "wall s": auto["wall_seconds"], "Auto relMSE": auto[TIME_ERROR],
                      "best fixed in that time": f"{best['config']}, {best['samples']}" if best else "-",
                      "its relMSE": best[TIME_ERROR] if best else math.nan, "Auto / best": ratio,
                      "direct relMSE": direct[TIME_ERROR] if direct else math.nan,
                      f"{FULLEST_FIXED} wall s": fullest["wall_seconds"] if fullest else math.nan,
                      "verdict": verdict})
    if not table:
        return []
    met = sum(1 for row in table if row["verdict"] == "within 10 %")
    return ["### Auto against the fixed methods at equal time", "",
            f"Auto at its most samples against every fixed configuration and sample count that took no longer "
            f"(combined relMSE 4x4 against Cycles with two bounces): within 10 % of the best or better, and not above "
            f"direct light, on {met} of {len(table)} scenes. The last column but one is the fullest fixed plan at "
            f"Auto's samples: Auto's time saved by what it skipped is the difference.", "",
            report.markdown(table, list(table[0])), ""]


def _estimate_lines(rows):
    """Per configuration at its most samples on each scene: the error its render estimated for itself (its noise
    and the bias it accepts, addon/final.py) against the combined relMSE at full size measured against Cycles."""
    table = []
    for config in dict.fromkeys(r["config"] for r in rows if r["config"] != "Cycles"):
        mine = [r for r in rows if r["config"] == config and r.get("estimated_relmse", -1.0) > 0.0]
        ratios = []
        for scene in _scenes(mine):
            most = max((r for r in mine if r["scene"] == scene), key=lambda r: r["samples"])
            ratios.append(most[ESTIMATE_CHECK] / most["estimated_relmse"])
        if ratios:
            table.append({"config": config, "scenes": len(ratios),
                          "within a factor of 2": sum(1 for q in ratios if 0.5 <= q <= 2.0),
                          "measured / estimated, median": statistics.median(ratios),
                          "least": min(ratios), "most": max(ratios)})
    if not table:
        return []
    return ["### Estimated error against measured", "",
            "Each configuration at its most samples: the combined relMSE at full size measured against Cycles over "
            "the one its render estimated (noise and bias, addon/final.py).", "",
            report.markdown(table, list(table[0])), ""]


# Below this error weight the bounces are too faint for their bias class to be measured (the near-black box).
_LEAST_BOUNCES_WEIGHT = 1e-5


def _bias_class_lines(rows):
    """Per configuration: its bias class (native/src/auto_plan.cpp), the bias of its bounces over their error
    weight, the bias taken from the two largest sample counts as B + V / N, per scene and its median."""
    table = []
    for config in dict.fromkeys(r["config"] for r in rows if r["config"] != "Cycles"):
        classes = {}
        for scene in _scenes(rows):
            mine = sorted((r for r in rows if r["config"] == config and r["scene"] == scene
                           and "bounces_error_share" in r), key=lambda r: r["samples"])
            if len(mine) < 2 or not mine[-1]["bounces_weight"] > _LEAST_BOUNCES_WEIGHT:
                continue
            (n1, e1), (n2, e2) = ((r["samples"], r["bounces_error_share"]) for r in mine[-2:])
            classes[scene] = max((n2 * e2 - n1 * e1) / (n2 - n1), 0.0) / mine[-1]["bounces_weight"]
        if classes:
            table.append({"config": config, "bias class, median": statistics.median(classes.values()),
                          **{scene: value for scene, value in classes.items()}})
    if not table:
        return []
    return ["### Bias classes", "",
            "The squared error per pixel each configuration's bounces keep against Cycles at its own bounce count, "
            "over what leaving them out would cost (both as parts of the combined relMSE at full size), with the "
            "noise taken out as B + V / N from its two largest sample counts; Auto's error estimate takes the "
            "median as its method's bias class (native/src/auto_plan.cpp).", "",
            report.markdown(table, list(dict.fromkeys(k for row in table for k in row))), ""]


_TIME_NOTE = """

Errors: relMSE = mean((x - r)^2 / (r^2 + 0.01)) after a 4x4 box downsample of both images, over the pixels that
see geometry. Combined is measured against Cycles with two diffuse bounces for every method (so a one-bounce
method carries the missing second bounce as error), Indirect against the bounces the method simulates (its own
target; a slope near -1 is unbiased Monte Carlo convergence, a flattening curve is the method's bias). The time is
the wall time of Blender's render operator (scene sync included, EXR writing not), one render each, after a
first render of the method in the same Blender run has paid the one-off costs (GL context, shaders, the
topology); Cycles' error within a budget is interpolated in log-log between the sample counts that bracket it."""


def _slope(points):
    """The least-squares slope of log(error) over log(samples)."""
    return report.linear_fit([math.log(x) for x, _ in points], [math.log(y) for _, y in points])[1]


def _budget_lines(scene, rows, cycles):
    """For each budget: the configuration and sample count with the lowest error within it, against Cycles'."""
    lines = []
    for budget in BUDGETS_S:
        within = [r for r in rows if r["config"] != "Cycles" and r["wall_seconds"] <= budget]
        cycles_error, how = report.error_at(cycles, budget)
        if how == "before first point":
            versus = f"Cycles has no image within it (1 sample takes {cycles[0][0]:.3g} s)"
        elif how == "after last point":
            versus = (f"Cycles' most samples take {cycles[-1][0]:.3g} s, less than the budget, for "
                      f"{report.fmt(cycles_error)}")
        else:
            versus = f"Cycles reaches {report.fmt(cycles_error)}"
        if not within:
            lines.append(f"- {scene}, {budget:g} s: no Bounce render fits; {versus}.")
            continue
        best = min(within, key=lambda r: r[TIME_ERROR])
        beats = math.isnan(cycles_error) or best[TIME_ERROR] < cycles_error
        lines.append(f"- {scene}, {budget:g} s: best Bounce is {best['config']} at "
                     f"{report.plural(best['samples'], 'sample')}, relMSE {report.fmt(best[TIME_ERROR])} in "
                     f"{best['wall_seconds']:.3g} s; {versus}: Bounce {'beats' if beats else 'does NOT beat'} Cycles.")
    return lines + [""]


def _first_render_lines(ctx, records, scene, rows):
    """Each method's first render in the Blender run (one-off costs included) beside the same render again."""
    lines = []
    for first in (r for r in records if r.get("role") == "warm-up" and r["scene"] == scene):
        config = report.config_label(first.get("params") or {})
        again = next((r for r in rows if r["config"] == config and r["samples"] == first.get("samples")), None)
        if again is None:
            continue
        topology = f" (topology {first['topology'].split(':')[0]})" if first.get("topology") else ""
        extra = first["wall_seconds"] - again["wall_seconds"]
        lines.append(f"- {scene}, {config}, {report.plural(first['samples'], 'sample')}: first render in the "
                     f"Blender run {first['wall_seconds']:.3g} s{topology}, the same render again "
                     f"{again['wall_seconds']:.3g} s: "
                     + (f"{extra:.3g} s of one-off costs." if extra > 0.1 * again["wall_seconds"] else
                        "no one-off cost beyond the timing noise."))
    return lines + [""] if lines else []


def _convergence(scene, rows, records):
    """{config: (curve, own)}: each configuration's indirect relMSE over samples against Cycles, and `own`
    (_self_convergence: against its own render with the most samples, i.e. its variance alone, bias left out)."""
    out = {}
    for config in dict.fromkeys(r["config"] for r in rows if r["config"] != "Cycles"):
        curve = [(r["samples"], r[CONVERGENCE_ERROR]) for r in rows if r["config"] == config
                 and r.get(CONVERGENCE_ERROR, 0) > 0]
        if len(curve) >= 2:
            out[config] = curve, _self_convergence(
                [r for r in records if r.get("role") == "measure" and r["scene"] == scene and r.get("exr")
                 and report.config_label(r.get("params") or {}) == config])
    return out


def _convergence_lines(scene, convergence):
    lines = []
    for config, (curve, own) in convergence.items():
        text = ", ".join(f"{report.fmt(e)}" for _, e in curve)
        lines.append(f"- {scene}, {config}: indirect relMSE {text} at {', '.join(str(s) for s, _ in curve)} "
                     f"samples, slope {report.fmt(_slope(curve))}" +
                     (f"; against its own {own[0]}-sample render, slope {report.fmt(_slope(own[1]))}" if own else "")
                     + ".")
    return lines + [""] if lines else []


def _self_convergence(records):
    """(most samples, [(samples, indirect relMSE 4x4 against the render with the most samples)])."""
    loaded = sorted(((r["samples"], images.load(r["exr"])) for r in records), key=lambda pair: pair[0])
    loaded = [(samples, image) for samples, image in loaded if "indirect" in image]
    if len(loaded) < 3:
        return None
    most, target = loaded[-1]
    key = f"indirect_rel_mse_{images.DOWNSAMPLE}x{images.DOWNSAMPLE}"
    points = [(samples, images.compare(image, target, "", parts=("indirect",))[key]) for samples, image in loaded[:-1]]
    points = [p for p in points if p[1] > 0]
    return (most, points) if len(points) >= 2 else None
