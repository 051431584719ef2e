#!/usr/bin/env python3
"""Experiment runner: runs ViewSyn and MeshRender over scenes, cameras and parameter sweeps, in parallel
and resumably, writes one CSV row per run and, with --report, a Markdown report with the classic
comparison table against VSRS 4.2, a work-precision plot and zoomed crops around depth edges.

    python3 scripts/experiment.py cfg/experiments/middlebury.json -j 2 --report doc/results.md

The experiment file format is described in doc/results.md's appendix and in cfg/experiments/README.md;
in short it is JSON with the sections "scenes", "methods", "tables", "plot" and "crops".
Only the Python standard library is needed to run experiments; the report's plots and crops need the
Debian packages python3-matplotlib and python3-numpy.
"""

import argparse
import concurrent.futures
import csv
import datetime
import glob
import hashlib
import itertools
import json
import math
import os
import platform
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
TOOLS = ("ViewSyn", "MeshRender")
STAGES = ("read_s", "depth_warp_s", "texture_warp_s", "blend_s", "hole_fill_s", "write_s")
RESULT_FIELDS = ("scene", "group", "camera", "tool", "settings", "config", "frames", "jobs", "split", "split_check",
                 "psnr_y", "psnr_u", "psnr_v", "psnr_yuv", "seconds_per_frame") + STAGES + (
                 "wall_s_per_frame", "cpu_s_per_frame", "output", "finished")
# Keys the runner sets itself on every command line; an experiment may not set them.
RUNNER_KEYS = {"StartFrame", "OutputVirtualViewImageName", "ReferenceVirtualViewImageName", "ReportFile", "Threads"}


class ExperimentError(Exception):
    """Bad experiment file or command line: every problem found, one a line."""


# ----------------------------------------------------------------------------------------------
# Small file formats: VSRS configs, camera files, the tools' report CSV and their stdout summary.

def read_vsrs_config(path):
    """Key -> value text of a VSRS-style config (`Key value # comment`, the last setting wins)."""
    values = {}
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            parts = line.split(None, 1)
            values[parts[0]] = parts[1].strip() if len(parts) > 1 else ""
    return values


def read_camera_file(path):
    """name -> (K 3x3, R 3x3, t 3) from a VSRS 4.x camera parameter file (R world to camera, t centre)."""
    tokens = Path(path).read_text().split()
    cameras, i = {}, 0
    while i + 24 <= len(tokens):
        name = tokens[i]
        numbers = [float(x) for x in tokens[i + 1:i + 24]]
        k = [numbers[0:3], numbers[3:6], numbers[6:9]]
        rt = numbers[11:23]
        r = [rt[0:3], rt[4:7], rt[8:11]]
        t = [rt[3], rt[7], rt[11]]
        cameras[name] = (k, r, t)
        i += 24
    return cameras


def read_tool_report(path):
    """Rows of a ViewSyn/MeshRender ReportFile as dicts (numbers still text)."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


MEAN_PSNR = re.compile(r"^mean PSNR: Y (\S+) U (\S+) V (\S+) YUV (\S+) dB", re.M)


def frame_mean(values):
    """Mean PSNR as the tools compute it: over frames with a finite PSNR; inf when every frame is exact."""
    finite = [float(v) for v in values if v not in ("inf", "")]
    if not finite:
        return "inf" if values else ""
    return "%.4f" % (sum(finite) / len(finite))


# ----------------------------------------------------------------------------------------------
# The experiment file.

def setting_text(value):
    """A JSON value as the tools read it: 4 -> '4', 0.05 -> '0.05', 1.0 -> '1.0', 'auto' -> 'auto'."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ExperimentError("setting values must be numbers or text, not %r" % (value,))
    return str(value)


def settings_key(settings):
    """Canonical text of a setting: `Key=Value` sorted by key, space separated ('' for the config as is)."""
    return " ".join("%s=%s" % (k, settings[k]) for k in sorted(settings))


def slug(text, limit=80):
    s = re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("_") or "config"
    if len(s) > limit:
        s = s[:limit - 9] + "_" + hashlib.sha1(text.encode()).hexdigest()[:8]
    return s


def check_keys(where, obj, allowed, required, problems):
    if not isinstance(obj, dict):
        problems.append("%s: expected an object" % where)
        return False
    for key in obj:
        if key not in allowed:
            near = min(allowed, key=lambda a: _distance(a, key))
            problems.append("%s: unknown key '%s' (did you mean '%s'?)" % (where, key, near))
    for key in required:
        if key not in obj:
            problems.append("%s: missing key '%s'" % (where, key))
    return True


def _distance(a, b):
    prev = list(range(len(b) + 1))
    for i, ca in enumerate(a, 1):
        cur = [i]
        for j, cb in enumerate(b, 1):
            cur.append(min(prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (ca.lower() != cb.lower())))
        prev = cur
    return prev[-1]


class Scene:
    """One scene folder with the cameras to synthesize and how to find their configs."""

    def __init__(self, name, group, folder, cameras, config, reference, frames_per_job, verify_split, scenegen=None):
        self.name, self.group, self.folder = name, group, Path(folder)
        self.cameras, self.config, self.reference = list(cameras), config, reference
        self.frames_per_job, self.verify_split, self.scenegen = frames_per_job, verify_split, scenegen

    def config_path(self, tool, camera):
        pattern = self.config[tool] if isinstance(self.config, dict) else self.config
        return self.folder / pattern.format(camera=camera)

    def reference_path(self, camera, config_values):
        if self.reference:
            return self.folder / self.reference.format(camera=camera)
        name = config_values.get("ReferenceVirtualViewImageName")
        return self.folder / name if name else None


class Method:
    def __init__(self, name, label, tool, settings_list, groups, cameras, keep_output):
        self.name, self.label, self.tool = name, label, tool
        self.settings_list = settings_list  # list of dicts Key -> text
        self.groups, self.cameras, self.keep_output = groups, cameras, keep_output


