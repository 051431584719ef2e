"""The work-precision plot: mean PSNR-Y against seconds per frame per setting, with the Pareto front."""

import json
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


METRICS = (("psnr", "PSNR-Y (dB)"), ("ivpsnr", "IV-PSNR (dB)"))
VSRS_LABEL = {"general": "VSRS 4.2 general", "1d": "VSRS 4.2 1D"}


def _place_labels(fig, ax, points, labelled, fontsize=7):
    """Numbers beside the labelled points, placed greedily: of eight offsets around a point, the first whose
    text box overlaps no placed label, no marker and stays inside the axes (else the one overlapping least)."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    box_axes = ax.get_window_extent(renderer)
    marks = []
    for x, y in points:
        px, py = ax.transData.transform((x, y))
        marks.append((px - 4, py - 4, px + 4, py + 4))
    placed = []
    offsets = [(5, 3), (5, -9), (-5, 3), (-5, -9), (0, 7), (0, -13), (9, -3), (-9, -3), (12, 8), (-12, 8),
               (12, -14), (-12, -14)]

    def overlap(a, b):
        return max(0.0, min(a[2], b[2]) - max(a[0], b[0])) * max(0.0, min(a[3], b[3]) - max(a[1], b[1]))

    for number, (x, y) in labelled:
        best = None
        for dx, dy in offsets:
            text = ax.annotate(str(number), (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=fontsize,
                               ha="left" if dx > 0 else ("right" if dx < 0 else "center"), color="0.1")
            bb = text.get_window_extent(renderer)
            box = (bb.x0 - 3, bb.y0 - 2, bb.x1 + 3, bb.y1 + 2)  # a margin: "2" beside "5" must not read "25"
            cost = sum(overlap(box, p) for p in placed) * 10 + sum(overlap(box, m) for m in marks)
            if bb.x0 < box_axes.x0 or bb.x1 > box_axes.x1 or bb.y0 < box_axes.y0 or bb.y1 > box_axes.y1:
                cost += 1e6
            if best is None or cost < best[0]:
                if best is not None:
                    best[1].remove()
                best = (cost, text, box)
            else:
                text.remove()
            if cost == 0:
                break
        placed.append(best[2])


def collect_points(report):
    """Every plotted point: one per setting of each tool (mean over the same (scene, camera) runs) and one per
    VSRS 4.2 mode, all over the (scene, camera) pairs that every point has."""
    plot = report.exp.plot
    scenes = report._scenes_of(plot["groups"])
    cameras = plot.get("cameras")
    per_tool = {}
    common = None
    for tool in [t for t in plot.get("tools", TOOLS) if any(m.tool == t for m in report.exp.methods)]:
        pairs, points = plot_points(report, tool, scenes, cameras)
        if points:
            per_tool[tool] = points
            common = set(pairs) if common is None else common & set(pairs)
    vsrs_modes = plot.get("vsrs", ["general", "1d"])
    for mode in vsrs_modes:
        have = {(s.name, c) for s in scenes for c in s.cameras if (not cameras or c in cameras)
                and report.baseline.get((s.name, c, mode))}
        if have:
            common = have if common is None else common & have
    common = sorted(common or [])
    points = []
    for mode in vsrs_modes:
        rows = [report.baseline.get((sc, c, mode)) for sc, c in common]
        if not rows or None in rows:
            continue
        scores = [report.vsrs_scores.get((sc, c, mode), {}).get("ivpsnr") for sc, c in common]
        points.append(dict(tool="VSRS 4.2", series=VSRS_LABEL.get(mode, mode), method=None, key=mode,
                           psnr=mean([float(r["psnr_y"]) for r in rows]),
                           ivpsnr=mean(scores) if None not in scores else None,
                           seconds=mean([float(r["seconds"]) for r in rows]), cpu=None, tool_s=None,
                           wall=mean([float(r["seconds"]) for r in rows])))
    for tool in per_tool:
        _, tool_points = plot_points(report, tool, scenes, cameras, common)
        for p in tool_points:
            p["series"] = p["method"].label
        points.extend(tool_points)
    return common, points


def plot_section(report):
    """The report's section on quality against run time: the work-precision chart of every tool and VSRS 4.2
    on the same axes, the per-scene gain over VSRS, and their tables (lines of Markdown). The plotted values
    are written beside each image as JSON (checked by scripts/test_experiment.py)."""
    plot = report.exp.plot
    pairs, points = collect_points(report)
    out = ["## Quality against run time\n"]
    if not points:
        out.append("No runs to plot.\n")
        return out
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    kind = plot.get("seconds", "cpu")
    metrics = [(k, t) for k, t in METRICS if all(p.get(k) is not None for p in points)]
    if len(metrics) < len(METRICS):  # a point without IV-PSNR: plot PSNR alone rather than a partial panel
        metrics = METRICS[:1]
    # Which points carry a number: VSRS, the Pareto front of each panel, and every method of a single setting.
    numbered = []
    for k, _ in metrics:
        for i in pareto_front([(p["seconds"], p[k]) for p in points]):
            if i not in numbered:
                numbered.append(i)
    for i, p in enumerate(points):
        if (p["tool"] == "VSRS 4.2" or (p["method"] is not None and len(p["method"].settings_list) == 1)) \
                and i not in numbered:
            numbered.append(i)
    numbered.sort(key=lambda i: (points[i]["seconds"], -points[i]["psnr"]))
    number = {i: n + 1 for n, i in enumerate(numbered)}
    series = []
    for p in points:
        if p["series"] not in series:
            series.append(p["series"])
    styles = {}
    palette = {"VSRS 4.2": ["black", "0.5"], "ViewSyn": ["tab:blue", "tab:cyan", "tab:purple", "tab:olive",
                                                          "mediumblue", "tab:green", "navy"],
               "MeshRender": ["tab:red", "tab:orange", "tab:brown", "tab:pink", "darkred"]}
    markers = {"VSRS 4.2": "*", "ViewSyn": "osD^v<>", "MeshRender": "sDp^v"}
    used = {}
    for name in series:
        tool = next(p["tool"] for p in points if p["series"] == name)
        k = used.get(tool, 0)
        used[tool] = k + 1
        colours, shapes = palette[tool] if tool in palette else ["k"], markers.get(tool, "o")
        styles[name] = (colours[k % len(colours)], shapes[k % len(shapes)])
    fig, axes = plt.subplots(1, len(metrics), figsize=(5.2 * len(metrics), 4.4), squeeze=False, sharex=True)
    for ax, (k, title) in zip(axes[0], metrics):
        for name in series:
            pts = [p for p in points if p["series"] == name]
            colour, shape = styles[name]
            ax.scatter([p["seconds"] for p in pts], [p[k] for p in pts], s=60 if shape == "*" else 22,
                       marker=shape, color=colour, label=name, alpha=0.85, edgecolors="none", zorder=3)
        front = [points[i] for i in pareto_front([(p["seconds"], p[k]) for p in points])]
        ax.plot([p["seconds"] for p in front], [p[k] for p in front], "-", color="0.3", lw=0.9,
                drawstyle="steps-post", label="Pareto front", zorder=2)
        ax.set_xscale("log")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("seconds per frame (log scale)", fontsize=8)
        ax.set_ylabel(title, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3, which="both")
        ys = [p[k] for p in points]
        ax.set_ylim(min(ys) - 0.3, max(ys) + 0.3)
        xs = [p["seconds"] for p in points]
        ax.set_xlim(min(xs) / 1.4, max(xs) * 1.4)
        ticks = [t for t in (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50)
                 if min(xs) / 1.4 <= t <= max(xs) * 1.4]
        ax.set_xticks(ticks)
        ax.set_xticklabels(["%g" % t for t in ticks])
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7, frameon=False)
    rows = (len(labels) + 2) // 3
    fig.tight_layout(rect=(0, 0.04 * rows + 0.01, 1, 1))
    for ax, (k, _) in zip(axes[0], metrics):
        _place_labels(fig, ax, [(p["seconds"], p[k]) for p in points],
                      [(number[i], (points[i]["seconds"], points[i][k])) for i in numbered])
    name = plot.get("file", "work_precision.png")
    fig.savefig(report.image_dir / name, dpi=200)
    plt.close(fig)
    seconds_text = SECONDS_LABEL[kind]
    values = {"pairs": [list(p) for p in pairs], "seconds": kind, "points": [
        {"number": number.get(i), "tool": p["tool"], "series": p["series"], "settings": p["key"],
         "psnr_y": p["psnr"], "ivpsnr": p.get("ivpsnr"), "seconds": p["seconds"]} for i, p in enumerate(points)]}
    (report.image_dir / (os.path.splitext(name)[0] + ".json")).write_text(json.dumps(values, indent=1) + "\n")
    rel = os.path.relpath(report.image_dir / name, report.path.parent)
    n_scenes = len({s for s, _ in pairs})
    cams = sorted({c for _, c in pairs})
    out.append("![PSNR-Y and IV-PSNR against seconds per frame](%s)\n" % rel)
    out.append("One point per setting: the mean PSNR-Y (left) and IV-PSNR (right) over the same %d runs (%d scenes, "
               "%s of %s) against the mean seconds per frame on a log axis: for ViewSyn and MeshRender the %s, for "
               "VSRS 4.2 its single-threaded process wall clock on an idle machine (`vsrs_baseline.csv`, "
               "../shared/tools/README.md). The grey staircase is the Pareto front (no other point is both "
               "faster and better). Numbered points (VSRS, the fronts and every single-setting method):\n"
               % (len(pairs), n_scenes, ", ".join(cams), ", ".join(plot["groups"]), seconds_text))
    out.append("| # | tool | setting | PSNR-Y | IV-PSNR | s/frame |")
    out.append("|---:|---|---|---:|---:|---:|")
    for i in numbered:
        p = points[i]
        setting = ("`%s`" % p["key"]) if p["tool"] != "VSRS 4.2" else p["series"][len("VSRS 4.2 "):]
        if p["tool"] != "VSRS 4.2" and not p["key"]:
            setting = "config as given"
        out.append("| %d | %s | %s%s | %.2f | %s | %.3f |" % (
            number[i], p["tool"], setting, " (%s)" % p["method"].name if p["method"] is not None else "", p["psnr"],
            "%.2f" % p["ivpsnr"] if p.get("ivpsnr") is not None else "–", p["seconds"]))
    out.append("")
    every = {(m.tool, settings_key(s)) for m in report.exp.methods if m.tool in {p["tool"] for p in points}
             and (not m.groups or set(m.groups) & set(plot["groups"])) for s in m.settings_list}
    left_out = len(every - {(p["tool"], p["key"]) for p in points if p["method"] is not None})
    if left_out > 0:
        out.append("%d setting%s of the sweeps had not run on all of these scene-views when this report was written "
                   "and %s left out of the chart; regenerate to add them.\n"
                   % (left_out, "s" if left_out != 1 else "", "are" if left_out != 1 else "is"))
    out.append("<details><summary>Every setting (%d points)</summary>\n" % len(points))
    out.append("| tool | setting | PSNR-Y | IV-PSNR | CPU s/frame | in-tool s/frame | process s/frame |")
    out.append("|---|---|---:|---:|---:|---:|---:|")
    for p in sorted(points, key=lambda p: (p["tool"], p["seconds"])):
        out.append("| %s | `%s` | %.2f | %s | %s | %s | %.3f |" % (
            p["tool"], p["key"] or "config as given", p["psnr"],
            "%.2f" % p["ivpsnr"] if p.get("ivpsnr") is not None else "–",
            "%.3f" % p["cpu"] if p["cpu"] is not None else "–",
            "%.3f" % p["tool_s"] if p["tool_s"] is not None else "–", p["wall"]))
    out.append("\n</details>\n")
    scenes = report._scenes_of(plot["groups"])
    gain_pairs = [(s.name, c) for s in scenes for c in s.cameras if not plot.get("cameras") or c in plot["cameras"]]
    out.extend(gain_section(report, gain_pairs))
    return out


def gain_section(report, pairs):
    """Per scene: PSNR-Y and IV-PSNR gain of each gain method over VSRS 4.2 general, sorted bars."""
    plot = report.exp.plot
    methods = [report.methods[m] for m in plot.get("gain_methods", []) if m in report.methods]
    if not methods:
        return []
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = []
    for scene, camera in pairs:
        base = report.baseline.get((scene, camera, "general"))
        base_iv = report.vsrs_scores.get((scene, camera, "general"), {}).get("ivpsnr")
        if not base:
            continue
        entry = {"scene": scene, "camera": camera, "gain": {}}
        for m in methods:
            r = report.row(scene, camera, m.tool, settings_key(m.settings_list[0]))
            if r is None:
                continue
            iv = _f(r.get("ivpsnr"))
            entry["gain"][m.name] = {"psnr_y": _f(r["psnr_y"]) - float(base["psnr_y"]),
                                     "ivpsnr": iv - base_iv if iv is not None and base_iv is not None else None}
        if len(entry["gain"]) == len(methods):
            rows.append(entry)
    if not rows:
        return []
    first = methods[0].name
    rows.sort(key=lambda e: e["gain"][first]["psnr_y"])
    keys = [("psnr_y", "PSNR-Y gain over VSRS 4.2 general (dB)"), ("ivpsnr", "IV-PSNR gain (dB)")]
    keys = [k for k in keys if all(e["gain"][m.name][k[0]] is not None for e in rows for m in methods)]
    fig, axes = plt.subplots(1, len(keys), figsize=(5.2 * len(keys), 0.26 * len(rows) + 1.4), squeeze=False,
                             sharey=True)
    colours = ["tab:blue", "tab:red", "tab:green", "tab:orange"]
    height = 0.8 / len(methods)
    for ax, (k, title) in zip(axes[0], keys):
        for j, m in enumerate(methods):
            ys = [i + (j - (len(methods) - 1) / 2.0) * height for i in range(len(rows))]
            ax.barh(ys, [e["gain"][m.name][k] for e in rows], height=height, color=colours[j % 4], label=m.label)
        ax.axvline(0, color="k", lw=0.8)
        ax.set_yticks(range(len(rows)))
        ax.set_yticklabels([e["scene"].split("/")[-1] for e in rows], fontsize=7)
        ax.set_title(title, fontsize=9)
        ax.tick_params(axis="x", labelsize=7)
        ax.grid(axis="x", alpha=0.3)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(methods), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.4 / (0.26 * len(rows) + 1.4), 1, 1))
    name = plot.get("gain_file", "gain_over_vsrs.png")
    fig.savefig(report.image_dir / name, dpi=200)
    plt.close(fig)
    (report.image_dir / (os.path.splitext(name)[0] + ".json")).write_text(json.dumps(rows, indent=1) + "\n")
    rel = os.path.relpath(report.image_dir / name, report.path.parent)
    out = ["![Gain over VSRS 4.2 per scene](%s)\n" % rel]
    wins = {m.name: sum(1 for e in rows if e["gain"][m.name]["psnr_y"] > 0) for m in methods}
    out.append("Per scene (%s), the gain in dB over VSRS 4.2 general (PSNR-Y from `vsrs_baseline.csv`, IV-PSNR "
               "of its own output), sorted by the PSNR-Y gain of *%s*; above zero is better than VSRS. Ahead of "
               "VSRS on PSNR-Y: %s.\n" % (
                   ", ".join(sorted({e["camera"] for e in rows})), methods[0].label,
                   "; ".join("*%s* on %d of %d scenes" % (m.label, wins[m.name], len(rows)) for m in methods)))
    return out


def plot_points(report, tool, scenes, cameras=None, pairs=None):
    """Per setting of a tool: a point (method, settings key, mean PSNR-Y, IV-PSNR and seconds) over the
    (scene, camera) pairs that every setting of the tool has (or over `pairs` when given)."""
    methods = [m for m in report.exp.methods if m.tool == tool]
    settings = []
    for m in methods:
        for s in m.settings_list:
            key = settings_key(s)
            if key not in [k for _, k, _ in settings]:
                settings.append((m, key, s))
    if pairs is None:
        # The pairs every single-setting method has (all settings when the tool has no such method): a sweep
        # setting not run on all of them yet is left out rather than shrinking every point's pairs.
        fixed = [(m, key, s) for m, key, s in settings if len(m.settings_list) == 1] or settings
        for _, key, _ in fixed:
            have = {(s.name, c) for s in scenes for c in s.cameras
                    if (not cameras or c in cameras) and report.row(s.name, c, tool, key)}
            if have:  # a setting that never ran on these scenes (a method of other groups) is no point
                pairs = have if pairs is None else pairs & have
    pairs = sorted(pairs or [])
    points = []
    for m, key, s in settings:
        rows = [report.row(sc, c, tool, key) for sc, c in pairs]
        if not rows or None in rows:
            continue
        iv = [_f(r.get("ivpsnr")) for r in rows]
        point = dict(tool=tool, method=m, key=key, settings=s, psnr=mean([_f(r["psnr_y"]) for r in rows]),
                     ivpsnr=mean(iv) if None not in iv else None,
                     cpu=mean([float(r["cpu_s_per_frame"]) for r in rows]),
                     tool_s=mean([float(r["seconds_per_frame"]) for r in rows]),
                     wall=mean([float(r["wall_s_per_frame"]) for r in rows]))
        point["seconds"] = point[{"cpu": "cpu", "tool": "tool_s", "wall": "wall"}[report.exp.plot.get("seconds", "cpu")]]
        points.append(point)
    return pairs, points
