"""Records -> summary rows -> Markdown tables, CSV files and matplotlib plots, for scripts/benchmark.

A record is one render (a JSON line of blender_render.py, plus the scene name, the swept parameters and the
errors the driver measured). A row is the median over a configuration's repeats.
"""
import csv
import math
import statistics
from collections import defaultdict

# Stages that are not part of producing a frame (copying it back to Blender).
NON_FRAME_STAGES = ("Readback",)


def flatten(record):
    """One flat dict per render: stage times become '<stage> ms' (total over the samples: the GPU's time, or the
    CPU's for a stage that runs on the CPU alone, such as the Topology method's), swept parameters their own
    columns; 'frame ms' sums the GPU's."""
    flat = {k: v for k, v in record.items() if k not in ("stages", "params")}
    for name, value in (record.get("params") or {}).items():
        flat[name] = value
    stages = record.get("stages") or {}
    for name, times in stages.items():
        flat[f"{name} ms"] = times["gpu_ms"] or times.get("cpu_ms", 0.0)
    if stages:
        flat["frame ms"] = sum(t["gpu_ms"] for n, t in stages.items() if n not in NON_FRAME_STAGES)
    return flat


def stage_names(records):
    names = []
    for record in records:
        for name in record.get("stages") or {}:
            if name not in names:
                names.append(name)
    return names


def summarise(records, keys):
    """Median of every numeric field over the records sharing `keys`; stage and frame times also per sample."""
    groups = defaultdict(list)
    for record in records:
        flat = flatten(record)
        groups[tuple(flat.get(k) for k in keys)].append(flat)
    rows = []
    for key, runs in groups.items():
        row = dict(zip(keys, key))
        row["repeats"] = len(runs)
        for field in runs[0]:
            values = [r[field] for r in runs if isinstance(r.get(field), (int, float)) and not isinstance(r.get(field), bool)]
            if field not in row and values:
                row[field] = statistics.median(values)
        if "sync_seconds" in row:
            row["sync_ms"] = row["sync_seconds"] * 1e3
        samples = row.get("samples") or 1
        for field in list(row):
            if field.endswith(" ms"):
                row[field.replace(" ms", " ms/sample")] = row[field] / samples
        rows.append(row)
    return rows


def plural(count, noun):
    return f"{count} {noun}" + ("" if count == 1 else "s")


def fmt(value):
    if isinstance(value, float):
        if math.isnan(value):
            return "-"
        if value == 0 or 0.01 <= abs(value) < 1e5:
            return f"{value:.3g}" if abs(value) < 100 else f"{value:,.0f}"
        return f"{value:.3g}"
    if isinstance(value, int) and abs(value) >= 10000:
        return f"{value:,}"
    return "-" if value is None else str(value)


def markdown(rows, columns, headers=None):
    """A Markdown table of `columns` (only those some row has); numbers right-aligned."""
    columns = [c for c in columns if any(c in r for r in rows)]
    headers = headers or {}
    numeric = [any(isinstance(r.get(c), (int, float)) for r in rows) for c in columns]
    lines = ["| " + " | ".join(headers.get(c, c) for c in columns) + " |",
             "| " + " | ".join("---:" if n else "---" for n in numeric) + " |"]
    for row in rows:
        lines.append("| " + " | ".join(fmt(row.get(c)) for c in columns) + " |")
    return "\n".join(lines)


def write_csv(path, records):
    flat = [flatten(r) for r in records]
    fields = []
    for row in flat:
        fields += [k for k in row if k not in fields]
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(flat)


def linear_fit(xs, ys):
    """Least-squares y = a + b x; returns (a, b, r^2). Fewer than two distinct x: b is nan."""
    n = len(xs)
    if n < 2 or len(set(xs)) < 2:
        return (ys[0] if ys else float("nan")), float("nan"), float("nan")
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    b = sxy / sxx
    a = my - b * mx
    ss_tot = sum((y - my) ** 2 for y in ys)
    ss_res = sum((y - a - b * x) ** 2 for x, y in zip(xs, ys))
    return a, b, (1 - ss_res / ss_tot) if ss_tot > 0 else float("nan")