class Experiment:
    """The parsed experiment file. Paths in the file are relative to the file's folder."""

    TOP = {"name", "title", "description", "data", "work", "threads", "scenes", "methods", "tables", "plot", "crops",
           "notes", "baseline"}

    def __init__(self, path, data_override=None, work_override=None):
        self.path = Path(path).resolve()
        try:
            spec = json.loads(self.path.read_text())
        except (OSError, ValueError) as e:
            raise ExperimentError("%s: %s" % (path, e))
        problems = []
        check_keys(str(path), spec, self.TOP, ("scenes", "methods"), problems)
        if problems:
            raise ExperimentError("\n".join(problems))
        base = self.path.parent
        self.spec = spec
        self.name = spec.get("name", self.path.stem)
        self.title = spec.get("title", self.name)
        self.description = spec.get("description", "")
        data = data_override or os.environ.get("VS_DATA_DIR") or spec.get("data", "../../shared/data")
        self.data_dir = (Path.cwd() / data) if data_override or os.environ.get("VS_DATA_DIR") else (base / data)
        self.data_dir = self.data_dir.resolve()
        work = work_override or spec.get("work", "../../out/experiments/" + self.name)
        self.work = ((Path.cwd() / work) if work_override else (base / work)).resolve()
        self.threads = int(spec.get("threads", 1))
        self.notes = spec.get("notes", [])
        self.baseline_file = spec.get("baseline", "vsrs_baseline.csv")
        self.scenes = self._scenes(spec["scenes"], problems)
        self.methods = self._methods(spec["methods"], problems)
        self.tables = spec.get("tables", [])
        self.plot = spec.get("plot")
        self.crops = spec.get("crops", [])
        names = {m.name for m in self.methods}
        groups = {s.group for s in self.scenes}
        for i, table in enumerate(self.tables):
            where = "tables[%d]" % i
            if check_keys(where, table, {"title", "groups", "rows", "per_scene", "caption"}, ("groups", "rows"),
                          problems):
                for g in table["groups"]:
                    if g not in groups:
                        problems.append("%s: unknown group '%s'" % (where, g))
                for j, row in enumerate(table["rows"]):
                    w = "%s.rows[%d]" % (where, j)
                    check_keys(w, row, {"label", "short", "method", "pick", "vsrs"}, ("label",), problems)
                    if "method" in row and row["method"] not in names:
                        problems.append("%s: unknown method '%s'" % (w, row["method"]))
                    if ("method" in row) == ("vsrs" in row):
                        problems.append("%s: give exactly one of 'method' and 'vsrs'" % w)
        if self.plot is not None and check_keys("plot", self.plot, {"file", "groups", "tools", "title", "seconds"},
                                                ("groups",), problems):
            if self.plot.get("seconds", "cpu") not in ("cpu", "tool", "wall"):
                problems.append("plot.seconds: one of cpu, tool, wall")
            for g in self.plot["groups"]:
                if g not in groups:
                    problems.append("plot: unknown group '%s'" % g)
        for i, crop in enumerate(self.crops):
            where = "crops[%d]" % i
            if check_keys(where, crop, {"scene", "camera", "methods", "size", "zoom", "frame", "file", "at", "caption"},
                          ("scene", "camera", "methods"), problems):
                for m in crop["methods"]:
                    if m not in names:
                        problems.append("%s: unknown method '%s'" % (where, m))
                if not any(s.name == crop["scene"] for s in self.scenes):
                    problems.append("%s: unknown scene '%s'" % (where, crop["scene"]))
        if problems:
            raise ExperimentError("\n".join("%s: %s" % (self.path.name, p) for p in problems))
        # The runs a crop shows keep their outputs.
        self.crop_keep = {(c["scene"], c["camera"], m) for c in self.crops for m in c["methods"]}
        self.missing_tools = []  # tools not built: their methods are left out (see main)

    def _scenes(self, entries, problems):
        scenes, seen = [], set()
        allowed = {"group", "path", "scenegen", "name", "cameras", "config", "reference", "frames_per_job",
                   "verify_split"}
        for i, entry in enumerate(entries):
            where = "scenes[%d]" % i
            if not check_keys(where, entry, allowed, ("group", "cameras", "config"), problems):
                continue
            if ("path" in entry) == ("scenegen" in entry):
                problems.append("%s: give exactly one of 'path' (data set folders) and 'scenegen'" % where)
                continue
            config = entry["config"]
            if isinstance(config, dict):
                for tool in config:
                    if tool not in TOOLS:
                        problems.append("%s.config: unknown tool '%s' (tools: %s)" % (where, tool, ", ".join(TOOLS)))
            common = dict(group=entry["group"], cameras=entry["cameras"], config=config,
                          reference=entry.get("reference"), frames_per_job=entry.get("frames_per_job"),
                          verify_split=entry.get("verify_split", False))
            if "scenegen" in entry:
                name = entry.get("name") or entry["scenegen"].get("Scene", "demo")
                folder = self.work / "scenes" / slug(name)
                found = [Scene("scenegen/" + name, folder=folder, scenegen=entry["scenegen"], **common)]
            else:
                paths = entry["path"] if isinstance(entry["path"], list) else [entry["path"]]
                found = []
                for p in paths:
                    matches = sorted(glob.glob(str(self.data_dir / p)))
                    matches = [m for m in matches if os.path.isdir(m)]
                    if not matches:
                        problems.append("%s: no scene folder matches %s" % (where, self.data_dir / p))
                    for m in matches:
                        rel = os.path.relpath(m, self.data_dir)
                        found.append(Scene(rel.replace(os.sep, "/"), folder=m, **common))
                for scene in found:
                    for camera in scene.cameras:
                        tools = config.keys() if isinstance(config, dict) else TOOLS[:1]
                        for tool in tools:
                            if not scene.config_path(tool, camera).is_file():
                                problems.append("%s: %s does not exist" % (where, scene.config_path(tool, camera)))
            for scene in found:
                if scene.name in seen:
                    problems.append("%s: scene %s listed twice" % (where, scene.name))
                seen.add(scene.name)
                scenes.append(scene)
        return scenes

    def _methods(self, entries, problems):
        methods, names = [], set()
        allowed = {"name", "label", "tool", "settings", "sweep", "groups", "cameras", "keep_output"}
        for i, entry in enumerate(entries):
            where = "methods[%d]" % i
            if not check_keys(where, entry, allowed, ("name", "tool"), problems):
                continue
            if entry["tool"] not in TOOLS:
                problems.append("%s: unknown tool '%s' (tools: %s)" % (where, entry["tool"], ", ".join(TOOLS)))
                continue
            if entry["name"] in names:
                problems.append("%s: method name '%s' used twice" % (where, entry["name"]))
            names.add(entry["name"])
            fixed = entry.get("settings", {})
            # A sweep is {Key: [values]} (every combination), or a list of such: the union of their
            # combinations, e.g. Filter only where Precision is not 1 (integer positions need no filter).
            sweeps = entry.get("sweep", {})
            sweeps = sweeps if isinstance(sweeps, list) else [sweeps]
            keys_used = set(fixed)
            for k, sweep in enumerate(sweeps):
                if not isinstance(sweep, dict):
                    problems.append("%s.sweep[%d]: expected an object {Key: [values]}" % (where, k))
                    sweeps = []
                    break
                keys_used |= set(sweep)
                for key, values in sweep.items():
                    if not isinstance(values, list) or not values:
                        problems.append("%s.sweep.%s: expected a non-empty list" % (where, key))
            for key in sorted(keys_used):
                if key in RUNNER_KEYS:
                    problems.append("%s: '%s' is set by the runner and cannot be a setting" % (where, key))
            try:
                base = {k: setting_text(v) for k, v in fixed.items()}
                settings_list, seen_keys = [], set()
                for sweep in sweeps or [{}]:
                    keys = sorted(sweep)
                    for combo in itertools.product(*(sweep[k] for k in keys)):
                        s = dict(base)
                        s.update({k: setting_text(v) for k, v in zip(keys, combo)})
                        if settings_key(s) not in seen_keys:
                            seen_keys.add(settings_key(s))
                            settings_list.append(s)
            except (ExperimentError, TypeError) as e:
                problems.append("%s: %s" % (where, e))
                continue
            methods.append(Method(entry["name"], entry.get("label", entry["name"]), entry["tool"], settings_list,
                                  entry.get("groups"), entry.get("cameras"), bool(entry.get("keep_output", False))))
        return methods


