"""The Markdown report: provenance, the comparison tables against VSRS 4.2, the plot section
(plots.py), frame-range splitting, the crops (crops.py) and the experiment file's description."""

import csv
import datetime
import json
import math
import os
import platform
import subprocess
from pathlib import Path

from . import METRIC_COLUMNS, REPO, TOOLS
from .experiment import settings_key
from .crops import make_crop
from . import plots, tools
from .plots import _f, mean



def fnum(value, digits=2):
    return "–" if value is None else ("%.*f" % (digits, value))



class Report:
    def __init__(self, exp, runs, results, path, command, elapsed, query):
        self.exp, self.runs, self.results, self.query = exp, runs, results, query
        self.path = Path(path).resolve()
        self.image_dir = self.path.parent / self.path.stem
        self.command, self.elapsed = command, elapsed
        self.methods = {m.name: m for m in exp.methods}
        self.baseline = self._baseline()
        self.vsrs_scores = {}  # (scene, camera, mode) -> YuvPsnr's means of VSRS 4.2's own output (runner.score_vsrs)

    def _baseline(self):
        path = self.exp.data_dir / self.exp.baseline_file
        table = {}
        if path.is_file():
            with open(path, newline="") as f:
                for r in csv.DictReader(f):
                    table[(r["set"] + "/" + r["scene"], r["target"], r["mode"])] = r
        return table

    def row(self, scene, camera, tool, settings):
        return self.results.get((scene, camera, tool, settings))

    def method_rows(self, method, settings, scenes, camera):
        out = []
        for s in scenes:
            r = self.row(s.name, camera, method.tool, settings_key(settings))
            if r:
                out.append(r)
        return out

    def _scenes_of(self, groups):
        return [s for s in self.exp.scenes if s.group in groups]

    def _cameras_of(self, scenes):
        cams = []
        for s in scenes:
            for c in s.cameras:
                if c not in cams:
                    cams.append(c)
        return cams

    def scope(self, method, scenes, cameras):
        """The scenes and cameras of a table that a method runs on."""
        return ([s for s in scenes if not method.groups or s.group in method.groups],
                [c for c in cameras if not method.cameras or c in method.cameras])

    def best_setting(self, method, scenes, cameras):
        """The setting with the highest mean PSNR-Y among those with the most runs (a setting with
        missing runs must not win on a friendlier subset)."""
        scenes, cameras = self.scope(method, scenes, cameras)
        scored = []
        for settings in method.settings_list:
            values = [_f(r["psnr_y"]) for camera in cameras for r in self.method_rows(method, settings, scenes, camera)]
            if values:
                scored.append((len(values), mean(values), settings))
        if not scored:
            return None
        most = max(n for n, _, _ in scored)
        return max(((v, s) for n, v, s in scored if n == most and v is not None), key=lambda vs: vs[0],
                   default=(None, None))[1]

    def table_rows(self, table):
        """(label, short, {camera: [(scene, psnr_y, seconds, wall)]}) per row of a table spec."""
        scenes = self._scenes_of(table["groups"])
        cameras = self._cameras_of(scenes)
        rows = []
        for spec in table["rows"]:
            cells = {c: [] for c in cameras}
            label = spec["label"]
            if "vsrs" in spec:
                for s in scenes:
                    for c in cameras:
                        b = self.baseline.get((s.name, c, spec["vsrs"]))
                        if b:
                            scores = self.vsrs_scores.get((s.name, c, spec["vsrs"]), {})
                            cells[c].append((s.name, float(b["psnr_y"]), None, None, float(b["seconds"]),
                                             {k: scores.get(k) for k in METRIC_COLUMNS}))
            elif spec["method"] not in self.methods:
                label += " (not run: its tool is not built)"
            else:
                method = self.methods[spec["method"]]
                settings = method.settings_list[0]
                if spec.get("pick") == "best" or len(method.settings_list) > 1:
                    settings = self.best_setting(method, scenes, cameras) or settings
                    label += " (%s)" % (settings_key(settings) or "config as given")
                in_scenes, in_cameras = self.scope(method, scenes, cameras)
                for s in in_scenes:
                    for c in in_cameras:
                        r = self.row(s.name, c, method.tool, settings_key(settings))
                        if r:
                            cells[c].append((s.name, _f(r["psnr_y"]), float(r["cpu_s_per_frame"]),
                                             float(r["seconds_per_frame"]), float(r["wall_s_per_frame"]),
                                             {k: _f(r.get(k)) for k in METRIC_COLUMNS}))
            rows.append((label, spec.get("short", spec.get("method", spec.get("vsrs", "?"))), cells))
        return scenes, cameras, rows

    def write(self):
        self.image_dir.mkdir(parents=True, exist_ok=True)
        out = []
        e = self.exp
        out.append("# %s\n" % e.title)
        out.append("<!-- Generated by scripts/experiment.py; edit %s and regenerate instead of editing this file. -->\n"
                   % os.path.relpath(e.path, REPO))
        if e.description:
            out.append(e.description.strip() + "\n")
        out.append("Regenerate (resumable; finished runs are kept in `%s`):\n\n```\n%s\n```\n"
                   % (os.path.relpath(e.work, REPO), self.command))
        out.append(self._provenance())
        warnings = e.work / "warnings.txt"
        if warnings.is_file() and warnings.read_text().strip():
            out.append("**Warnings from the runs:**\n")
            out.extend("- %s" % line for line in warnings.read_text().splitlines() if line.strip())
            out.append("")
        for tool in e.missing_tools:
            out.append("**%s was not built when this report was made: its rows and plot are missing.** Build it "
                       "(`bash scripts/build.sh build`) and run the command above again: only its runs will run.\n"
                       % tool)
        for table in e.tables:
            out.extend(self._table(table))
        if e.plot:
            out.extend(plots.plot_section(self))
        out.extend(self._split_section())
        if e.crops:
            out.extend(self._crops())
        if e.notes:
            out.append("## Notes\n")
            for note in e.notes:
                out.append(note.strip() + "\n")
        out.append(self._format_appendix())
        self.path.write_text("\n".join(out).rstrip() + "\n")

    def _provenance(self):
        try:
            commit = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"], capture_output=True,
                                    text=True).stdout.strip()
        except OSError:
            commit = ""
        cpu = ""
        try:
            for line in open("/proc/cpuinfo"):
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
        except OSError:
            pass
        rows = list(self.results.values())
        job_wall = sum(float(r["wall_s_per_frame"]) * int(r["frames"]) for r in rows)
        job_cpu = sum(float(r["cpu_s_per_frame"]) * int(r["frames"]) for r in rows)
        invocations = []
        try:
            invocations = [json.loads(line) for line in
                           (self.exp.work / "invocations.jsonl").read_text().splitlines() if line.strip()]
        except (OSError, ValueError):
            pass
        versions = []
        for tool in TOOLS:
            v = _tool_version(self.exp, tool)
            ids = [i["tools"][tool] for i in invocations if tool in i.get("tools", {})]
            if v and ids:
                v += " (%s, md5 %s, built %s%s)" % (
                    ids[-1]["path"], ids[-1]["md5"][:12], ids[-1]["modified"].replace("T", " "),
                    ", a sanitizer build" if ids[-1]["sanitizer"] else "")
            if v:
                versions.append(v)
        took = "wall clock of the invocations that ran jobs (SceneGen included): " + "; ".join(
            "%d runs in %.0f s with `-j %d` (%s, load average %s at the start and %s at the end on %d cores%s)"
            % (i["runs"], i["seconds"], i["jobs"], i["date"][:16].replace("T", " "), i.get("load_start", "?"),
               i.get("load_end", "?"), os.cpu_count() or 0, ", %d failed" % i["failed"] if i["failed"] else "")
            for i in invocations) if invocations else "run time not recorded"
        lines = ["Runs: %d result rows in `%s` (one per scene, camera, tool and setting); the tools' processes "
                 "took %.0f s wall clock and %.0f s CPU in all; %s."
                 % (len(rows), os.path.relpath(self.exp.work / "results.csv", REPO), job_wall, job_cpu, took),
                 "Tools: %s; the repository was at commit %s when this report was written (%s). "
                 "Machine: %d cores (%s), "
                 "shared with other work: wall-clock seconds grow with its load (above), CPU seconds much less."
                 % (", ".join(versions) or "?", commit or "?", datetime.date.today().isoformat(),
                    os.cpu_count() or 0, cpu or platform.machine()),
                 "Every job runs with `Threads=%d` (and `LP_NUM_THREADS=%d` for Mesa's llvmpipe), up to `-j` jobs "
                 "at once. Seconds per frame come three ways: *CPU*, the CPU time of the tool's process (user + "
                 "system, every thread, start-up included), the steadiest figure on a busy shared machine; "
                 "*in-tool*, the tool's own wall-clock total of its stages (read, warp, blend, hole fill, write) "
                 "from its `SummaryFile`; *process*, the wall clock of the whole process. VSRS's seconds in "
                 "`vsrs_baseline.csv` are the process wall clock (median of 7 runs) of single-threaded VSRS on an "
                 "idle 2-core machine. PSNR is over the whole frame against the real (or exactly rendered) view; "
                 "a run's PSNR is the mean over its frames of the per-frame PSNR, as the tools print it."
                 % (self.exp.threads, self.exp.threads)]
        return "\n\n".join(lines) + "\n"

    def _table(self, table):
        scenes, cameras, rows = self.table_rows(table)
        out = ["## %s\n" % table.get("title", "Comparison")]
        if table.get("caption"):
            out.append(table["caption"].strip() + "\n")
        metric_cams = [c for c in table.get("metric_cameras", cameras) if c in cameras]
        head = ("| method | " + " | ".join("PSNR-Y %s" % c for c in cameras) + " | "
                + "".join("IV-PSNR %s | " % c for c in metric_cams) + "".join("SSIM-Y %s | " % c for c in metric_cams)
                + "CPU s/frame | in-tool s/frame | process s/frame |")
        out.append(head)
        out.append("|---|" + "---:|" * (len(cameras) + 2 * len(metric_cams) + 3))
        n = len(scenes)
        for label, short, cells in rows:
            parts = []
            for c in cameras:
                values = [v[1] for v in cells[c]]
                text = fnum(mean(values))
                if values and len(values) < n:
                    text += " (%d/%d)" % (len(values), n)
                parts.append(text)
            for key, digits in (("ivpsnr", 2), ("ssim_y", 4)):
                for c in metric_cams:
                    values = [v[5][key] for v in cells[c] if v[5].get(key) is not None]
                    text = fnum(mean(values), digits)
                    if values and len(values) < n:
                        text += " (%d/%d)" % (len(values), n)
                    parts.append(text)
            cpu, tool, wall = (mean([v[k] for c in cameras for v in cells[c]]) for k in (2, 3, 4))
            out.append("| %s | %s | %s | %s | %s |" % (label, " | ".join(parts), fnum(cpu, 3), fnum(tool, 3),
                                                        fnum(wall, 3)))
        out.append("")
        out.append("Cells: PSNR-Y%s, mean over the %d scene%s of %s; (k/N) marks a mean over fewer scenes. "
                   "Seconds per frame, mean over the runs: *CPU*, the processes' CPU time (user + system, all "
                   "threads); *in-tool*, the tool's own wall-clock total of its stages; *process*, the processes' "
                   "wall clock. VSRS's figure is its process wall clock on an idle machine, single-threaded, so "
                   "compare it with *CPU* when this machine was busy."
                   % (" in dB, IV-PSNR (MPEG-I's metric, which forgives shifts of up to 2 samples and small global "
                      "colour offsets; YUV 4:1:1, [metrics.md](metrics.md)) in dB and SSIM of luma (IV-PSNR "
                      "software 7.1's convention)" if metric_cams else " in dB",
                      n, "s" if n != 1 else "", ", ".join(table["groups"])))
        if metric_cams and any("vsrs" in spec for spec in table["rows"]):
            out.append("VSRS 4.2's IV-PSNR and SSIM are those of its own outputs for %s (`%s`), scored by "
                       "`YuvPsnr --metrics psnr,ivpsnr,ssim --json` against the same reference (cached in `%s`); "
                       "its PSNR-Y as scored so equals `vsrs_baseline.csv`'s." % (
                           ", ".join(metric_cams), os.path.relpath(self.exp.vsrs_outputs, REPO),
                           os.path.relpath(self.exp.work / "vsrs", REPO)))
        if any(v[1] is not None and not math.isfinite(v[1]) for _, _, cells in rows for c in cells for v in cells[c]):
            out.append("An exact frame (infinite PSNR) is left out of a mean.")
        out.append("")
        if table.get("per_scene") and n > 1:
            for c in cameras:
                have = [(label, short, cells) for label, short, cells in rows if cells[c]]
                if not have:
                    continue
                out.append("<details><summary>Per scene, %s (PSNR-Y, dB)</summary>\n" % c)
                out.append("| scene | " + " | ".join(short for _, short, _ in have) + " |")
                out.append("|---|" + "---:|" * len(have))
                for s in scenes:
                    values = []
                    for _, _, cells in have:
                        v = [x[1] for x in cells[c] if x[0] == s.name]
                        values.append(fnum(v[0]) if v else "–")
                    best = max((float(x) for x in values if x != "–"), default=None)
                    values = [("**%s**" % x) if best is not None and x != "–" and float(x) == best else x
                              for x in values]
                    out.append("| %s | %s |" % (s.name.split("/")[-1], " | ".join(values)))
                out.append("\n</details>\n")
        return out

    def _split_section(self):
        rows = [r for r in self.results.values() if r.get("split")]
        if not rows:
            return []
        out = ["## Frame-range splitting\n",
               "Runs of scene groups with `frames_per_job` are split into frame ranges (`StartFrame`, "
               "`TotalNumberOfFrames`) run as separate jobs, and the outputs are joined in frame order. With "
               "`verify_split` the whole range also runs as one job and the two files are compared byte by byte. "
               "ViewSyn runs in 1D mode (or `SynthesisMode auto`) with `TemporalImprovementOption 1` are never "
               "split: that option reuses the previous frame's hole fill in static rows, so a range's first "
               "frame can differ from the same frame of one long run.\n",
               ]
        split = [r for r in rows if int(r["jobs"]) > 1]
        same = [r for r in split if r["split_check"].startswith("identical")]
        differ = [r for r in split if r["split_check"].startswith("DIFFERENT")]
        refused = [r for r in rows if int(r["jobs"]) == 1]
        out.append("Here: %d run%s split into frame ranges; %d of them also ran whole, and the joined output was "
                   "byte-identical to the whole run in %d and different in %d%s. %d run%s not split (1D with "
                   "`TemporalImprovementOption 1`).\n" % (
                       len(split), "s" if len(split) != 1 else "", len(same) + len(differ), len(same), len(differ),
                       (" (**%s**)" % ", ".join("%s %s %s" % (r["scene"], r["tool"], r["settings"]) for r in differ))
                       if differ else "", len(refused), "s" if len(refused) != 1 else ""))
        out.append("<details><summary>Every split or refused run</summary>\n")
        out.append("| scene | camera | tool | setting | frames | jobs | joined output against one run |")
        out.append("|---|---|---|---|---:|---:|---|")
        for r in sorted(rows, key=lambda r: (r["scene"], r["camera"], r["tool"], r["settings"])):
            out.append("| %s | %s | %s | `%s` | %s | %s | %s |" % (
                r["scene"], r["camera"], r["tool"], r["settings"] or "config", r["frames"], r["jobs"],
                r["split_check"] or ("not checked" if int(r["jobs"]) > 1 else r["split"])))
        out.append("\n</details>\n")
        return out

    def _crops(self):
        out = ["## Where the methods differ: crops\n",
               "Each crop: the truth, VSRS 4.2's own output and the tools' outputs over the same window, zoomed "
               "without smoothing, colours as the files have them; above each panel its PSNR-Y over the crop. "
               "The window is picked by a rule, not by hand (each caption says it).\n"]
        for i, crop in enumerate(self.exp.crops):
            try:
                name, caption = make_crop(self, crop, i)
            except Exception as e:  # a missing output should not lose the rest of the report
                out.append("Crop %d (%s %s) failed: %s\n" % (i, crop["scene"], crop["camera"], e))
                continue
            out.append("![crop of %s %s](%s)\n" % (crop["scene"], crop["camera"], os.path.relpath(self.image_dir / name,
                                                                              self.path.parent)))
            out.append(caption + "\n")
        return out

    def _format_appendix(self):
        return ("## The experiment file\n\n"
                "`%s` (JSON; paths relative to the file's folder): `scenes` lists scene groups: data set folders "
                "(`path`, globs under `data`) or SceneGen scenes (`scenegen`: SceneGen keys), the `cameras` to "
                "synthesize, the `config` file pattern per tool (`{camera}` is replaced), the ground truth "
                "`reference` pattern, and optionally `frames_per_job` and `verify_split`. `methods` name a `tool`, "
                "fixed `settings` (`Key: value`, passed as `Key=Value` overrides) and a `sweep` (`Key: [values]`; "
                "every combination is one setting; a list of such objects: their union), optionally restricted "
                "to `groups` and `cameras`. `tables`, `plot` and `crops` say what the report shows. A result "
                "row's key is (scene, camera, tool, settings), so a run shared by two methods runs once, and a "
                "resumed run skips rows already in `results.csv`. The full description: [cfg/experiments/README.md](%s).\n"
                % (os.path.relpath(self.exp.path, REPO),
                   os.path.relpath(REPO / "cfg" / "experiments" / "README.md", self.path.parent)))




def _load():
    """The 1-minute load average, to say how busy the shared machine was."""
    try:
        return Path("/proc/loadavg").read_text().split()[0]
    except OSError:
        return "?"



def _tool_version(exp, tool):
    """"ViewSyn 0.1.0" from the summaries of the runs (SummaryFile)."""
    for path in sorted((exp.work / "runs").glob("*/*/%s/*/*.summary.json" % tool))[:20]:
        try:
            return tools.tool_version(tools.read_summary(path))
        except (OSError, ValueError):
            continue
    return ""




# ----------------------------------------------------------------------------------------------
