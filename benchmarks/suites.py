"""The suites of scripts/benchmark: what each renders (scenes, resolutions, default sweeps; smaller with
--quick) and how its records become tables, plots and statements. Each suite's report gets the summary rows
and writes into the output folder; it returns the Markdown it wants printed.
"""
import os
from dataclasses import dataclass, field

import budget
import images
import report
from images import METRIC_TEXT

ERROR_COLUMNS = ("combined_rel_rmse", "combined_rel_mae", "indirect_rel_rmse", "indirect_rel_mae",
                 "first_rel_rmse", "second_rel_rmse", "cpuref_indirect_rel_rmse", "cpuref_indirect_rel_mae")


@dataclass
class Suite:
    name: str
    summary: str
    method: str
    scenes: list          # [(scene name, width, height)]
    quick_scenes: list
    sets: dict = field(default_factory=dict)        # setting -> values swept (one value: fixed)
    quick_sets: dict = field(default_factory=dict)
    repeats: int = 3
    errors: bool = True
    cycles_samples: tuple = ()                      # Cycles renders measured against the reference too
    quick_cycles_samples: tuple = ()
    direct_baseline: bool = False                   # also render method DIRECT, for frame / direct-only ratios
    reference_bounces: int = 1                      # diffuse bounces of the Cycles reference
    reference_per_method: bool = False              # measure each render against the bounces its method simulates
    cpu_reference: bool = True                      # measure FLC renders against the CPU model too
    configs: list = None                            # [{method, setting: value}]: the configurations instead of
                                                    # `method` (each still swept over `sets`)
    script: str = None                              # a Blender script of benchmarks/ run on each scene instead
    script_config: dict = field(default_factory=dict)  # of the render jobs, and its config ("quick": overrides)
    gui: bool = False                               # the script runs in Blender's GUI on an Xvfb screen of the
                                                    # scene's size
    images: bool = False                            # write each configuration's EXR even without errors
    report: object = None


def _label(row, keys, named=()):
    """The values of `keys`, and `named` ones as 'name value' (e.g. 'cornell SSVP samples 16')."""
    return " ".join(f"{HEADERS.get(k, k)} {row[k]}" if k in named else f"{row[k]}"
                    for k in keys if row.get(k) is not None)


def _time_columns(rows, stages):
    return [f"{s} ms/sample" for s in stages] + ["frame ms/sample", "sync_ms", "wall_seconds"]


HEADERS = {"sync_ms": "sync ms", "combined_rel_rmse": "combined rel. RMSE", "combined_rel_mae": "combined rel. MAE",
           "indirect_rel_rmse": "indirect rel. RMSE", "indirect_rel_mae": "indirect rel. MAE",
           "cpuref_indirect_rel_rmse": "indirect rel. RMSE vs CPU model",
           "cpuref_indirect_rel_mae": "indirect rel. MAE vs CPU model", "wall_seconds": "wall s",
           "render_seconds": "render s",
           "frame ms/sample": "frame GPU ms/sample", "flc_vpls_per_pixel": "N_avg", "flc_tiling": "tiling",
           "first_rel_rmse": "1st bounce rel. RMSE", "second_rel_rmse": "2nd bounce rel. RMSE",
           "ssvp_clusters": "clusters", "ssvp_vpls": "1st-bounce VPLs", "ssvp_second_vpls": "2nd-bounce VPLs"}


def _errors_note(rows, bounces=1):
    if not any(any(c in r for c in ERROR_COLUMNS) for r in rows):
        return ""
    kind = "one-bounce" if bounces == 1 else f"{bounces}-bounce"
    note = f"\n\nErrors against the Cycles {kind} reference: {METRIC_TEXT}."
    if bounces == 2:
        note += (" The 1st and 2nd bounce columns compare Indirect - Second Bounce with Cycles' DiffInd at one "
                 "bounce, and Second Bounce with DiffInd(2) - DiffInd(1), both times DiffCol.")
    if any("cpuref_indirect_rel_rmse" in r for r in rows):
        note += (" The 'vs CPU model' columns compare the Indirect pass with what FLC converges to (native/reference,"
                 " continuous mode: unshadowed VPL-to-receiver transfer, ray-traced irradiance at the VPLs) times the"
                 " render's own albedo; for Cycles, the gap is the light FLC's model leaves out.")
    return note


def sweep_report(ctx, records, stages):
    """Any sweep: one row per scene and swept value; frame time and error against the swept value."""
    swept = ctx.swept or ["method"]
    rows = ctx.summarise(records, ["scene", "method", "width", "height", *swept])
    columns = ["scene", "method", "width", "height", *swept, *(["samples"] if "samples" not in swept else []),
               *_time_columns(rows, stages),
               *ERROR_COLUMNS]
    table = report.markdown(rows, columns, HEADERS)
    x = swept[-1]
    numeric = all(isinstance(r.get(x), (int, float)) for r in rows)
    if numeric:
        series = {}
        for row in sorted(rows, key=lambda r: r[x]):
            label = _label(row, ["scene", "method"] + [k for k in swept[:-1]], named=swept[:-1])
            xs, fields = series.setdefault(label, ([], {}))
            xs.append(row[x])
            for f in ("frame ms/sample", "wall_seconds", "combined_rel_rmse", "indirect_rel_rmse",
                      "second_rel_rmse", "cpuref_indirect_rel_rmse"):
                fields.setdefault(f, []).append(row.get(f, float("nan")))
        panels = [("frame GPU time per sample (ms)", "frame ms/sample"), ("render wall time (s)", "wall_seconds")]
        if any("combined_rel_rmse" in r for r in rows):
            panels.append(("relative RMSE (combined)", "combined_rel_rmse"))
        if any("second_rel_rmse" in r for r in rows):
            panels.append(("relative RMSE (indirect)", "indirect_rel_rmse"))
        if any("cpuref_indirect_rel_rmse" in r for r in rows):
            panels.append(("indirect relative RMSE vs CPU model", "cpuref_indirect_rel_rmse"))
        report.plot_lines(series, ctx.out / f"{ctx.suite.name}.png", ctx.title, HEADERS.get(x, x), panels,
                          logx=x == "flc_vpls_per_pixel")
    return table + _errors_note(rows, ctx.suite.reference_bounces)


