"""The experiment file: scenes, methods (settings and sweeps), tables, plot and crops, checked as a
whole (every problem at once)."""

import glob
import hashlib
import itertools
import json
import os
import re
from pathlib import Path

from . import TOOLS, RUNNER_KEYS, ExperimentError


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

    def __init__(self, name, group, folder, cameras, config, reference, frames_per_job, verify_split, scenegen=None,
                 shards=None):
        self.name, self.group, self.folder = name, group, Path(folder)
        self.shards = shards
        self.cameras, self.config, self.reference = list(cameras), config, reference
        self.frames_per_job, self.verify_split, self.scenegen = frames_per_job, verify_split, scenegen

    def config_path(self, tool, camera):
        pattern = self.config[tool] if isinstance(self.config, dict) else self.config
        return self.folder / pattern.format(camera=camera)

    def reference_path(self, camera, configured):
        """The ground truth of `camera`: the group's `reference` pattern, else the config's own
        ReferenceVirtualViewImageName as the tool resolved it (`configured`, None when unset)."""
        if self.reference:
            return self.folder / self.reference.format(camera=camera)
        return Path(configured) if configured else None


class Method:
    def __init__(self, name, label, tool, settings_list, groups, cameras, keep_output):
        self.name, self.label, self.tool = name, label, tool
        self.settings_list = settings_list  # list of dicts Key -> text
        self.groups, self.cameras, self.keep_output = groups, cameras, keep_output


class Experiment:
    """The parsed experiment file. Paths in the file are relative to the file's folder."""

    TOP = {"name", "title", "description", "data", "work", "threads", "scenes", "methods", "tables", "plot", "crops",
           "notes", "baseline", "executor", "slurm", "vsrs_outputs"}

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
        self.executor = spec.get("executor", "local")
        if self.executor not in ("local", "slurm"):
            problems.append("executor: 'local' or 'slurm', not %r" % (self.executor,))
        self.slurm = spec.get("slurm", {})
        if check_keys("slurm", self.slurm, {"partition", "time", "mem", "cpus_per_task", "account", "throttle",
                                            "options", "poll", "jobs_per_task"}, (), problems):
            if not isinstance(self.slurm.get("options", []), list):
                problems.append("slurm.options: a list of sbatch options, e.g. [\"--qos=long\"]")
        else:
            self.slurm = {}
        self.vsrs_outputs = self.data_dir / spec.get("vsrs_outputs", "vsrs42-outputs")
        self.scenes = self._scenes(spec["scenes"], problems)
        self.methods = self._methods(spec["methods"], problems)
        self.tables = spec.get("tables", [])
        self.plot = spec.get("plot")
        self.crops = spec.get("crops", [])
        names = {m.name for m in self.methods}
        groups = {s.group for s in self.scenes}
        for i, table in enumerate(self.tables):
            where = "tables[%d]" % i
            if check_keys(where, table, {"title", "groups", "rows", "per_scene", "caption", "metric_cameras"}, ("groups", "rows"),
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
        if self.plot is not None and check_keys("plot", self.plot, {"file", "groups", "tools", "title", "seconds", "cameras", "gain_file",
                                                        "gain_methods", "vsrs"},
                                                ("groups",), problems):
            if self.plot.get("seconds", "cpu") not in ("cpu", "tool", "wall"):
                problems.append("plot.seconds: one of cpu, tool, wall")
            for g in self.plot["groups"]:
                if g not in groups:
                    problems.append("plot: unknown group '%s'" % g)
        for i, crop in enumerate(self.crops):
            where = "crops[%d]" % i
            if check_keys(where, crop, {"scene", "camera", "methods", "size", "zoom", "frame", "file", "at", "caption", "vsrs"},
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
        allowed = {"group", "path", "scenegen", "name", "cameras", "config", "reference", "frames_per_job", "shards",
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
                          verify_split=entry.get("verify_split", False), shards=entry.get("shards"))
            if "shards" in entry and "frames_per_job" in entry:
                problems.append("%s: give at most one of 'frames_per_job' and 'shards'" % where)
            if "shards" in entry and (not isinstance(entry["shards"], int) or isinstance(entry["shards"], bool)
                                      or entry["shards"] < 1):
                problems.append("%s.shards: a whole number of frame ranges, at least 1" % where)
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