# ----------------------------------------------------------------------------------------------
# Runs and jobs.

class Run:
    """One result row: a scene, a camera, a tool and a setting; done in one or more jobs (parts)."""

    def __init__(self, scene, camera, tool, settings):
        self.scene, self.camera, self.tool, self.settings = scene, camera, tool, settings
        self.key = (scene.name, camera, tool, settings_key(settings))
        self.keep_output = False
        self.methods = []
        self.parts = []          # (start, count) per job
        self.split_note = ""
        self.verify = False

    @property
    def settings_text(self):
        return self.key[3]

    def folder(self, work):
        """Every file of the run: output.yuv, and per job (run, part000, ..., whole) its .log, .report.csv,
        .yuv (parts only, until joined) and .done (until the row is written)."""
        return work / "runs" / slug(self.scene.name) / slug(self.camera) / self.tool / slug(self.settings_text)

    def output_path(self, work):
        return self.folder(work) / "output.yuv"


def plan_runs(exp):
    runs = {}
    for method in exp.methods:
        for scene in exp.scenes:
            if method.groups and scene.group not in method.groups:
                continue
            for camera in scene.cameras:
                if method.cameras and camera not in method.cameras:
                    continue
                for settings in method.settings_list:
                    run = Run(scene, camera, method.tool, settings)
                    run = runs.setdefault(run.key, run)
                    run.keep_output |= method.keep_output or (scene.name, camera, method.name) in exp.crop_keep
                    if method.name not in run.methods:
                        run.methods.append(method.name)
    problems = []
    for run in runs.values():
        cfg_path = run.scene.config_path(run.tool, run.camera)
        if not cfg_path.is_file():
            problems.append("%s: no %s config %s" % (run.scene.name, run.tool, cfg_path))
            continue
        values = read_vsrs_config(cfg_path)
        values.update(run.settings)
        run.config_path = cfg_path
        run.config_values = values
        run.reference = run.scene.reference_path(run.camera, values)
        if run.reference is None:
            problems.append("%s %s: no reference view (give the scene group a 'reference' pattern)"
                            % (run.scene.name, run.camera))
        start = int(values.get("StartFrame", 0))
        total = int(values.get("TotalNumberOfFrames", 300))
        run.start, run.total = start, total
        step = run.scene.frames_per_job
        run.parts = [(start, total)]
        if step and total > step:
            mode = values.get("SynthesisMode", "auto").strip()
            temporal = values.get("TemporalImprovementOption", "1").strip()
            if run.tool == "ViewSyn" and mode != "0" and temporal != "0":
                # 1D TemporalImprovementOption keeps the previous frame's hole fill where a row is static,
                # so the first frame of a later range could differ from the same frame of one run.
                run.split_note = ("not split: SynthesisMode %s with TemporalImprovementOption 1 carries the "
                                  "previous frame's hole fill" % mode)
            else:
                run.parts = [(s, min(step, start + total - s)) for s in range(start, start + total, step)]
                run.split_note = "%d frames per job" % step
                verify = run.scene.verify_split
                run.verify = bool(verify) if not isinstance(verify, list) else any(m in verify for m in run.methods)
    if problems:
        raise ExperimentError("\n".join(sorted(set(problems))))
    return list(runs.values())


def read_results(path):
    if not path.is_file():
        return {}
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {(r["scene"], r["camera"], r["tool"], r["settings"]): r for r in rows}


class Progress:
    """A progress bar on a terminal (stderr), a plain line per finished job otherwise."""

    def __init__(self, total, stream=sys.stderr):
        self.total, self.done, self.failed, self.stream = total, 0, 0, stream
        self.tty = stream.isatty()
        self.start = time.monotonic()
        self.lock = threading.Lock()
        self.running = 0

    def _eta(self):
        elapsed = time.monotonic() - self.start
        if self.done == 0:
            return elapsed, None
        return elapsed, elapsed / self.done * (self.total - self.done)

    def started(self):
        with self.lock:
            self.running += 1
            self._draw()

    def finished(self, line, failed=False):
        with self.lock:
            self.running -= 1
            self.done += 1
            self.failed += failed
            if self.tty:
                self.stream.write("\r\x1b[K%s\n" % line if failed else "")
            else:
                self.stream.write("[%d/%d] %s\n" % (self.done, self.total, line))
            self._draw()
            self.stream.flush()

    def _draw(self):
        if not self.tty:
            return
        elapsed, left = self._eta()
        width = 30
        filled = int(width * self.done / max(1, self.total))
        text = "\r\x1b[K[%s%s] %d/%d jobs, %d running, %s elapsed" % (
            "#" * filled, "-" * (width - filled), self.done, self.total, self.running, _clock(elapsed))
        if left is not None:
            text += ", ~%s left" % _clock(left)
        if self.failed:
            text += ", %d FAILED" % self.failed
        self.stream.write(text)
        self.stream.flush()

    def close(self):
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()