def stages_report(ctx, records, stages):
    """Per-stage GPU time per configuration, sync, and each method's frame time over the direct-only frame."""
    keys = ["scene", "method", "width", "height", *[k for k in ctx.swept if k != "method"]]
    rows = ctx.summarise(records, keys)
    direct = {(r["scene"], r["width"], r["height"]): r for r in rows if r.get("method") == "DIRECT"}
    for row in rows:
        base = direct.get((row["scene"], row["width"], row["height"]))
        if base and base.get("frame ms/sample") and len({r["method"] for r in rows}) > 1:
            row["frame / direct-only frame"] = row["frame ms/sample"] / base["frame ms/sample"]
        row["sync s/Mtri"] = row.get("sync_seconds", 0) * 1e6 / max(row.get("triangles", 1), 1)
        row["_label"] = _label(row, keys[:2]) + f"\n{row['width']}x{row['height']}"
    columns = ["scene", "method", "width", "height", *keys[4:], "samples", "triangles", "sync s/Mtri",
               *_time_columns(rows, stages), "frame / direct-only frame", *ERROR_COLUMNS]
    report.plot_stage_bars(rows, stages, ctx.out / f"{ctx.suite.name}.png", ctx.title)
    return report.markdown(rows, columns, HEADERS) + _errors_note(rows, ctx.suite.reference_bounces)


def triangles_report(ctx, records, stages):
    """Frame and sync time against the triangle count, with least-squares slopes."""
    rows = ctx.summarise(records, ["scene", "method", "width", "height", *ctx.swept])
    rows.sort(key=lambda r: (r.get("method"), r.get("triangles", 0)))
    lines = [report.markdown(rows, ["scene", "method", "width", "height", "triangles", "instances", "samples",
                                    *_time_columns(rows, stages)], HEADERS), ""]
    series = {}
    for method in sorted({r["method"] for r in rows}):
        mine = [r for r in rows if r["method"] == method]
        mtris = [r["triangles"] / 1e6 for r in mine]
        xs, fields = series.setdefault(method, (mtris, {}))
        for f in ("frame ms/sample", "sync_seconds"):
            fields[f] = [r.get(f, float("nan")) for r in mine]
            a, b, r2 = report.linear_fit(mtris, fields[f])
            unit, scale = ("ms", 1) if f.endswith("ms/sample") else ("ms", 1e3)
            lines.append(f"- {method}, {'frame GPU time per sample' if scale == 1 else 'Blender -> core sync'}: "
                         f"{b * scale:.3g} {unit} per million triangles (intercept {a * scale:.3g} {unit}, "
                         f"R² {r2:.3f}, least squares over {len(mine)} points)")
    report.plot_lines(series, ctx.out / f"{ctx.suite.name}.png", ctx.title, "million triangles (instanced)",
                      [("frame GPU time per sample (ms)", "frame ms/sample"), ("sync (s)", "sync_seconds")])
    return "\n".join(lines)


