"""Runs and jobs: the runs an experiment asks for, their frame-range jobs, the tools' processes, and
results.csv (one row per run, resumable)."""

import csv
import datetime
import hashlib
import json
import os
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

from . import METRIC_COLUMNS, QUALITY_METRICS, RESULT_FIELDS, STAGES, TOOLS, ExperimentError
from .experiment import setting_text, settings_key, slug
from . import tools
from .executors import LocalExecutor, execute_job, finished_job


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
        """Every file of the run: output.yuv, and per job (run, part000, ..., whole) its .log, .summary.json,
        .yuv (parts only, until joined) and .done (until the row is written)."""
        return work / "runs" / slug(self.scene.name) / slug(self.camera) / self.tool / slug(self.settings_text)

    def output_path(self, work):
        return self.folder(work) / "output.yuv"


def frame_mean(values):
    """Mean PSNR as the tools compute it: over frames with a finite PSNR; inf when every frame is exact."""
    finite = [float(v) for v in values if v not in ("inf", "")]
    if not finite:
        return "inf" if values else ""
    return "%.4f" % (sum(finite) / len(finite))


def check_settings(exp, query):
    """Gives every setting of every method once to its tool (`--print-config` with one config of the
    method's scenes): a misspelt key or a bad value is refused here, before anything runs, with the
    tool's own message (which names the nearest key)."""
    problems = []
    for method in exp.methods:
        configs = [s.config_path(method.tool, c) for s in exp.scenes
                   if not method.groups or s.group in method.groups
                   for c in s.cameras if not method.cameras or c in method.cameras]
        configs = [c for c in configs if c.is_file()]
        if not configs:
            continue
        for settings in method.settings_list:
            try:
                query.print_config(method.tool, configs[0].resolve(), settings)
            except ExperimentError as e:
                problems.append("method %s, setting '%s': %s" % (method.name, settings_key(settings) or "(config)", e))
    if problems:
        raise ExperimentError("\n".join(problems))


