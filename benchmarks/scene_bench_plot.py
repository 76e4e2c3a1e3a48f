"""Plots what bounce_scene_bench measured (benchmarks/scene_bench.cpp):

    python3 benchmarks/scene_bench_plot.py OUT.png A.csv [B.csv ...]

One panel per scene, one bar per method: its median wall time per sample, split into the stages' GPU times
(Topology's stages run on the CPU and count their render-thread time); what the stages leave of the wall time is
drawn as "other" (synchronisation, CPU work between stages). Needs matplotlib.
"""
import csv
import statistics
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(paths):
    """{scene: {method: {stage: median ms per sample}}}, the wall time under "wall"."""
    values = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                gpu = float(row["gpu_ms_per_sample"]) if row["gpu_ms_per_sample"] else 0.0
                cost = gpu if gpu > 0.0 else float(row["cpu_ms_per_sample"])
                values[row["scene"]][row["method"]][row["stage"]].append(cost)
    return {scene: {method: {stage: statistics.median(v) for stage, v in stages.items()}
                    for method, stages in methods.items()} for scene, methods in values.items()}


def main(out, paths):
    data = load(paths)
    stages = sorted({s for methods in data.values() for st in methods.values() for s in st if s != "wall"})
    colours = {s: plt.cm.tab20(i % 20) for i, s in enumerate(stages + ["other"])}
    fig, axes = plt.subplots(1, len(data), figsize=(max(9.0, 4.5 * len(data)), 5.0), squeeze=False)
    for ax, (scene, methods) in zip(axes[0], sorted(data.items())):
        for x, (method, st) in enumerate(methods.items()):
            bottom = 0.0
            for stage in stages:
                if st.get(stage, 0.0) > 0.0:
                    ax.bar(x, st[stage], bottom=bottom, color=colours[stage], label=stage)
                    bottom += st[stage]
            other = st.get("wall", bottom) - bottom
            if other > 0.0:
                ax.bar(x, other, bottom=bottom, color=colours["other"], label="other")
        ax.set_xticks(range(len(methods)), list(methods), rotation=30, ha="right")
        ax.set_title(scene)
        ax.set_ylabel("ms per sample")
    handles = {}
    for ax in axes[0]:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, handle)
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=4, fontsize="small")
    fig.tight_layout(rect=(0, 0.2, 1, 1))
    fig.savefig(out, dpi=110)
    print(f"scene_bench_plot: {out}")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