def _clock(seconds):
    seconds = int(seconds)
    return "%d:%02d" % (seconds // 60, seconds % 60)


class Runner:
    def __init__(self, exp, bin_dir, jobs, quiet=False):
        self.exp, self.bin_dir, self.jobs = exp, Path(bin_dir), jobs
        self.results_path = exp.work / "results.csv"
        self.lock = threading.Lock()
        self.processes = set()
        self.stop = threading.Event()
        self.failures = []
        self.quiet = quiet
        self.tool_ids = {}  # tool -> binary identity, filled when jobs run

    # -- scenes --
    def generate_scenes(self):
        for scene in self.exp.scenes:
            if not scene.scenegen:
                continue
            args = ["%s=%s" % (k, setting_text(v)) for k, v in sorted(scene.scenegen.items())]
            marker = scene.folder / ".scenegen-done"
            stamp = json.dumps(args)
            if marker.is_file() and marker.read_text() == stamp:
                continue
            scene.folder.mkdir(parents=True, exist_ok=True)
            cmd = [str(self.bin_dir / "SceneGen")] + args + ["OutputFolder=%s" % scene.folder,
                                                             "Threads=%d" % max(1, self.jobs)]
            self.say("generating %s: %s" % (scene.name, " ".join(cmd)))
            log = scene.folder / "scenegen.log"
            with open(log, "w") as f:
                rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
            if rc != 0:
                raise ExperimentError("SceneGen failed (exit %d), see %s" % (rc, log))
            marker.write_text(stamp)
        # Configs of generated scenes exist only now: check them.
        missing = [str(s.config_path(t, c)) for s in self.exp.scenes if s.scenegen for c in s.cameras
                   for t in (s.config.keys() if isinstance(s.config, dict) else TOOLS[:1])
                   if not s.config_path(t, c).is_file()]
        if missing:
            raise ExperimentError("configs missing after SceneGen: " + ", ".join(missing))

    def say(self, text):
        if not self.quiet:
            print(text, flush=True)

    # -- one job --
    def command(self, run, start, count, output, report):
        cmd = [str(self.bin_dir / run.tool), str(run.config_path)]
        cmd += ["%s=%s" % (k, v) for k, v in sorted(run.settings.items())]
        cmd += ["StartFrame=%d" % start, "TotalNumberOfFrames=%d" % count,
                "OutputVirtualViewImageName=%s" % output, "ReferenceVirtualViewImageName=%s" % run.reference,
                "ReportFile=%s" % report, "Threads=%d" % self.exp.threads]
        return cmd

    def execute(self, run, index, start, count):
        """Runs one part (index >= 0) or the verification run of the whole range (index -1)."""
        folder = run.folder(self.exp.work)
        stem = "whole" if index < 0 else ("part%03d" % index if len(run.parts) > 1 else "run")
        output = run.output_path(self.exp.work) if stem == "run" else folder / (stem + ".yuv")
        report = folder / (stem + ".report.csv")
        log = folder / (stem + ".log")
        done = folder / (stem + ".done")
        if done.is_file() and output.is_file() and report.is_file():
            return json.loads(done.read_text())
        folder.mkdir(parents=True, exist_ok=True)
        for p in (output, report, done):
            if p.exists():
                p.unlink()
        cmd = self.command(run, start, count, output, report)
        env = dict(os.environ)
        env["LP_NUM_THREADS"] = str(self.exp.threads)  # Mesa llvmpipe: as many render threads as Threads
        env["OMP_NUM_THREADS"] = str(self.exp.threads)
        began = time.monotonic()
        with open(log, "w") as f:
            f.write("# cwd %s\n# %s\n" % (run.scene.folder, " ".join(cmd)))
            f.flush()
            proc = subprocess.Popen(cmd, cwd=str(run.scene.folder), stdout=f, stderr=subprocess.STDOUT, env=env)
            with self.lock:
                self.processes.add(proc)
            # wait4: the CPU time of the tool (every thread), which a busy shared machine disturbs far
            # less than the wall clock.
            _, status, usage = os.wait4(proc.pid, 0)
            rc = proc.returncode = os.waitstatus_to_exitcode(status)
            with self.lock:
                self.processes.discard(proc)
        wall = time.monotonic() - began
        cpu = usage.ru_utime + usage.ru_stime
        text = log.read_text(errors="replace")
        if rc != 0:
            tail = "\n".join(text.strip().splitlines()[-6:])
            raise RuntimeError("%s exited with %d (log %s):\n%s" % (run.tool, rc, log, tail))
        rows = read_tool_report(report)
        if len(rows) != count:
            raise RuntimeError("%s wrote %d report rows, expected %d (log %s)" % (run.tool, len(rows), count, log))
        info = {"wall": wall, "cpu": cpu, "rows": rows, "output": str(output)}
        m = MEAN_PSNR.search(text)
        if m:
            info["printed"] = m.groups()
        first = text.splitlines()[2] if len(text.splitlines()) > 2 else ""
        info["version"] = first.strip()
        done.write_text(json.dumps(info))
        return info

    def join(self, run, infos):
        output = run.output_path(self.exp.work)
        if len(infos) > 1:
            with open(output, "wb") as out:
                for info in infos:
                    with open(info["output"], "rb") as part:
                        shutil.copyfileobj(part, out, 1 << 22)
        return output

    def tidy(self, run):
        """Parts, check runs and done markers go; logs and per-job reports stay; the joined output stays
        only when a method or crop wants it."""
        output = run.output_path(self.exp.work)
        for p in run.folder(self.exp.work).iterdir():
            if p.suffix == ".done" or (p.suffix == ".yuv" and p != output):
                p.unlink()
        if not run.keep_output and output.exists():
            output.unlink()

    def finish(self, run, infos, whole):
        """Joins the parts of a run, checks the split against the whole run, writes the result row."""
        rows = [r for info in infos for r in info["rows"]]
        frames = len(rows)
        output = self.join(run, infos)
        if len(infos) > 1:
            # The mean of the per-frame values the tool reported (4 decimals): within 1e-4 dB of the mean
            # one run would print from unrounded values.
            psnr = [frame_mean([r["psnr_" + c] for r in rows]) for c in ("y", "u", "v", "yuv")]
        else:
            psnr = list(infos[0].get("printed") or [frame_mean([r["psnr_" + c] for r in rows])
                                                    for c in ("y", "u", "v", "yuv")])
        check = ""
        if whole is not None:
            check = "identical" if _same_file(output, whole["output"]) else "DIFFERENT"
            if check == "identical":
                check += " (md5 %s)" % _md5(output)
        row = {
            "scene": run.scene.name, "group": run.scene.group, "camera": run.camera, "tool": run.tool,
            "settings": run.settings_text, "config": os.path.relpath(run.config_path, run.scene.folder),
            "frames": frames, "jobs": len(run.parts), "split": run.split_note, "split_check": check,
            "psnr_y": psnr[0], "psnr_u": psnr[1], "psnr_v": psnr[2], "psnr_yuv": psnr[3],
            "seconds_per_frame": "%.6f" % (sum(float(r["total_s"]) for r in rows) / frames),
            "wall_s_per_frame": "%.6f" % (sum(i["wall"] for i in infos) / frames),
            "cpu_s_per_frame": "%.6f" % (sum(i["cpu"] for i in infos) / frames),
            "output": os.path.relpath(output, self.exp.work) if run.keep_output else "",
            "finished": datetime.datetime.now().isoformat(timespec="seconds"),
        }
        for stage in STAGES:
            row[stage] = "%.6f" % (sum(float(r[stage]) for r in rows) / frames)
        self.append_row(row)
        self.tidy(run)
        return row

    def check_builds(self, tools):
        """Timings of a sanitizer build mean nothing: say so now and in the report (work/warnings.txt).
        Also notes which binaries ran (md5, modification time) for the report."""
        for tool in sorted(tools):
            path = self.bin_dir / tool
            try:
                data = path.read_bytes()
            except OSError:
                continue
            self.tool_ids[tool] = {"path": str(path), "md5": hashlib.md5(data).hexdigest(),
                                   "modified": datetime.datetime.fromtimestamp(path.stat().st_mtime)
                                   .isoformat(timespec="seconds"),
                                   "sanitizer": b"__asan_init" in data or b"__ubsan_handle" in data}
            if b"__asan_init" in data or b"__ubsan_handle" in data:
                text = ("%s: %s is a sanitizer build (AddressSanitizer/UBSan): its seconds are not those of a "
                        "Release build" % (datetime.datetime.now().isoformat(timespec="seconds"), path))
                print("warning: " + text, file=sys.stderr)
                with open(self.exp.work / "warnings.txt", "a") as f:
                    f.write(text + "\n")

    def restore_output(self, run, infos):
        """A kept output was deleted after its row was written: the jobs ran again; join, and name the
        output in the row."""
        output = self.join(run, infos)
        self.tidy(run)
        with self.lock:
            rows = list(read_results(self.results_path).values())
            for r in rows:
                if (r["scene"], r["camera"], r["tool"], r["settings"]) == run.key:
                    r["output"] = os.path.relpath(output, self.exp.work)
            tmp = self.results_path.with_suffix(".tmp")
            with open(tmp, "w", newline="") as f:
                writer = csv.DictWriter(f, fieldnames=RESULT_FIELDS)
                writer.writeheader()
                writer.writerows(rows)
            os.replace(tmp, self.results_path)
        return run.reuse_row

    def append_row(self, row):
        with self.lock:
            new = not self.results_path.is_file()
            with open(self.results_path, "a", newline="") as f:
                writer = csv.DictWriter(f, fieldnames=RESULT_FIELDS)
                if new:
                    writer.writeheader()
                writer.writerow(row)

    # -- the whole experiment --
    def run_all(self, runs):
        self.exp.work.mkdir(parents=True, exist_ok=True)
        existing = read_results(self.results_path)
        todo = []
        for run in runs:
            row = existing.get(run.key)
            if row is None:
                todo.append(run)
            elif run.keep_output and not run.output_path(self.exp.work).is_file():
                # The row exists but the output a crop needs is gone: make it again, keep the row.
                run.reuse_row = row
                todo.append(run)
        skipped = len(runs) - len(todo)
        jobs = [(run, i, s, n) for run in todo for i, (s, n) in enumerate(run.parts)]
        jobs += [(run, -1, run.start, run.total) for run in todo if run.verify and len(run.parts) > 1]

        def cost(job):
            run, _, _, n = job
            v = run.config_values
            pixels = int(v.get("SourceWidth", 1280)) * int(v.get("SourceHeight", 960))
            return pixels * n * (4 if run.tool == "MeshRender" else 1)
        jobs.sort(key=cost, reverse=True)
        self.say("%s: %d runs, %d already in %s, %d to run as %d jobs (-j %d)"
                 % (self.exp.name, len(runs), skipped, self.results_path, len(todo), len(jobs), self.jobs))
        if not jobs:
            return 0, skipped
        self.check_builds({run.tool for run in todo})
        progress = Progress(len(jobs))
        pending = {id(run): {"parts": {}, "whole": None,
                             "left": len(run.parts) + (1 if run.verify and len(run.parts) > 1 else 0)}
                   for run in todo}

        def work(job):
            run, index, start, count = job
            if self.stop.is_set():
                return job, None, "stopped"
            progress.started()
            try:
                info = self.execute(run, index, start, count)
            except Exception as e:  # reported, the run is left for a later resume
                if self.stop.is_set():
                    return job, None, "stopped"  # terminated by us: not a failure of the tool
                progress.finished("FAILED %s %s %s %s: %s" % (run.scene.name, run.camera, run.tool,
                                                              run.settings_text or "(config)", e), failed=True)
                return job, None, str(e)
            row = None
            with self.lock:
                state = pending[id(run)]
                if index < 0:
                    state["whole"] = info
                else:
                    state["parts"][index] = info
                state["left"] -= 1
                complete = state["left"] == 0
            if complete:
                infos = [state["parts"][i] for i in range(len(run.parts))]
                if getattr(run, "reuse_row", None):
                    row = self.restore_output(run, infos)
                else:
                    row = self.finish(run, infos, state["whole"])
            what = "%s %s %s %s" % (run.scene.name, run.camera, run.tool, run.settings_text or "(config)")
            if len(run.parts) > 1 or index < 0:
                what += " [%s]" % ("whole-range check" if index < 0 else "frames %d-%d" % (start, start + count - 1))
            if row:
                what += ": Y %s dB, %.3f s/frame" % (row["psnr_y"], float(row["seconds_per_frame"]))
                if row.get("split_check"):
                    what += ", split %s" % row["split_check"].split()[0]
            progress.finished(what)
            return job, row, None

        with concurrent.futures.ThreadPoolExecutor(max_workers=self.jobs) as pool:
            futures = [pool.submit(work, job) for job in jobs]
            try:
                for future in concurrent.futures.as_completed(futures):
                    job, row, error = future.result()
                    if error and error != "stopped":
                        self.failures.append((job[0], error))
            except KeyboardInterrupt:
                self.stop.set()
                pool.shutdown(wait=False, cancel_futures=True)
                with self.lock:
                    for proc in self.processes:
                        proc.terminate()
                progress.close()
                raise
        progress.close()
        return len(todo), skipped


def _same_file(a, b):
    if os.path.getsize(a) != os.path.getsize(b):
        return False
    with open(a, "rb") as fa, open(b, "rb") as fb:
        while True:
            x, y = fa.read(1 << 22), fb.read(1 << 22)
            if x != y:
                return False
            if not x:
                return True


def _md5(path):
    h = hashlib.md5()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 22), b""):
            h.update(block)
    return h.hexdigest()