def error_time_report(ctx, records, stages):
    """Error against time for Bounce's sample sweep and Cycles' sample sweep; how long Cycles needs to reach
    Bounce's error, interpolated on the Cycles curve (log-log)."""
    rows = ctx.summarise(records, ["scene", "engine", "method", "width", "height", "samples"])
    rows.sort(key=lambda r: (r["scene"], r["engine"], r.get("method") or "", r["samples"]))
    table = report.markdown(rows, ["scene", "engine", "method", "width", "height", "samples", "wall_seconds",
                                   "render_seconds", "frame ms/sample", *ERROR_COLUMNS], HEADERS)
    lines = [table, "", "Time is the wall time of Blender's render operator (scene sync included, EXR writing "
             "not), median over the repeats. Cycles time to reach Bounce's error, interpolated in log-log between "
             "the two Cycles sample counts that bracket it:", ""]
    plt = report.pyplot()
    scenes = sorted({r["scene"] for r in rows})
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.5 * len(scenes), 4.4), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        cycles = [r for r in rows if r["scene"] == scene and r["engine"] == "CYCLES"]
        # Cycles converges to the true one-bounce image, not to FLC's model: against the model its curve
        # flattens at the model's own error, so only the Cycles-reference metrics get time-to-error statements.
        for metric, style, statements in (("combined_rel_rmse", "-", True), ("indirect_rel_rmse", "--", True),
                                          ("cpuref_indirect_rel_rmse", ":", False)):
            curve = [(r["wall_seconds"], r[metric]) for r in cycles if metric in r]
            name = HEADERS[metric].replace(" rel. RMSE", "")
            if curve:
                ax.plot(*zip(*curve), style, marker="o", color="tab:gray", label=f"Cycles {name}")
            for method in sorted({r["method"] for r in rows if r["scene"] == scene and r["engine"] == "BOUNCE"}):
                mine = [r for r in rows if r["scene"] == scene and r["engine"] == "BOUNCE" and r["method"] == method
                        and metric in r]
                if not mine:
                    continue
                ax.plot([r["wall_seconds"] for r in mine], [r[metric] for r in mine], style, marker="s",
                        label=f"Bounce {method} {name}")
                for r in mine if statements else ():
                    t, how = report.crossing_time(curve, r[metric])
                    if how == "interpolated":
                        verdict = f"Cycles needs {t:.3g} s ({t / r['wall_seconds']:.3g}x Bounce's time)"
                    elif how == "below first point":
                        verdict = f"Cycles is already below it at 1 sample ({t:.3g} s)"
                    else:
                        verdict = f"Cycles does not reach it within {max(c['samples'] for c in cycles)} samples"
                    lines.append(f"- {scene}, {metric[:-9]}: Bounce {method} at "
                                 f"{report.plural(r['samples'], 'sample')} has relative "
                                 f"RMSE {r[metric]:.3g} in {r['wall_seconds']:.3g} s; {verdict}.")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("render wall time (s)")
        ax.set_ylabel("relative RMSE")
        ax.set_title(scene, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    report.save(fig, ctx.out / f"{ctx.suite.name}.png", ctx.title)
    return "\n".join(lines) + _errors_note(rows, ctx.suite.reference_bounces)


# Aranha et al. 2020, Sec. III-B: RMSE of 4, 8 and 16 clusters against 32 (Sponza, 1080p, after their
# tone mapping); Table I: Sponza at 1920x1080, 256 + 256 VPLs, GTX 1060, ms.
PAPER_RMSE_AGAINST_32 = {4: 0.1259, 8: 0.1020, 16: 0.0806}
PAPER_TABLE_I = {4: (1.03, 0.26, 1.16, 10.44, 12.89), 8: (1.03, 0.29, 2.50, 10.90, 14.72),
                 16: (1.03, 0.30, 7.90, 11.08, 20.31), 32: (1.03, 0.30, 56.29, 11.13, 68.75)}


def clusters_report(ctx, records, stages):
    """The cluster sweep, plus each cluster count's Combined against the largest count's (the paper's measure)."""
    text = sweep_report(ctx, records, stages)
    lines = ["", "", "Combined against the largest cluster count's image, the paper's measure (its RMSE is of tone-"
             "mapped 8-bit images, ours the relative RMSE of linear Combined, so compare the trend, not the digits):",
             ""]
    by_scene = {}
    for r in records:
        if r.get("role") == "measure" and r.get("exr") and r.get("method") == "SSVP":
            key = (r["scene"], r["params"].get("samples", 1))
            by_scene.setdefault(key, {}).setdefault(r["params"]["ssvp_clusters"], r["exr"])
    table = []
    for (scene, samples), exrs in sorted(by_scene.items()):
        most = max(exrs)
        reference = images.load(exrs[most])
        for clusters in sorted(exrs):
            if clusters == most:
                continue
            errors = images.compare(images.load(exrs[clusters]), reference, "")
            table.append({"scene": scene, "samples": samples, "clusters": clusters, "against": most,
                          "combined rel. RMSE": errors["combined_rel_rmse"],
                          "indirect rel. RMSE": errors.get("indirect_rel_rmse", float("nan")),
                          "paper RMSE": PAPER_RMSE_AGAINST_32.get(clusters, float("nan")) if most == 32 else None})
    lines.append(report.markdown(table, ["scene", "samples", "clusters", "against", "combined rel. RMSE",
                                         "indirect rel. RMSE", "paper RMSE"]))
    return text + "\n".join(lines)


def table1_report(ctx, records, stages):
    """The paper's Table I: G-buffer, misc (RSM, sampling, clustering, propagation), paraboloids, shading (with
    denoising), total, per cluster count, beside the paper's GTX 1060 figures."""
    rows = ctx.summarise(records, ["scene", "method", "width", "height", "ssvp_clusters"])
    parts = {"G-buffer": ["G-buffer"], "Misc": ["Shadows", "SSVP RSM", "SSVP sampling + clustering"],
             "Paraboloids": ["SSVP paraboloids"], "Shading": ["SSVP shading", "SSVP denoise"]}
    table = []
    for row in sorted(rows, key=lambda r: r.get("ssvp_clusters", 0)):
        out = {"clusters": row.get("ssvp_clusters"), "resolution": f"{row['width']}x{row['height']}"}
        for part, names in parts.items():
            out[part] = sum(row.get(f"{n} ms/sample", 0.0) for n in names)
        out["Total"] = row.get("frame ms/sample")
        paper = PAPER_TABLE_I.get(out["clusters"])
        if paper:
            out["paper Total (GTX 1060)"] = paper[4]
            out["paper Paraboloids"] = paper[2]
        table.append(out)
    columns = ["clusters", "resolution", *parts, "Total", "paper Paraboloids", "paper Total (GTX 1060)"]
    plt = report.pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.2))
    bottom = [0.0] * len(table)
    labels = [str(t["clusters"]) for t in table]
    for part in parts:
        values = [t[part] for t in table]
        ax.bar(labels, values, bottom=bottom, label=part)
        bottom = [b + v for b, v in zip(bottom, values)]
    ax.set_xlabel("clusters")
    ax.set_ylabel("GPU ms per frame")
    ax.legend(fontsize=8)
    report.save(fig, ctx.out / f"{ctx.suite.name}.png", ctx.title)
    return (report.markdown(table, columns) + "\n\nMisc holds the shadow maps, the RSM (rendered once per render: the "
            "light and the geometry are still), first-bounce sampling, the k-means readback and the second-bounce "
            "propagation; Shading holds the interleaved shading of both bounces, the debug view and the blur.")