def plan_runs(exp, query):
    """Every run of the experiment (a run shared by two methods once), with its frame ranges. The
    effective config of each run is the tool's (`--print-config`) plus the run's settings."""
    check_settings(exp, query)
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
        try:
            answer = query.print_config(run.tool, cfg_path.resolve())
        except ExperimentError as e:
            problems.append("%s %s: %s" % (run.scene.name, run.camera, e))
            continue
        values = {k: v for k, v in answer["config"].items() if v != tools.NOT_SET}
        values.update(run.settings)
        run.config_path = cfg_path
        run.config_values = values
        run.reference = run.scene.reference_path(run.camera, answer["scene"].get("reference"))
        if run.reference is None:
            problems.append("%s %s: no reference view (give the scene group a 'reference' pattern)"
                            % (run.scene.name, run.camera))
        start = int(values.get("StartFrame", 0))
        total = int(values.get("TotalNumberOfFrames", 300))
        run.start, run.total = start, total
        step = run.scene.frames_per_job
        shards = min(total, run.scene.shards or 1)
        run.parts = [(start, total)]
        if (step and total > step) or shards > 1:
            mode = values.get("SynthesisMode", "auto").strip()
            temporal = values.get("TemporalImprovementOption", "1").strip()
            if run.tool == "ViewSyn" and mode != "0" and temporal != "0":
                # 1D TemporalImprovementOption keeps the previous frame's hole fill where a row is static,
                # and that fill was itself kept from the frame before: a row static since frame 0 still
                # shows frame 0's fill at frame 299. No fixed number of earlier frames that a shard could
                # run and drop makes it exact, so the run is not split (the test shows the difference).
                run.split_note = ("not split: SynthesisMode %s with TemporalImprovementOption 1 carries the "
                                  "previous frame's hole fill" % mode)
            else:
                if shards > 1:  # K ranges as equal as can be, the longer ones first
                    sizes = [total // shards + (i < total % shards) for i in range(shards)]
                    firsts = [start + sum(sizes[:i]) for i in range(shards)]
                    run.parts = list(zip(firsts, sizes))
                    run.split_note = "%d shards" % shards
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
    def __init__(self, exp, bin_dir, jobs, quiet=False, executor=None):
        self.exp, self.bin_dir, self.jobs = exp, Path(bin_dir), jobs
        self.executor = executor or LocalExecutor()
        self.results_path = exp.work / "results.csv"
        self.lock = threading.Lock()
        self.processes = set()
        self.stop = threading.Event()
        self.failures = []
        self.quiet = quiet
        self.tool_ids = {}  # tool -> binary identity, filled when jobs run
        self.query = tools.ToolQuery(self.bin_dir)

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

    def score_vsrs(self):
        """VSRS 4.2's own outputs (experiment key `vsrs_outputs`: a folder of SCENE_CAMERA_MODE.yuv, e.g.
        Art_view3_general.yuv) scored against each scene's reference with `YuvPsnr --metrics psnr,ivpsnr,ssim
        --json`; the JSON files are kept in WORK/vsrs/ and reused. Returns {(scene, camera, mode): mean}."""
        folder = getattr(self.exp, "vsrs_outputs", None)
        scores = {}
        if not folder or not folder.is_dir() or not (self.bin_dir / "YuvPsnr").is_file():
            return scores
        baseline = {}
        path = self.exp.data_dir / self.exp.baseline_file
        if path.is_file():
            with open(path, newline="") as f:
                for r in csv.DictReader(f):
                    baseline[(r["set"] + "/" + r["scene"], r["target"])] = (int(r["width"]), int(r["height"]))
        cache = self.exp.work / "vsrs"
        cache.mkdir(parents=True, exist_ok=True)
        for scene in self.exp.scenes:
            for camera in scene.cameras:
                size = baseline.get((scene.name, camera))
                reference = scene.reference_path(camera, None)
                for mode in ("general", "1d"):
                    output = folder / ("%s_%s_%s.yuv" % (scene.name.split("/")[-1], camera, mode))
                    if not size or reference is None or not output.is_file():
                        continue
                    out = cache / ("%s_%s_%s.json" % (slug(scene.name), camera, mode))
                    if not out.is_file():
                        cmd = [str(self.bin_dir / "YuvPsnr"), str(reference), str(output), "%dx%d" % size,
                               "--metrics", "psnr,ivpsnr,ssim", "--json", str(out) + ".tmp"]
                        done = subprocess.run(cmd, capture_output=True, text=True)
                        if done.returncode != 0:
                            raise ExperimentError("%s failed (exit %d): %s" % (" ".join(cmd), done.returncode,
                                                                               done.stderr.strip()))
                        os.replace(str(out) + ".tmp", out)
                    scores[(scene.name, camera, mode)] = json.loads(out.read_text()).get("mean", {})
        return scores

    def say(self, text):
        if not self.quiet:
            print(text, flush=True)

    # -- one job --
    def command(self, run, start, count, output, summary):
        cmd = [str(self.bin_dir / run.tool), str(run.config_path)]
        cmd += ["%s=%s" % (k, v) for k, v in sorted(run.settings.items())]
        cmd += ["StartFrame=%d" % start, "TotalNumberOfFrames=%d" % count,
                "OutputVirtualViewImageName=%s" % output, "ReferenceVirtualViewImageName=%s" % run.reference,
                "SummaryFile=%s" % summary, "Threads=%d" % self.exp.threads, "QualityMetrics=%s" % QUALITY_METRICS]
        return cmd

    def job_spec(self, run, index, start, count):
        """Everything one job needs, as JSON-able text: the command, its folder, its files. A Slurm array
        task gets exactly this (executors.py), so a job runs the same way under either executor."""
        folder = run.folder(self.exp.work)
        stem = "whole" if index < 0 else ("part%03d" % index if len(run.parts) > 1 else "run")
        output = run.output_path(self.exp.work) if stem == "run" else folder / (stem + ".yuv")
        summary = folder / (stem + ".summary.json")
        return {"tool": run.tool, "cwd": str(run.scene.folder), "folder": str(folder), "output": str(output),
                "summary": str(summary), "log": str(folder / (stem + ".log")), "done": str(folder / (stem + ".done")),
                "count": count, "threads": self.exp.threads,
                "command": self.command(run, start, count, output, summary)}

    def execute(self, run, index, start, count):
        """Runs one part (index >= 0) or the verification run of the whole range (index -1)."""
        spec = self.job_spec(run, index, start, count)
        return finished_job(spec) or execute_job(spec, self.processes, self.lock)

    def join(self, run, infos):
        output = run.output_path(self.exp.work)
        if len(infos) > 1:
            with open(output, "wb") as out:
                for info in infos:
                    with open(info["output"], "rb") as part:
                        shutil.copyfileobj(part, out, 1 << 22)
        return output

    def tidy(self, run):
        """Parts, check runs and done markers go; logs and per-job summaries stay; the joined output stays
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
        for k in METRIC_COLUMNS:
            if len(infos) == 1 and infos[0].get("metrics", {}).get(k):
                row[k] = infos[0]["metrics"][k]
            else:
                m = frame_mean([r.get(k, "") for r in rows])
                row[k] = "%.6f" % float(m) if m not in ("", "inf") else m
        for stage in STAGES:
            row[stage] = "%.6f" % (sum(float(r[stage]) for r in rows) / frames)
        self.append_row(row)
        self.tidy(run)
        return row

    def check_builds(self, names):
        """Timings of a sanitizer build mean nothing: say so now and in the report (work/warnings.txt).
        Also notes which binaries ran (md5, modification time) for the report."""
        for tool in sorted(names):
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
        self.say("%s: %d runs, %d already in %s, %d to run as %d jobs (%s)"
                 % (self.exp.name, len(runs), skipped, self.results_path, len(todo), len(jobs),
                    self.executor.describe(self.jobs)))
        if not jobs:
            return 0, skipped
        self.check_builds({run.tool for run in todo})
        progress = Progress(len(jobs))
        pending = {id(run): {"parts": {}, "whole": None,
                             "left": len(run.parts) + (1 if run.verify and len(run.parts) > 1 else 0)}
                   for run in todo}

        self.pending, self.progress = pending, progress
        try:
            self.executor.run(self, jobs, progress)
        finally:
            progress.close()
        return len(todo), skipped

    @staticmethod
    def job_name(job):
        run, index, start, count = job
        what = "%s %s %s %s" % (run.scene.name, run.camera, run.tool, run.settings_text or "(config)")
        if len(run.parts) > 1 or index < 0:
            what += " [%s]" % ("whole-range check" if index < 0 else "frames %d-%d" % (start, start + count - 1))
        return what

    def job_failed(self, job, error):
        """A job that failed: one progress line, and its run is reported at the end (left for a resume)."""
        self.progress.finished("FAILED %s: %s" % (self.job_name(job), error), failed=True)
        self.failures.append((job[0], str(error)))

    def job_done(self, job, info):
        """A job that finished (here or on a cluster node): once every job of its run is in, the parts
        are joined and the run's row written. Returns the row or None."""
        run, index, start, count = job
        row = None
        with self.lock:
            state = self.pending[id(run)]
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
        what = self.job_name(job)
        if row:
            what += ": Y %s dB, %.3f s/frame" % (row["psnr_y"], float(row["seconds_per_frame"]))
            if row.get("split_check"):
                what += ", split %s" % row["split_check"].split()[0]
        self.progress.finished(what)
        return row


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
