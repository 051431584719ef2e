"""The work-precision plot: mean PSNR-Y against seconds per frame per setting, with the Pareto front."""

import math
import os

from . import TOOLS
from .experiment import settings_key


SECONDS_LABEL = {"cpu": "CPU seconds per frame (process, 1 thread)", "tool": "seconds per frame (in-tool wall clock)",
                 "wall": "seconds per frame (process wall clock)"}


def mean(values):
    values = [v for v in values if v is not None and math.isfinite(v)]
    return sum(values) / len(values) if values else None

def _f(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


SHORT = {"Precision": "P", "Filter": "F", "IvsrsInpaint": "I", "ViewBlending": "B", "SynthesisMode": "M",
         "MeshGridStep": "G", "MeshDiscontinuityThreshold": "T", "TemporalImprovementOption": "TI"}


def _short_setting(key):
    parts = []
    for item in key.split():
        k, v = item.split("=", 1)
        parts.append(SHORT.get(k, k) + v)
    return " ".join(parts) or "config"


def pareto_front(points):
    """Indices of points (seconds, psnr) that no other point beats on both: faster and at least as good."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], -points[i][1]))
    front, best = [], -math.inf
    for i in order:
        if points[i][1] > best:
            front.append(i)
            best = points[i][1]
    return front


def plot_section(report):
    """The report's section on error against run time: the figure and its tables (lines of Markdown)."""
    plot = report.exp.plot
    scenes = report._scenes_of(plot["groups"])
    tools = [t for t in plot.get("tools", TOOLS)]
    data = {}
    for tool in tools:
        pairs, points = plot_points(report, tool, scenes)
        if points:
            data[tool] = (pairs, points)
    out = ["## Error against run time\n"]
    if not data:
        out.append("No runs to plot.\n")
        return out
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(data), figsize=(5.0 * len(data), 3.8), squeeze=False)
    markers = "osD^v<>p*h"
    for ax, (tool, (pairs, points)) in zip(axes[0], data.items()):
        methods = []
        for p in points:
            if p["method"] not in methods:
                methods.append(p["method"])
        for k, m in enumerate(methods):
            pts = [p for p in points if p["method"] is m]
            ax.scatter([p["seconds"] for p in pts], [p["psnr"] for p in pts], s=18, marker=markers[k % 10],
                       label=m.label, alpha=0.75)
        front = [points[i] for i in pareto_front([(p["seconds"], p["psnr"]) for p in points])]
        ax.plot([p["seconds"] for p in front], [p["psnr"] for p in front], "k-", lw=1, drawstyle="steps-post",
                label="Pareto front")
        for p in front:
            ax.annotate(_short_setting(p["key"]), (p["seconds"], p["psnr"]), fontsize=6,
                        xytext=(3, -8), textcoords="offset points")
        ax.set_title("%s (%d runs a point)" % (tool, len(pairs)), fontsize=9)
        ax.set_xlabel(SECONDS_LABEL[plot.get("seconds", "cpu")], fontsize=8)
        ax.set_ylabel("mean PSNR-Y (dB)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, loc="best")
    fig.tight_layout()
    name = plot.get("file", "work_precision.png")
    fig.savefig(report.image_dir / name, dpi=90)
    plt.close(fig)
    rel = os.path.relpath(report.image_dir / name, report.path.parent)
    out.append("![PSNR-Y against seconds per frame](%s)\n" % rel)
    out.append("One point per setting: mean PSNR-Y against mean %s over the same (scene, camera) runs of %s; "
               "the black staircase is the Pareto front (no other setting is both faster and better). Labels: "
               "P Precision, F Filter, I IvsrsInpaint, B ViewBlending, M SynthesisMode, G MeshGridStep, "
               "T MeshDiscontinuityThreshold.\n" % (SECONDS_LABEL[plot.get("seconds", "cpu")],
                                                     ", ".join(plot["groups"])))
    for tool, (pairs, points) in data.items():
        cams = sorted({c for _, c in pairs})
        front_idx = set(pareto_front([(p["seconds"], p["psnr"]) for p in points]))
        out.append("### %s: %d settings, each over %d runs (%d scenes x %s)\n"
                   % (tool, len(points), len(pairs), len({s for s, _ in pairs}), ", ".join(cams)))
        front = sorted((points[i] for i in front_idx), key=lambda p: p["seconds"])
        out.append("On the Pareto front, fastest first (seconds per frame: CPU / in-tool / process wall): "
                   + "; ".join("`%s` %.2f dB at %.3f / %.3f / %.3f s" % (
                       p["key"] or "config as given", p["psnr"], p["cpu"], p["tool"], p["wall"])
                       for p in front) + ".\n")
        out.append("<details><summary>Every setting</summary>\n")
        out.append("| setting | PSNR-Y | CPU s/frame | in-tool s/frame | process s/frame | front |")
        out.append("|---|---:|---:|---:|---:|:---:|")
        for i, p in sorted(enumerate(points), key=lambda ip: ip[1]["seconds"]):
            out.append("| `%s` | %.2f | %.3f | %.3f | %.3f | %s |" % (
                p["key"] or "config as given", p["psnr"], p["cpu"], p["tool"], p["wall"],
                "*" if i in front_idx else ""))
        out.append("\n</details>\n")
    return out



def plot_points(report, tool, scenes):
    """Per setting of a tool: (label, method, settings, mean psnr_y, mean seconds, mean wall) over the
    (scene, camera) pairs that every setting of the tool has."""
    methods = [m for m in report.exp.methods if m.tool == tool]
    settings = []
    for m in methods:
        for s in m.settings_list:
            key = settings_key(s)
            if key not in [k for _, k, _ in settings]:
                settings.append((m, key, s))
    pairs = None
    for _, key, _ in settings:
        have = {(s.name, c) for s in scenes for c in s.cameras if report.row(s.name, c, tool, key)}
        if have:  # a setting that never ran on these scenes (a method of other groups) is no point
            pairs = have if pairs is None else pairs & have
    pairs = sorted(pairs or [])
    points = []
    for m, key, s in settings:
        rows = [report.row(sc, c, tool, key) for sc, c in pairs]
        if not rows or None in rows:
            continue
        point = dict(method=m, key=key, settings=s, psnr=mean([_f(r["psnr_y"]) for r in rows]),
                     cpu=mean([float(r["cpu_s_per_frame"]) for r in rows]),
                     tool=mean([float(r["seconds_per_frame"]) for r in rows]),
                     wall=mean([float(r["wall_s_per_frame"]) for r in rows]))
        point["seconds"] = point[report.exp.plot.get("seconds", "cpu")]
        points.append(point)
    return pairs, points