def temporal_report(ctx, records, _stages):
    """Frame-to-frame change of the Indirect pass per motion and cluster seeding: a table and change per frame."""
    import statistics
    groups = {}
    for r in records:
        groups.setdefault((r["scene"], r["motion"], r["seeding"]), []).append(r)
    rows = []
    for (scene, motion, seeding), frames in sorted(groups.items()):
        changes = [f["change"] for f in frames if f.get("change") is not None]
        static = [f["change_static"] for f in frames if f.get("change_static") is not None]
        rows.append({"scene": scene, "motion": motion, "seeding": seeding, "frames": len(frames),
                     "mean change": statistics.fmean(changes), "max change": max(changes),
                     "mean change, static region": statistics.fmean(static) if static else float("nan"),
                     "static pixels": statistics.median(f.get("static_pixels", 0) for f in frames[1:]),
                     "frame s": statistics.median(f["seconds"] for f in frames)})
    lines = [report.markdown(rows, ["scene", "motion", "seeding", "frames", "mean change", "max change",
                                    "mean change, static region", "static pixels", "frame s"]), ""]
    for scene, motion in sorted({(r["scene"], r["motion"]) for r in rows}):
        by = {r["seeding"]: r for r in rows if r["scene"] == scene and r["motion"] == motion}
        if "fresh" in by and "last frame" in by and by["last frame"]["mean change"] > 0:
            lines.append(f"- {scene}, {motion}: seeding from the last frame changes the Indirect pass by "
                         f"{100 * by['last frame']['mean change']:.2f} % a frame on average, fresh seeding by "
                         f"{100 * by['fresh']['mean change']:.2f} % "
                         f"({by['fresh']['mean change'] / by['last frame']['mean change']:.3g}x).")
    plt = report.pyplot()
    motions = sorted({r["motion"] for r in records})
    fig, axes = plt.subplots(1, len(motions), figsize=(5.5 * len(motions), 4), squeeze=False)
    for ax, motion in zip(axes[0], motions):
        for (scene, m, seeding), frames in sorted(groups.items()):
            if m != motion:
                continue
            points = [(f["frame"], 100 * f["change"]) for f in frames if f.get("change") is not None]
            ax.plot(*zip(*points), marker=".", label=f"{scene}, clusters seeded: {seeding}")
        ax.set_title({"orbit": "camera orbit, still light (fixed probe view)",
                      "light": "turning light, still camera"}.get(motion, motion), fontsize=10)
        ax.set_xlabel("frame")
        ax.set_ylabel("change of Indirect from the last frame (%)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    report.save(fig, ctx.out / f"{ctx.suite.name}.png", ctx.title)
    return "\n".join(lines) + ("\n\nChange of frame f: mean |I_f - I_(f-1)| / mean I_(f-1) over the pixels that see "
                               "geometry; the static region: the pixels no direct light reaches in either frame.")


# Noel and Biri 2014: Table II, configuration 1 (Sponza; MSE of 8-bit images against shadow rays); Sec. VI's
# preview times at 1024x512 on their GPU; the thinning at 256^3 (1.2 GHz Xeon, unoptimised).
PAPER_TABLE_II = {"direct only": 111.96, "no visibility": 69.11, "clusters and gates": 33.10}
PAPER_PREVIEW_MS = {512: 33.6, 1024: 57.0, 2048: 103.6}
PAPER_THINNING_S = 109.0
TOPOLOGY_COLUMNS = tuple(PAPER_TABLE_II)


def _table2_picture(records, path, title):
    """Per scene: the shadow-ray reference, each column's Combined, its signed error (red: too bright), and the
    Topology pass (visibility clusters in colours, gates as disks)."""
    import numpy as np
    plt = report.pyplot()
    records = [r for r in records if r.get("images")]
    if not records:
        return
    fig, axes = plt.subplots(len(records), 5, figsize=(22, 2.6 * len(records) + 0.6), squeeze=False)
    for row, record in zip(axes, records):
        data = np.load(record["images"])
        display = lambda name: np.flipud(data[f"{name}_8bit"])  # noqa: E731
        reference = data["reference"]
        scale = max(float(np.percentile(reference, 99)), 1e-6) * 0.25
        panels = [("shadow rays (reference)", display("reference"), {}),
                  ("no visibility - reference", np.flipud((data["no_visibility"] - reference).mean(axis=-1)),
                   {"cmap": "RdBu_r", "vmin": -scale, "vmax": scale}),
                  ("clusters and gates", display("clusters_and_gates"), {}),
                  ("clusters and gates - reference",
                   np.flipud((data["clusters_and_gates"] - reference).mean(axis=-1)),
                   {"cmap": "RdBu_r", "vmin": -scale, "vmax": scale}),
                  ("Topology pass", np.flipud(data["topology"][..., :3]), {})]
        for ax, (name, image, style) in zip(row, panels):
            ax.imshow(image, **style)
            ax.set_title(f"{record['scene']}: {name}", fontsize=9)
            ax.axis("off")
    report.save(fig, path, title)


def sample_times(frames):
    """Milliseconds per sample between a viewport render's frames, from the time per sample so far each says it
    used ("Used N ms", the render thread's clock); the first frame (scene sync, restart) left out."""
    import re
    used = [(f["samples"], float(m.group(1))) for f in frames if (m := re.search(r"Used (\d+) ms", f["plan"]))]
    return [(b_ms * b - a_ms * a) / (b - a) for (a, a_ms), (b, b_ms) in zip(used, used[1:]) if b > a]


def viewport_budget_report(ctx, records, _stages):
    """Auto's viewport samples against each Sample Budget: the plan, the median time per sample, and whether it
    is within 20 % of the budget (issue 17's goal); a plot of every sample's time."""
    import re
    import statistics
    rows, measured = [], [r for r in records if r.get("render") == "measured"]
    for r in measured:
        times = sample_times(r["frames"])
        plans = [re.sub(r" Used \d+ ms\.$", "", f["plan"]) for f in r["frames"][1:]]
        median = statistics.median(times) if times else float("nan")
        rows.append({"scene": r["scene"], "region": f"{r['region_width']}x{r['region_height']}",
                     "budget ms": r["budget_ms"], "samples timed": len(times), "median ms per sample": median,
                     "median / budget": median / r["budget_ms"],
                     "within 20 %": "yes" if abs(median / r["budget_ms"] - 1.0) <= 0.2 else "NO",
                     "plan (most frames)": max(set(plans), key=plans.count) if plans else ""})
    plt = report.pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for index, r in enumerate(measured):
        times = sample_times(r["frames"])
        ax.plot(range(2, 2 + len(times)), times, marker=".", color=f"C{index}", label=f"budget {r['budget_ms']} ms")
        ax.axhline(r["budget_ms"], color=f"C{index}", linestyle=":", linewidth=1)
    ax.set(yscale="log", xlabel="frame seen", ylabel="ms per sample (between frames seen)",
           title="Auto in the viewport: time per sample against the Sample Budget (dotted)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    report.save(fig, ctx.out / f"{ctx.suite.name}.png", ctx.title)
    met = sum(1 for row in rows if row["within 20 %"] == "yes")
    return "\n".join([report.markdown(rows, list(rows[0])) if rows else "No viewport render finished.", "",
                      f"Within 20 % of the budget on {met} of {len(rows)} budgets. The time per sample is the "
                      "render thread's, between the frames the script saw (the first, which pays the scene sync "
                      "and the restart, left out), in the second render at each budget: the first taught the cost "
                      "model the plans it had not measured (as a viewport restarts whenever the view moves)."])


def topology_report(ctx, records, _stages):
    """Table II (MSE per indirect visibility), the precomputation per stage and the preview time per VPL count."""
    part = lambda name: [r for r in records if r.get("part") == name]  # noqa: E731
    accuracy = []
    for r in part("accuracy"):
        row = {"scene": r["scene"], "image": f"{r['width']}x{r['height']}", "VPLs": r["vpls"],
               "grid": r["topology_resolution"]}
        for column in TOPOLOGY_COLUMNS:
            row[f"8-bit MSE, {column}"] = r[f"mse8 {column}"]
            row[f"linear MSE, {column}"] = r[f"mse {column}"]
        row["no visibility / method"] = r["mse no visibility"] / max(r["mse clusters and gates"], 1e-30)
        row["shadow-ray render s"] = r.get("SHADOW_RAYS render s")
        row["method render s"] = r.get("CLUSTERS render s")
        accuracy.append(row)
    paper = {"scene": "paper: Sponza, config. 1", **{f"8-bit MSE, {c}": v for c, v in PAPER_TABLE_II.items()},
             "no visibility / method": PAPER_TABLE_II["no visibility"] / PAPER_TABLE_II["clusters and gates"]}
    columns = ["scene", "image", "VPLs", "grid", *(f"8-bit MSE, {c}" for c in TOPOLOGY_COLUMNS),
               *(f"linear MSE, {c}" for c in TOPOLOGY_COLUMNS), "no visibility / method", "shadow-ray render s",
               "method render s"]
    lines = ["### Table II: error against Embree shadow rays, same VPLs", "",
             report.markdown(accuracy + [paper], columns), ""]
    for row in accuracy:
        method, none = row["8-bit MSE, clusters and gates"], row["8-bit MSE, no visibility"]
        ratio = row["no visibility / method"]
        lines.append(f"- {row['scene']}: clusters and gates {'beat' if method < none else 'do NOT beat'} no "
                     f"visibility on the paper's measure, 8-bit MSE {method:.3g} against {none:.3g} "
                     f"(ratio {none / max(method, 1e-30):.3g}; direct light only: "
                     f"{row['8-bit MSE, direct only']:.3g}); in linear radiance the method's MSE is "
                     + (f"{ratio:.3g}x lower." if ratio >= 1 else f"{1 / ratio:.3g}x HIGHER."))
    _table2_picture(part("accuracy"), ctx.out / f"{ctx.suite.name}-images.png", ctx.title)
    lines.append(f"\nImages: {ctx.suite.name}-images.png (Combined of each column, its error against the "
                 "shadow rays, and the Topology pass).")

    stage_names = [n[:-2] for n in (part("precompute") or [{}])[0] if n.endswith(" s") and n != "precomputation s"
                   and not n.endswith("render s")]
    precompute = ctx.summarise(part("precompute"), ["scene", "topology_resolution", "grid"])
    precompute.sort(key=lambda r: (r["scene"], r["topology_resolution"]))
    lines += ["", "### Precomputation per stage (s)", "",
              report.markdown(precompute, ["scene", "topology_resolution", "grid", *(f"{n} s" for n in stage_names),
                                           "precomputation s", "skeleton_nodes", "segmented_nodes", "clusters",
                                           "gates"], {"topology_resolution": "resolution"}), "",
              f"Paper: the thinning alone took {PAPER_THINNING_S:.0f} s at 256^3 (1.2 GHz Xeon, unoptimised); "
              "the aim here is under 10 s at 256^3 on this machine."]

    preview = ctx.summarise(part("preview"), ["scene", "width", "height", "vpls"])
    preview.sort(key=lambda r: (r["scene"], r["vpls"]))
    frame_stages = [n[:-3] for n in (part("preview") or [{}])[0] if n.endswith(" ms") and n != "render ms"]
    for row in preview:
        row["paper GPU ms"] = PAPER_PREVIEW_MS.get(row["vpls"]) if (row["width"], row["height"]) == (1024, 512) \
            else None
    lines += ["", "### Preview: one sample, topology cached (ms, median)", "",
              report.markdown(preview, ["scene", "width", "height", "vpls", "render ms",
                                        *(f"{n} ms" for n in frame_stages), "paper GPU ms"], {"vpls": "VPLs"}), "",
              f"The method runs on the CPU ({os.cpu_count()} cores here); the paper's times are of its GPU renderer. "
              "The render time is the wall time of the core's render (scene sync excluded), traced VPLs included."]

    plt = report.pyplot()
    fig, (error_ax, build_ax, time_ax) = plt.subplots(1, 3, figsize=(16, 4.6))
    width = 0.8 / (len(accuracy) + 1)
    for i, row in enumerate(accuracy + [paper]):
        xs = [k + (i - len(accuracy) / 2) * width for k in range(len(TOPOLOGY_COLUMNS))]
        error_ax.bar(xs, [row[f"8-bit MSE, {c}"] for c in TOPOLOGY_COLUMNS], width, label=row["scene"],
                     hatch="//" if row is paper else None)
    error_ax.set_xticks(range(len(TOPOLOGY_COLUMNS)), TOPOLOGY_COLUMNS, fontsize=8)
    error_ax.set_yscale("log")
    error_ax.set_ylabel("MSE against shadow rays (8-bit sRGB)")
    error_ax.set_title("Table II", fontsize=10)
    error_ax.legend(fontsize=8)
    labels = [f"{r['scene']}\n{r['topology_resolution']}^3" for r in precompute]
    bottom = [0.0] * len(precompute)
    for name in stage_names:
        values = [r.get(f"{name} s", 0.0) for r in precompute]
        build_ax.bar(labels, values, bottom=bottom, label=name)
        bottom = [b + v for b, v in zip(bottom, values)]
    build_ax.axhline(10.0, color="tab:red", linestyle="--", linewidth=1, label="aim at 256^3")
    build_ax.set_ylabel("seconds")
    build_ax.set_title("Precomputation per stage", fontsize=10)
    build_ax.legend(fontsize=7)
    for scene in sorted({r["scene"] for r in preview}):
        mine = [r for r in preview if r["scene"] == scene]
        time_ax.plot([r["vpls"] for r in mine], [r["render ms"] for r in mine], marker="o", label=f"{scene} (CPU)")
    time_ax.plot(list(PAPER_PREVIEW_MS), list(PAPER_PREVIEW_MS.values()), "k--", marker="s", label="paper (GPU)")
    time_ax.set_xscale("log", base=2)
    time_ax.set_xlabel("VPLs")
    time_ax.set_ylabel("render ms")
    time_ax.set_title("Preview, one sample" + (f" at {preview[0]['width']}x{preview[0]['height']}" if preview
                                                else ""), fontsize=10)
    time_ax.grid(True, alpha=0.3)
    time_ax.legend(fontsize=8)
    report.save(fig, ctx.out / f"{ctx.suite.name}.png", ctx.title)
    return "\n".join(lines) + ("\n\nMSE of Combined against the shadow-ray render with identical VPLs (seed, count, "
                               "bounces); 'direct only' is the reference's Direct pass. 8-bit: Blender's Standard "
                               "view (sRGB, clamped), in 0..255 units, the paper's measure.")


def _tiling(frame, tile_size):
    """(tiles, 'W x H' of a tile) of a frame side pair in tiles of one size, at most tile_size a side, as the
    renderer cuts it (native/src/renderer.cpp)."""
    (width, height), counts = frame, [-(-side // tile_size) for side in frame]
    return counts[0] * counts[1], f"{-(-width // counts[0])}x{-(-height // counts[1])}"


def tiling_report(ctx, records, _stages):
    """Each tiled render against the same configuration in one tile: render time over the untiled one's, and the
    difference of its images, next to the difference another seed makes (the noise it must stay within)."""
    rows = ctx.summarise(records, ["scene", "method", "width", "height", "tile_size", "seed"])
    exrs = {(r["scene"], r["method"], r.get("params", {}).get("tile_size"), r.get("params", {}).get("seed")): r["exr"]
            for r in records if r.get("exr") and r.get("role") == "measure"}
    whole = {}
    for row in rows:
        if row.get("seed") is None and row["tile_size"] >= max(row["width"], row["height"]):
            whole[(row["scene"], row["method"])] = row
    table = []
    for row in sorted(rows, key=lambda r: (r["scene"], r["method"], -r["tile_size"], r.get("seed") or 0)):
        base = whole.get((row["scene"], row["method"]))
        if base is None:
            continue
        tiles, tile = _tiling((row["width"], row["height"]), row["tile_size"])
        out = {"scene": row["scene"], "method": row["method"], "frame": f"{row['width']}x{row['height']}",
               "tile_size": row["tile_size"], "tiles": tiles, "tile": tile,
               "seed": row.get("seed") if row.get("seed") is not None else "-",
               "render s": row["render_seconds"], "wall s": row["wall_seconds"],
               "render / untiled": row["render_seconds"] / base["render_seconds"]}
        mine = exrs.get((row["scene"], row["method"], row["tile_size"], row.get("seed")))
        theirs = exrs.get((row["scene"], row["method"], base["tile_size"], None))
        if mine and theirs and mine != theirs:
            image, untiled = images.load(mine), images.load(theirs)
            scale = max(float(untiled["direct"].max()), 1e-30)
            out["direct max |diff| / max"] = float(abs(image["direct"] - untiled["direct"]).max()) / scale
            errors = images.compare(image, untiled, "", parts=("combined", "indirect"))
            out["combined relMSE 4x4"] = errors["combined_rel_mse_4x4"]
            if "indirect_ratio" in errors:
                out["indirect mean / untiled"] = errors["indirect_ratio"]
                out["indirect relMSE 4x4"] = errors["indirect_rel_mse_4x4"]
        table.append(out)
    noise = {(r["scene"], r["method"]): r for r in table if r["seed"] != "-"}
    for r in table:
        other_seed = noise.get((r["scene"], r["method"]))
        if r["seed"] == "-" and r["tiles"] > 1:
            within = other_seed is None or r.get("combined relMSE 4x4", 0) <= other_seed.get("combined relMSE 4x4", 0)
            r["within noise"] = "yes" if within else "NO"
            r["at most 1.2x"] = "yes" if r["render / untiled"] <= 1.2 else "NO"
    series = {}
    for r in table:
        if r["seed"] == "-":
            xs, fields = series.setdefault(f"{r['scene']} {r['method']}", ([], {}))
            xs.append(r["tiles"])
            fields.setdefault("render / untiled", []).append(r["render / untiled"])
            fields.setdefault("render s", []).append(r["render s"])
    report.plot_lines(series, ctx.out / f"{ctx.suite.name}.png", ctx.title, "tiles in the frame",
                      [("render time over the untiled render's", "render / untiled"), ("render s", "render s")],
                      logx=True)
    tiled = [r for r in table if "within noise" in r]
    return "\n".join([
        report.markdown(table, list(dict.fromkeys(k for r in table for k in r))), "",
        f"Tiled renders within 1.2x of the untiled render's time: "
        f"{sum(r['at most 1.2x'] == 'yes' for r in tiled)} of {len(tiled)}; images within noise: "
        f"{sum(r['within noise'] == 'yes' for r in tiled)} of {len(tiled)}. The untiled render is the same "
        "configuration with a tile as large as the frame; the row with a seed is that untiled render with another "
        "seed, whose difference is the noise a tiled image's difference is held to. Render time is the core's "
        "(median of the repeats), scene sync left out; tiles are of one size, the last column and row reaching "
        "past the frame when the tile size does not divide it."])


_BUDGET_SCENES = [("cornell", 256, 256), ("sponza", 480, 270), ("two-rooms", 480, 270), ("two-rooms-wall", 480, 270),
                  (budget.LIT_ROOM, 480, 270), ("sunlit-interior", 480, 270),
                  # lit by emission or the world alone, or by the world added (issue 16)
                  ("cornell-emissive", 256, 256), ("sponza-hdri", 480, 270), ("sunlit-interior-sky", 480, 270),
                  # its sources apart: the world's and the sun's share of each component
                  ("sunlit-interior-sky@world", 480, 270), ("sunlit-interior-sky@lamps", 480, 270),
                  # where the bounces matter little, not at all, or most (issue 17)
                  ("open-ground", 480, 270), ("cornell-black", 256, 256), ("cornell-white", 256, 256)]
_QUICK_BUDGET_SCENES = [("cornell", 64, 64)] + [(name, 96, 54) for name, _, _ in _BUDGET_SCENES[1:]]
# Error over time needs a reference that is not black: not the closed room.
_TIME_SCENES = [s for s in _BUDGET_SCENES if s[0] not in (budget.CLOSED_ROOM, budget.LIT_ROOM)]
_QUICK_TIME_SCENES = [s for s in _QUICK_BUDGET_SCENES if s[0] not in (budget.CLOSED_ROOM, budget.LIT_ROOM)]

_DRAGONS = (1, 2, 5, 10, 20, 50, 100)
_QUICK_DRAGONS = (1, 2, 3)

SUITES = {s.name: s for s in (
    Suite("sync", "sync time and per-stage GPU time of the standard scenes, plus sync of a 1M-triangle grid "
          "(the original scripts/benchmark)", "DIRECT",
          [("cornell", 1280, 720), ("sponza", 1280, 720), ("grid", 320, 180)],
          [("cornell", 128, 72), ("sponza", 128, 72), ("grid-100k", 64, 36)],
          sets={"samples": [1]}, repeats=5, errors=False, report=stages_report),
    Suite("flc-vpls", "frame time and error against N_avg (flc_vpls_per_pixel) on the Cornell box", "FLC",
          [("cornell", 1024, 1024)], [("cornell", 64, 64)],
          sets={"samples": [1], "flc_vpls_per_pixel": [64, 128, 256, 512, 1024]},
          quick_sets={"flc_vpls_per_pixel": [64, 256]}, report=sweep_report),
    Suite("flc-tiling", "frame time and error against the interleaved-sampling level (flc_tiling)", "FLC",
          [("cornell", 1024, 1024)], [("cornell", 64, 64)],
          sets={"samples": [1], "flc_tiling": [0, 1, 2, 3]}, quick_sets={"flc_tiling": [0, 2]},
          report=sweep_report),
    Suite("stages", "per-stage GPU time at 1280x720 and the method's frame over a direct-only frame", "FLC",
          [("cornell", 1280, 720), ("sponza", 1280, 720)], [("cornell", 128, 72), ("sponza", 128, 72)],
          sets={"samples": [1]}, direct_baseline=True, report=stages_report),
    Suite("triangles", "frame time against the triangle count: instanced Stanford dragons, 100k to 10M", "FLC",
          [(f"dragons-{n}", 1280, 720) for n in _DRAGONS], [(f"dragons-{n}", 96, 54) for n in _QUICK_DRAGONS],
          sets={"samples": [1]}, errors=False, report=triangles_report),
    Suite("error-time", "error against render time: Bounce at 1-64 samples, Cycles at 1-256 samples", "FLC",
          [("cornell", 512, 512), ("sponza", 640, 360)], [("cornell", 64, 64), ("sponza", 96, 54)],
          sets={"samples": [1, 4, 16, 64]}, quick_sets={"samples": [1, 4]},
          cycles_samples=tuple(2 ** i for i in range(9)), quick_cycles_samples=(1, 2, 4, 8),
          report=error_time_report),
    Suite("ssvp-clusters", "SSVP error and frame time against the cluster count (Eq. 2 k-means), against Cycles "
          "with two diffuse bounces, and against the 32-cluster image as in the paper", "SSVP",
          [("cornell", 512, 512), ("sponza", 640, 360)], [("cornell", 64, 64), ("sponza", 96, 54)],
          sets={"samples": [1, 16], "ssvp_clusters": [4, 8, 16, 32]},
          quick_sets={"samples": [1], "ssvp_clusters": [4, 32]}, reference_bounces=2, report=clusters_report),
    Suite("ssvp-vpls", "SSVP error and frame time against the first- and second-bounce VPL counts (8 clusters, so "
          "at least 256 second-bounce VPLs)", "SSVP",
          [("cornell", 512, 512)], [("cornell", 64, 64)],
          sets={"samples": [1], "ssvp_second_vpls": [256, 1024, 4096], "ssvp_vpls": [64, 128, 256, 512, 1024]},
          quick_sets={"ssvp_second_vpls": [256], "ssvp_vpls": [64, 256]}, reference_bounces=2,
          report=sweep_report),
    Suite("ssvp-bounces", "SSVP with one bounce against two, one frame and 16 samples, against Cycles with two "
          "diffuse bounces; each bounce against its own part of Cycles", "SSVP",
          [("cornell", 512, 512), ("sponza", 640, 360)], [("cornell", 64, 64), ("sponza", 96, 54)],
          sets={"samples": [1, 16], "bounces": [1, 2]}, quick_sets={"samples": [1]}, reference_bounces=2,
          report=sweep_report),
    Suite("ssvp-stages", "Table I: SSVP's per-stage GPU time on Sponza at 1920x1080 with 256 + 256 VPLs, 4 to 32 "
          "clusters", "SSVP", [("sponza", 1920, 1080)], [("sponza", 192, 108)],
          sets={"samples": [1], "ssvp_vpls": [256], "ssvp_second_vpls": [256], "ssvp_clusters": [4, 8, 16, 32]},
          quick_sets={"ssvp_clusters": [4, 8]}, errors=False, report=table1_report),
    Suite("ssvp-temporal", "SSVP's temporal stability over 60 frames, a camera orbit and a turning sun, with "
          "k-means seeded from the last frame against seeded afresh (paper Sec. III-C)", "SSVP",
          [("sponza", 320, 180)], [("sponza", 96, 54)], errors=False, script="ssvp_temporal.py",
          script_config={"frames": 60, "quick": {"frames": 6}, "orbit_degrees": 30.0, "light_degrees": 6.0,
                         "bounce": {"samples": 1, "ssvp_vpls": 256, "ssvp_second_vpls": 256, "ssvp_clusters": 8}},
          report=temporal_report),
    Suite("topology", "Table II of the topology method: MSE against Embree shadow rays with the same VPLs for "
          "direct light only, no indirect visibility and clusters and gates; the precomputation per stage at "
          "128^3 and 256^3; the preview at 1024x512 for 512, 1024 and 2048 VPLs", "TOPOLOGY",
          [("two-rooms", 512, 256), ("sponza", 512, 256)], [("two-rooms", 128, 64), ("sponza", 128, 64)],
          errors=False, script="topology_table.py",
          script_config={"bounce": {"method": "TOPOLOGY", "samples": 1, "topology_resolution": 128},
                         "resolutions": [128, 256], "accuracy": {"topology_resolution": 128, "topology_vpls": 1024},
                         "preview": {"width": 1024, "height": 512, "vpls": [512, 1024, 2048], "repeats": 3},
                         "quick": {"bounce": {"method": "TOPOLOGY", "samples": 1, "topology_resolution": 64},
                                   "resolutions": [64], "accuracy": {"topology_resolution": 64, "topology_vpls": 256},
                                   "preview": {"width": 128, "height": 64, "vpls": [256], "repeats": 1}}},
          report=topology_report),
    Suite("viewport-budget", "Auto's Sample Budget in a real viewport (Blender's GUI on Xvfb, Rendered shading "
          "through the scene's camera): time per progressive sample against budgets of 150, 300 and 600 ms", "AUTO",
          [("cornell", 800, 500)], [("cornell", 640, 400)], errors=False, script="viewport_budget.py", gui=True,
          script_config={"budgets": [150, 300, 600], "samples": 24, "quick": {"samples": 8}},
          report=viewport_budget_report),
    Suite("tiling", "tiled renders against one tile: render time over the untiled render's and the difference of "
          "the images, at tile sizes that do and do not divide the frame", "DIRECT",
          [("sunlit-interior", 1000, 600)], [("cornell", 520, 300)],
          sets={"samples": [2]}, quick_sets={"samples": [1]}, configs=[
              {"method": method, **tiling} for method in ("DIRECT", "FLC", "SSVP")
              for tiling in ({"tile_size": 4096}, {"tile_size": 4096, "seed": 1}, {"tile_size": 512},
                             {"tile_size": 384}, {"tile_size": 256})],
          errors=False, images=True, report=tiling_report),
    Suite("budget", "error budget per light path against Cycles (direct, first and second bounce, combined): the "
          "ratio of means over the image and its thirds and relMSE, per method, a picture of the signed errors, a "
          "bias check, and the light leaking into a closed room", "DIRECT", _BUDGET_SCENES, _QUICK_BUDGET_SCENES,
          sets={"samples": [16]}, repeats=1, configs=budget.CONFIGS, reference_bounces=2, reference_per_method=True,
          cpu_reference=False, report=budget.budget_report),
    Suite("budget-time", "error against render time per method at 1-64 samples and Cycles at 1-256 samples "
          "(combined against two bounces); the best method within 1 s and 2 s against Cycles; convergence of "
          "each method's indirect light", "DIRECT", _TIME_SCENES, _QUICK_TIME_SCENES,
          sets={"samples": [1, 4, 16, 64]}, quick_sets={"samples": [1, 4]}, repeats=1, configs=budget.CONFIGS,
          cycles_samples=tuple(2 ** i for i in range(9)), quick_cycles_samples=(1, 2, 4, 8), reference_bounces=2,
          reference_per_method=True, cpu_reference=False, report=budget.budget_time_report),
)}
