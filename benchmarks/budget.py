"""The error budget of scripts/benchmark (suite budget): how far each of Bounce's methods is from the Cycles oracle
in each light path.

budget: per scene and configuration, each component of the render against its part of the Cycles references
with one and two diffuse bounces (images.py; the combined against as many bounces as the method simulates):
the ratio of means over the image and its thirds, relMSE per pixel and after a 4x4 box downsample; a picture
of the signed error per component; a bias check; for the closed room of two-rooms-wall, the light that leaks
into it through the wall.
"""
import math

import numpy as np

import display
import images
import report

COMPONENTS = ("direct", "first", "second", "indirect", "combined")
PICTURE_COMPONENTS = ("direct", "first", "second", "combined")
BIAS_RANGE = (0.9, 1.1)
# Configurations: each a method and its settings (all others at their defaults). flc_visibility is FLC's
# indirect visibility, a setting still to come: the suite skips that configuration until the build has it.
CONFIGS = [{"method": "DIRECT"}, {"method": "FLC"}, {"method": "FLC", "flc_visibility": True},
           {"method": "SSVP", "bounces": 2}, {"method": "TOPOLOGY", "bounces": 2}, {"method": "TOPOLOGY", "bounces": 1}]
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


def _exempt(config):
    """FLC without indirect visibility leaks light by design (the paper's model): reported, not held to the rule."""
    return config == "FLC"


def _cell(row, part, fields, digits=3):
    values = [row.get(f"{part}_{f}") for f in fields]
    if all(v is None or (isinstance(v, float) and math.isnan(v)) for v in values):
        return "-"
    return " / ".join(report.fmt(v) if v is not None else "-" for v in values)


def budget_report(ctx, records, _stages):
    """Per scene a table of each component's ratio and relMSE per configuration, a picture of the signed errors;
    then the bias check and the closed room's leak."""
    rows = _config_rows(ctx, records)
    lines = []
    if ctx.skipped:
        lines += ["Configurations not run: " + "; ".join(ctx.skipped) + ".", ""]
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
    return "\n".join(lines) + _NOTE


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
suites."""


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
        level = float(np.percentile(lit, 98)) if lit.size else 0.0
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