# ----------------------------------------------------------------------------------------------
# Report: tables, the work-precision plot and the crops.

def mean(values):
    values = [v for v in values if v is not None and math.isfinite(v)]
    return sum(values) / len(values) if values else None


def fnum(value, digits=2):
    return "–" if value is None else ("%.*f" % (digits, value))


def pareto_front(points):
    """Indices of points (seconds, psnr) that no other point beats on both: faster and at least as good."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], -points[i][1]))
    front, best = [], -math.inf
    for i in order:
        if points[i][1] > best:
            front.append(i)
            best = points[i][1]
    return front


class Report:
    def __init__(self, exp, runs, results, path, command, elapsed):
        self.exp, self.runs, self.results = exp, runs, results
        self.path = Path(path).resolve()
        self.image_dir = self.path.parent / self.path.stem
        self.command, self.elapsed = command, elapsed
        self.methods = {m.name: m for m in exp.methods}
        self.baseline = self._baseline()

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
                            cells[c].append((s.name, float(b["psnr_y"]), None, None, float(b["seconds"])))
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
                                             float(r["seconds_per_frame"]), float(r["wall_s_per_frame"])))
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
            out.extend(self._plot())
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
                 "from its `ReportFile`; *process*, the wall clock of the whole process. VSRS's seconds in "
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
        head = "| method | " + " | ".join(cameras) + " | CPU s/frame | in-tool s/frame | process s/frame |"
        out.append(head)
        out.append("|---|" + "---:|" * (len(cameras) + 3))
        n = len(scenes)
        for label, short, cells in rows:
            parts = []
            for c in cameras:
                values = [v[1] for v in cells[c]]
                text = fnum(mean(values))
                if values and len(values) < n:
                    text += " (%d/%d)" % (len(values), n)
                parts.append(text)
            cpu, tool, wall = (mean([v[k] for c in cameras for v in cells[c]]) for k in (2, 3, 4))
            out.append("| %s | %s | %s | %s | %s |" % (label, " | ".join(parts), fnum(cpu, 3), fnum(tool, 3),
                                                        fnum(wall, 3)))
        out.append("")
        out.append("Cells: PSNR-Y in dB, mean over the %d scene%s of %s; (k/N) marks a mean over fewer scenes. "
                   "Seconds per frame, mean over the runs: *CPU*, the processes' CPU time (user + system, all "
                   "threads); *in-tool*, the tool's own wall-clock total of its stages; *process*, the processes' "
                   "wall clock. VSRS's figure is its process wall clock on an idle machine, single-threaded, so "
                   "compare it with *CPU* when this machine was busy."
                   % (n, "s" if n != 1 else "", ", ".join(table["groups"])))
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

    def _plot_points(self, tool, scenes):
        """Per setting of a tool: (label, method, settings, mean psnr_y, mean seconds, mean wall) over the
        (scene, camera) pairs that every setting of the tool has."""
        methods = [m for m in self.exp.methods if m.tool == tool]
        settings = []
        for m in methods:
            for s in m.settings_list:
                key = settings_key(s)
                if key not in [k for _, k, _ in settings]:
                    settings.append((m, key, s))
        pairs = None
        for _, key, _ in settings:
            have = {(s.name, c) for s in scenes for c in s.cameras if self.row(s.name, c, tool, key)}
            if have:  # a setting that never ran on these scenes (a method of other groups) is no point
                pairs = have if pairs is None else pairs & have
        pairs = sorted(pairs or [])
        points = []
        for m, key, s in settings:
            rows = [self.row(sc, c, tool, key) for sc, c in pairs]
            if not rows or None in rows:
                continue
            point = dict(method=m, key=key, settings=s, psnr=mean([_f(r["psnr_y"]) for r in rows]),
                         cpu=mean([float(r["cpu_s_per_frame"]) for r in rows]),
                         tool=mean([float(r["seconds_per_frame"]) for r in rows]),
                         wall=mean([float(r["wall_s_per_frame"]) for r in rows]))
            point["seconds"] = point[self.exp.plot.get("seconds", "cpu")]
            points.append(point)
        return pairs, points

    def _plot(self):
        plot = self.exp.plot
        scenes = self._scenes_of(plot["groups"])
        tools = [t for t in plot.get("tools", TOOLS)]
        data = {}
        for tool in tools:
            pairs, points = self._plot_points(tool, scenes)
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
        fig.savefig(self.image_dir / name, dpi=90)
        plt.close(fig)
        rel = os.path.relpath(self.image_dir / name, self.path.parent)
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
        out = ["## Zoomed crops around depth edges\n"]
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


SECONDS_LABEL = {"cpu": "CPU seconds per frame (process, 1 thread)", "tool": "seconds per frame (in-tool wall clock)",
                 "wall": "seconds per frame (process wall clock)"}


def _load():
    """The 1-minute load average, to say how busy the shared machine was."""
    try:
        return Path("/proc/loadavg").read_text().split()[0]
    except OSError:
        return "?"


def _f(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def _tool_version(exp, tool):
    for log in sorted((exp.work / "runs").glob("*/*/%s/*/*.log" % tool))[:20]:
        try:
            lines = log.read_text(errors="replace").splitlines()
        except OSError:
            continue
        for line in lines[2:6]:
            if line.startswith(tool + " "):
                return line.strip()
    return ""


SHORT = {"Precision": "P", "Filter": "F", "IvsrsInpaint": "I", "ViewBlending": "B", "SynthesisMode": "M",
         "MeshGridStep": "G", "MeshDiscontinuityThreshold": "T", "TemporalImprovementOption": "TI"}


def _short_setting(key):
    parts = []
    for item in key.split():
        k, v = item.split("=", 1)
        parts.append(SHORT.get(k, k) + v)
    return " ".join(parts) or "config"


# ----------------------------------------------------------------------------------------------
# Crops around depth edges.

def read_yuv_frame(path, width, height, frame=0, chroma="420", bit_depth=8):
    import numpy as np
    dtype = np.dtype(np.uint8) if bit_depth <= 8 else np.dtype("<u2")
    cw, ch = {"420": (width // 2, height // 2), "444": (width, height), "400": (0, 0)}[chroma]
    count = width * height + 2 * cw * ch
    data = np.fromfile(path, dtype=dtype, count=count, offset=frame * count * dtype.itemsize)
    if data.size != count:
        raise ValueError("%s: frame %d is beyond the end" % (path, frame))
    y = data[:width * height].reshape(height, width).astype(np.float64)
    if chroma == "400":
        return y, None, None
    u = data[width * height:width * height + cw * ch].reshape(ch, cw).astype(np.float64)
    v = data[width * height + cw * ch:].reshape(ch, cw).astype(np.float64)
    return y, u, v


def yuv_to_rgb(y, u, v, bit_depth=8):
    """BT.601 limited range to 8-bit RGB for display; chroma repeated to luma size."""
    import numpy as np
    scale = float(1 << (bit_depth - 8))
    y, u, v = y / scale, (u / scale if u is not None else None), (v / scale if v is not None else None)
    if u is None:
        u = v = np.full_like(y, 128.0)
    else:
        fy, fx = y.shape[0] // u.shape[0], y.shape[1] // u.shape[1]
        u = np.repeat(np.repeat(u, fy, axis=0), fx, axis=1)
        v = np.repeat(np.repeat(v, fy, axis=0), fx, axis=1)
    c, d, e = y - 16.0, u - 128.0, v - 128.0
    r = 1.164383 * c + 1.596027 * e
    g = 1.164383 * c - 0.391762 * d - 0.812968 * e
    b = 1.164383 * c + 2.017232 * d
    return np.clip(np.stack([r, g, b], axis=-1), 0, 255).astype(np.uint8)


def depth_edge_window(cfg_path, values, frame, size):
    """Centre (u, v) in the virtual view of the window with the strongest depth gradient of the left
    reference depth, found by summing |gradient| over every window and moving the best one into the
    virtual camera with its nearest depth."""
    import numpy as np
    folder = Path(cfg_path).parent
    width, height = int(values["SourceWidth"]), int(values["SourceHeight"])
    bits = int(values.get("DepthBitDepth", 8))
    depth, _, _ = read_yuv_frame(folder / values["LeftDepthMapName"], width, height, frame,
                                 values.get("DepthChromaFormat", "420"), bits)
    gx = np.zeros_like(depth)
    gy = np.zeros_like(depth)
    gx[:, 1:] = np.abs(np.diff(depth, axis=1))
    gy[1:, :] = np.abs(np.diff(depth, axis=0))
    grad = np.minimum(gx + gy, float((1 << bits) - 1) / 4)  # a few huge steps should not win alone
    cw, ch = size
    integral = np.zeros((height + 1, width + 1))
    integral[1:, 1:] = grad.cumsum(0).cumsum(1)
    sums = integral[ch:, cw:] - integral[:-ch, cw:] - integral[ch:, :-cw] + integral[:-ch, :-cw]
    # Keep the window away from the borders, where warping leaves the frame.
    margin_x, margin_y = width // 8, height // 8
    inside = np.zeros(sums.shape, dtype=bool)
    inside[margin_y:max(margin_y + 1, sums.shape[0] - margin_y),
           margin_x:max(margin_x + 1, sums.shape[1] - margin_x)] = True
    sums = np.where(inside, sums, -1)
    top, left = np.unravel_index(int(np.argmax(sums)), sums.shape)
    u, v = left + cw / 2.0, top + ch / 2.0
    block = depth[top:top + ch, left:left + cw]
    level = float(block.max())  # the foreground's level: the edge belongs to the nearer object
    lmax = float((1 << bits) - 1)
    znear, zfar = float(values["LeftNearestDepthValue"]), values["LeftFarthestDepthValue"]
    inv_far = 0.0 if zfar.strip().lower() == "inf" else 1.0 / float(zfar)
    z = 1.0 / ((level / lmax) * (1.0 / znear - inv_far) + inv_far)
    cams = read_camera_file(folder / values["CameraParameterFile"])
    kl, rl, tl = cams[values["LeftCameraName"]]
    kv, rv, tv = cams[values["VirtualCameraName"]]
    k_l, r_l, k_v, r_v = (np.array(a) for a in (kl, rl, kv, rv))
    if int(values.get("DepthType", 0)) != 0:
        return u, v, (left, top)  # world-z depth: keep the reference position
    x_cam = z * np.linalg.solve(k_l, np.array([u, v, 1.0]))
    world = r_l.T @ x_cam + np.array(tl)
    p = k_v @ (r_v @ (world - np.array(tv)))
    return p[0] / p[2], p[1] / p[2], (left, top)


def make_crop(report, crop, index):
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    exp = report.exp
    scene = next(s for s in exp.scenes if s.name == crop["scene"])
    camera = crop["camera"]
    frame = int(crop.get("frame", 0))
    cw, ch = crop.get("size", [96, 72])
    zoom = int(crop.get("zoom", 3))
    panels = []
    first_cfg = None
    for name in crop["methods"]:
        if name not in report.methods:
            continue  # its tool is not built
        method = report.methods[name]
        settings = settings_key(method.settings_list[0])
        row = report.row(scene.name, camera, method.tool, settings)
        output = Run(scene, camera, method.tool, method.settings_list[0]).output_path(exp.work)
        if not row or not output.is_file():
            raise RuntimeError("no kept output of %s for %s %s" % (name, scene.name, camera))
        cfg = scene.config_path(method.tool, camera)
        values = read_vsrs_config(cfg)
        values.update(method.settings_list[0])
        first_cfg = first_cfg or (cfg, values)
        panels.append((method.label, output, row))
    cfg, values = first_cfg
    width, height = int(values["SourceWidth"]), int(values["SourceHeight"])
    chroma = values.get("ChromaFormat", "420")
    bits = int(values.get("TextureBitDepth", 8))
    if "at" in crop:  # a window chosen by hand, e.g. where two methods differ most
        left, top = (int(x) for x in crop["at"])
        left, top = min(max(left, 0), width - cw), min(max(top, 0), height - ch)
        where = "chosen in the experiment file (`at`)"
    else:
        u, v, (ref_left, ref_top) = depth_edge_window(cfg, values, frame, (cw, ch))
        left = int(round(min(max(u - cw / 2.0, 0), width - cw)))
        top = int(round(min(max(v - ch / 2.0, 0), height - ch)))
        where = ("where the left reference depth (%s) has its strongest gradient, window at (%d, %d) there, moved "
                 "into the virtual camera with the foreground's depth" % (values["LeftDepthMapName"], ref_left,
                                                                         ref_top))
    reference = scene.reference_path(camera, values)
    images = [("original", reference, None)] + panels
    fig, axes = plt.subplots(1, len(images), figsize=(len(images) * cw * zoom / 100.0, ch * zoom / 100.0 + 0.45),
                             squeeze=False)
    for ax, (title, path, row) in zip(axes[0], images):
        y, uu, vv = read_yuv_frame(path, width, height, frame, chroma, bits)
        rgb = yuv_to_rgb(y, uu, vv, bits)[top:top + ch, left:left + cw]
        ax.imshow(rgb, interpolation="nearest")
        if row is not None:
            err = np.abs(y[top:top + ch, left:left + cw] -
                         read_yuv_frame(reference, width, height, frame, chroma, bits)[0][top:top + ch, left:left + cw])
            title = "%s\ncrop PSNR-Y %.2f dB" % (title, _psnr(err, bits))
        else:
            title = "%s (%s)\n%s" % (title, Path(path).name, "frame %d" % frame)
        ax.set_title(title, fontsize=7)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.subplots_adjust(left=0.005, right=0.995, bottom=0.01, top=0.86, wspace=0.03)
    name = crop.get("file", "crop_%s_%s.png" % (slug(scene.name.split("/")[-1]).lower(), camera))
    fig.savefig(report.image_dir / name, dpi=100)
    plt.close(fig)
    caption = "%s, %s, frame %d: a %dx%d window at (%d, %d) of the synthesized view, zoomed %dx, %s." % (
        scene.name, camera, frame, cw, ch, left, top, zoom, where)
    if crop.get("caption"):
        caption += " " + crop["caption"].strip()
    return name, caption


def _psnr(abs_err, bits):
    mse = float((abs_err ** 2).mean())
    peak = float((1 << bits) - 1)
    return math.inf if mse == 0 else 10 * math.log10(peak * peak / mse)


# ----------------------------------------------------------------------------------------------

def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("experiment", help="experiment file (JSON)")
    parser.add_argument("-j", "--jobs", type=int, default=1, help="jobs at once (default 1)")
    parser.add_argument("--report", help="write the Markdown report here; its images go to a folder named after it")
    parser.add_argument("--work", help="work folder (default: the file's 'work')")
    parser.add_argument("--data", help="data set folder (default: VS_DATA_DIR or the file's 'data')")
    parser.add_argument("--bin", default=str(REPO / "Bin"), help="folder of the executables (default Bin/)")
    parser.add_argument("--list", action="store_true", help="list the runs and their jobs (generating SceneGen "
                        "scenes if needed), run no synthesis")
    parser.add_argument("--no-run", action="store_true", help="run nothing; report from the results there are")
    parser.add_argument("--quiet", action="store_true", help="no summary lines (the progress bar stays)")
    args = parser.parse_args(argv)
    began = time.monotonic()

    load_start = _load()

    def terminate(signum, frame):
        raise KeyboardInterrupt()
    signal.signal(signal.SIGTERM, terminate)  # stop the tools and keep what finished, as for Ctrl-C
    try:
        if args.jobs < 1:
            raise ExperimentError("-j must be at least 1")
        exp = Experiment(args.experiment, args.data, args.work)
        runner = Runner(exp, args.bin, args.jobs, args.quiet)
        for tool in sorted({m.tool for m in exp.methods} | ({"SceneGen"} if any(s.scenegen for s in exp.scenes)
                                                            else set())):
            if (Path(args.bin) / tool).is_file():
                continue
            if tool != "MeshRender":
                raise ExperimentError("%s not found in %s (build first: bash scripts/build.sh build)"
                                      % (tool, args.bin))
            # MeshRender is optional (it needs OpenGL): run the rest, and say so in the report.
            print("warning: %s not found in %s: its runs are left out" % (tool, args.bin), file=sys.stderr)
            exp.missing_tools.append(tool)
            exp.methods = [m for m in exp.methods if m.tool != tool]
        if not args.no_run:
            runner.generate_scenes()  # also for --list: the runs of a generated scene come from its configs
        elif any(s.scenegen and not (s.folder / ".scenegen-done").is_file() for s in exp.scenes):
            raise ExperimentError("SceneGen scenes are not generated yet in %s: run without --no-run"
                                  % exp.work)
        runs = plan_runs(exp)
        if args.list:
            existing = read_results(exp.work / "results.csv")
            for run in runs:
                print("%-4s %s %s %s %s jobs=%d %s" % ("done" if run.key in existing else "todo", run.scene.name,
                                                       run.camera, run.tool, run.settings_text or "(config)",
                                                       len(run.parts), run.split_note))
            return 0
        if not args.no_run:
            ran, skipped = runner.run_all(runs)
            elapsed = time.monotonic() - began
            runner.say("ran %d runs, skipped %d already done, %.1f s" % (ran, skipped, elapsed))
            if ran:
                # The report's run time: every invocation that ran something, one JSON object a line.
                with open(exp.work / "invocations.jsonl", "a") as f:
                    f.write(json.dumps({
                        "seconds": round(elapsed, 1), "runs": ran, "skipped": skipped, "jobs": args.jobs,
                        "failed": len(runner.failures), "load_start": load_start, "load_end": _load(),
                        "tools": runner.tool_ids,
                        "date": datetime.datetime.now().isoformat(timespec="seconds")}) + "\n")
        if runner.failures:
            for run, error in runner.failures:
                print("failed: %s %s %s %s: %s" % (run.scene.name, run.camera, run.tool, run.settings_text, error),
                      file=sys.stderr)
        if args.report:
            results = read_results(exp.work / "results.csv")
            wanted = {run.key for run in runs}
            results = {k: v for k, v in results.items() if k in wanted}
            command = "python3 scripts/experiment.py %s -j %d --report %s" % (
                os.path.relpath(exp.path, Path.cwd()), args.jobs, os.path.relpath(Path(args.report).resolve(),
                                                                                 Path.cwd()))
            Report(exp, runs, results, args.report, command, time.monotonic() - began).write()
            runner.say("report: %s" % args.report)
        return 1 if runner.failures else 0
    except ExperimentError as e:
        print("error: %s" % e, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("\ninterrupted: finished runs are kept; run the same command again to resume", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