def config_label(config):
    """'FLC flc_visibility=True': a configuration's method and its other settings but samples."""
    return " ".join([str(config.get("method") or "")] + [f"{k}={v}" for k, v in config.items()
                                                         if k not in ("method", "samples") and v is not None]).strip()


def _loglog(x, x0, x1, y0, y1):
    """y at x on the straight line through (x0, y0) and (x1, y1) in log-log."""
    f = (math.log(x) - math.log(x0)) / (math.log(x1) - math.log(x0))
    return math.exp(math.log(y0) + f * (math.log(y1) - math.log(y0)))


def _positive(curve):
    return [p for p in curve if p[1] > 0 and p[0] > 0 and not math.isnan(p[1])]


def crossing_time(curve, error):
    """Where a (time, error) curve, in increasing sample order, first reaches `error`, interpolated linearly in
    log-log between the two points that bracket it (sample order, not time order: timing noise may reorder
    cheap renders). Returns (time, how) with how 'interpolated', 'below first point' or 'not reached'."""
    points = _positive(curve)
    if not points:
        return float("nan"), "no curve"
    if error >= points[0][1]:
        return points[0][0], "below first point"
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if e1 <= error <= e0 and e0 != e1:
            return _loglog(error, e0, e1, t0, t1), "interpolated"
    return float("nan"), "not reached"


def error_at(curve, time):
    """The error of a (time, error) curve, in increasing sample order, at `time`: interpolated linearly in log-log
    between the last point not after `time` and the next one. Returns (error, how) with how 'interpolated',
    'before first point' (nan: the curve's cheapest render takes longer) or 'after last point' (its last error)."""
    points = _positive(curve)
    if not points or time < points[0][0]:
        return float("nan"), "before first point" if points else "no curve"
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if t0 <= time <= t1 and t0 != t1:
            return _loglog(time, t0, t1, e0, e1), "interpolated"
    return points[-1][1], "after last point"


def pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save(fig, path, title):
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    pyplot().close(fig)


def plot_stage_bars(rows, stages, path, title, per="ms/sample"):
    """Stacked per-stage GPU time per configuration, and the sync time beside it (log scale)."""
    plt = pyplot()
    labels = [row["_label"] for row in rows]
    fig, (frame_ax, sync_ax) = plt.subplots(1, 2, figsize=(max(8, 2.2 * len(rows) + 3), 4.4),
                                            gridspec_kw={"width_ratios": [3, 2]})
    bottom = [0.0] * len(rows)
    for stage in stages:
        if stage in NON_FRAME_STAGES:
            continue
        values = [row.get(f"{stage} {per}", 0.0) for row in rows]
        frame_ax.bar(labels, values, bottom=bottom, label=stage)
        bottom = [b + v for b, v in zip(bottom, values)]
    frame_ax.set_ylabel(f"GPU time ({per})")
    frame_ax.set_title("Frame, per stage", fontsize=10)
    frame_ax.legend(fontsize=8)
    bars = sync_ax.bar(labels, [row.get("sync_seconds", 0) * 1e3 for row in rows], color="tab:gray")
    for bar, row in zip(bars, rows):
        sync_ax.annotate(f"{int(row.get('triangles', 0)):,} tris", (bar.get_x() + bar.get_width() / 2,
                                                                    bar.get_height()),
                         ha="center", va="bottom", fontsize=7)
    sync_ax.set_yscale("log")
    sync_ax.set_ylabel("Blender -> core sync (ms)")
    sync_ax.set_title("Scene sync", fontsize=10)
    for ax in (frame_ax, sync_ax):
        ax.tick_params(axis="x", labelsize=7)
    save(fig, path, title)


def plot_lines(series, path, title, xlabel, panels, logx=False, logy=()):
    """Line plots, one panel per (ylabel, field): `series` maps a legend label to (xs, {field: ys})."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.2), squeeze=False)
    for ax, (ylabel, field) in zip(axes[0], panels):
        for label, (xs, fields) in series.items():
            ys = fields.get(field)
            if ys and any(y is not None and not (isinstance(y, float) and math.isnan(y)) for y in ys):
                ax.plot(xs, ys, marker="o", label=label)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        if logx:
            ax.set_xscale("log", base=2)
        if field in logy:
            ax.set_yscale("log")
        ax.grid(True, alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
    save(fig, path, title)
