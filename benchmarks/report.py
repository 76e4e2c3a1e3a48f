"""Summarises benchmark records (JSON lines from blender_render.py): prints a Markdown table, writes a CSV and a
plot. Run with /usr/bin/python3 (numpy, matplotlib from Debian)."""
import argparse
import csv
import json
import statistics
import sys
from collections import defaultdict


def load(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def summarise(records):
    """One row per (scene, width, height, samples): medians over repeats (repeat 0 is kept: it is the
    F12 experience, sync included)."""
    groups = defaultdict(list)
    for r in records:
        groups[(r["scene"], r["width"], r["height"], r["samples"])].append(r)
    rows = []
    for (scene, width, height, samples), runs in groups.items():
        stage_names = list(runs[0]["stages"])
        row = {
            "scene": scene, "resolution": f"{width}x{height}", "samples": samples, "repeats": len(runs),
            "triangles": runs[0]["triangles"],
            "sync_ms": statistics.median(r["sync_seconds"] for r in runs) * 1e3,
            "sync_s_per_mtri": statistics.median(r["sync_seconds"] for r in runs) * 1e6 / max(runs[0]["triangles"], 1),
            "render_ms": statistics.median(r["render_seconds"] for r in runs) * 1e3,
        }
        for name in stage_names:
            row[f"{name} gpu_ms"] = statistics.median(r["stages"][name]["gpu_ms"] for r in runs) / samples
        row["frame gpu_ms"] = sum(row[f"{name} gpu_ms"] for name in stage_names if name != "Readback")
        rows.append(row)
    return rows


def markdown(rows):
    columns = list(rows[0])
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for row in rows:
        cells = [f"{row[c]:.2f}" if isinstance(row[c], float) else str(row[c]) for c in columns]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def plot(rows, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    stage_columns = [c for c in rows[0] if c.endswith(" gpu_ms") and c != "frame gpu_ms" and not c.startswith("Readback")]
    labels = [f"{r['scene']}\n{r['resolution']}" for r in rows]
    fig, (frame_ax, sync_ax) = plt.subplots(1, 2, figsize=(max(8, 3.2 * len(rows)), 4.2),
                                            gridspec_kw={"width_ratios": [3, 2]})
    bottom = [0.0] * len(rows)
    for column in stage_columns:
        values = [r[column] for r in rows]
        frame_ax.bar(labels, values, bottom=bottom, label=column.replace(" gpu_ms", ""))
        bottom = [b + v for b, v in zip(bottom, values)]
    frame_ax.set_ylabel("GPU time per sample (ms)")
    frame_ax.set_title("Frame, per stage", fontsize=10)
    frame_ax.legend(fontsize=8)
    bars = sync_ax.bar(labels, [r["sync_ms"] for r in rows], color="tab:gray")
    for bar, row in zip(bars, rows):
        sync_ax.annotate(f"{row['triangles']:,} tris", (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                         ha="center", va="bottom", fontsize=8)
    sync_ax.set_yscale("log")
    sync_ax.set_ylabel("Blender -> core sync (ms)")
    sync_ax.set_title("Scene sync (first render)", fontsize=10)
    for ax in (frame_ax, sync_ax):
        ax.tick_params(axis="x", labelsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("records")
    parser.add_argument("--csv", required=True)
    parser.add_argument("--markdown", required=True)
    parser.add_argument("--plot", required=True)
    parser.add_argument("--title", default="Bounce per-stage GPU time")
    args = parser.parse_args()
    rows = summarise(load(args.records))
    if not rows:
        sys.exit("no benchmark records")
    with open(args.csv, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    table = markdown(rows)
    with open(args.markdown, "w") as f:
        f.write(table + "\n")
    print(table)
    plot(rows, args.plot, args.title)
    print(f"wrote {args.csv}, {args.markdown}, {args.plot}")


main()
