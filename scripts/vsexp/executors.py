"""Where jobs run: here (`local`, the default: a pool of -j processes) or on a Slurm cluster (`slurm`: one
job array per invocation, one array task per job). Both run a job the same way (execute_job on the spec
Runner.job_spec makes) and hand its result to the runner, which joins the parts and writes the rows, so the
CSV rows and the outputs do not depend on the executor. Slurm's tasks write into the work folder, which
must therefore be on a file system the nodes share."""

import concurrent.futures
import json
import os
import shlex
import subprocess
import sys
import time
from pathlib import Path

from . import METRIC_COLUMNS, ExperimentError
from . import tools


def finished_job(spec):
    """The info a finished job left (its .done file), or None when it has to run."""
    done, output, summary = Path(spec["done"]), Path(spec["output"]), Path(spec["summary"])
    if done.is_file() and output.is_file() and summary.is_file():
        try:
            return json.loads(done.read_text())
        except ValueError:
            return None
    return None
class JobFailed(RuntimeError):
    """A tool that exited with an error (exit_code), or wrote no usable summary (exit_code 1)."""

    def __init__(self, message, exit_code):
        super().__init__(message)
        self.exit_code = exit_code


def execute_job(spec, processes=None, lock=None):
    """Runs one job (a spec of Runner.job_spec) here: the tool with its log, then its summary is checked
    and the info (seconds, per-frame rows, output) written to its .done file. Raises JobFailed."""
    folder = Path(spec["folder"])
    output, summary_path, log, done = (Path(spec[k]) for k in ("output", "summary", "log", "done"))
    folder.mkdir(parents=True, exist_ok=True)
    for p in (output, summary_path, done):
        if p.exists():
            p.unlink()
    cmd = spec["command"]
    env = dict(os.environ)
    env["LP_NUM_THREADS"] = str(spec["threads"])  # Mesa llvmpipe: as many render threads as Threads
    env["OMP_NUM_THREADS"] = str(spec["threads"])
    # Runs follow one another here, so none starts cold: huge pages make each one-frame run about a
    # quarter cheaper (doc/speed.md, "Cold starts and the pool's wake-ups"; the output is the same).
    env.setdefault("VS_HUGE_PAGES", "1")
    began = time.monotonic()
    with open(log, "w") as f:
        f.write("# cwd %s\n# %s\n" % (spec["cwd"], " ".join(cmd)))
        f.flush()
        proc = subprocess.Popen(cmd, cwd=spec["cwd"], stdout=f, stderr=subprocess.STDOUT, env=env)
        if processes is not None:
            with lock:
                processes.add(proc)
        # wait4: the CPU time of the tool (every thread), which a busy shared machine disturbs far
        # less than the wall clock.
        _, status, usage = os.wait4(proc.pid, 0)
        rc = proc.returncode = os.waitstatus_to_exitcode(status)
        if processes is not None:
            with lock:
                processes.discard(proc)
    wall = time.monotonic() - began
    cpu = usage.ru_utime + usage.ru_stime
    text = log.read_text(errors="replace")
    tool = spec["tool"]
    if rc != 0:
        # The tool's error lines ("ViewSyn: error: ..."), which its unbuffered stderr puts above the
        # buffered stdout in the log; else the log's last lines.
        lines = text.strip().splitlines()
        tail = "\n".join([l for l in lines if ": error:" in l][:6] or lines[-6:])
        raise JobFailed("%s exited with %d (log %s):\n%s" % (tool, rc, log, tail), rc if rc > 0 else 128 - rc)
    try:
        summary = tools.read_summary(summary_path)
    except (OSError, ValueError) as e:
        raise JobFailed("%s wrote no readable summary %s: %s (log %s)" % (tool, summary_path, e, log), 1)
    rows = tools.frame_rows(summary)
    if len(rows) != spec["count"]:
        raise JobFailed("%s wrote %d frames, expected %d (log %s)" % (tool, len(rows), spec["count"], log), 1)
    info = {"wall": wall, "cpu": cpu, "rows": rows, "output": str(output), "printed": tools.mean_psnr(summary),
            "metrics": {k: tools.text_value((summary.get("mean") or {}).get(k), 6) for k in METRIC_COLUMNS},
            "version": tools.tool_version(summary)}
    tmp = done.with_suffix(".done.tmp")
    tmp.write_text(json.dumps(info))
    os.replace(tmp, done)  # whole or not at all: a collector on another host may be reading
    return info


def rerun_command(spec):
    """The shell command that runs one job by hand, as the runner would."""
    return "cd %s && %s" % (shlex.quote(spec["cwd"]), " ".join(shlex.quote(c) for c in spec["command"]))


class LocalExecutor:
    """Today's behaviour: -j jobs at once as processes of this machine."""

    name = "local"

    def describe(self, jobs):
        return "-j %d" % jobs

    def run(self, runner, jobs, progress):
        def work(job):
            if runner.stop.is_set():
                return
            progress.started()
            try:
                info = runner.execute(*job)
            except Exception as e:  # reported, the run is left for a later resume
                if not runner.stop.is_set():  # terminated by us: not a failure of the tool
                    runner.job_failed(job, e)
                return
            runner.job_done(job, info)

        with concurrent.futures.ThreadPoolExecutor(max_workers=runner.jobs) as pool:
            futures = [pool.submit(work, job) for job in jobs]
            try:
                for future in concurrent.futures.as_completed(futures):
                    future.result()
            except KeyboardInterrupt:
                runner.stop.set()
                pool.shutdown(wait=False, cancel_futures=True)
                with runner.lock:
                    for proc in runner.processes:
                        proc.terminate()
                raise


# Slurm job states (squeue) of a task that has not ended yet.
ACTIVE = {"PENDING", "RUNNING", "CONFIGURING", "COMPLETING", "SUSPENDED", "REQUEUED", "REQUEUE_FED", "REQUEUE_HOLD",
          "RESIZING", "SIGNALING", "STAGE_OUT", "RESV_DEL_HOLD", "STOPPED"}
# What the slurm section of an experiment file (or the command line) may set.
SLURM_KEYS = {"partition": "--partition", "time": "--time", "mem": "--mem", "cpus_per_task": "--cpus-per-task",
              "account": "--account", "throttle": None, "options": None, "poll": None, "jobs_per_task": None}


class SlurmError(ExperimentError):
    pass


class SlurmExecutor:
    """One job array per invocation (`sbatch --array=0-N%THROTTLE`), one task per job not yet done (or per
    `jobs_per_task` jobs, run one after the other: Slurm starts about one task per CPU a second); the
    submissions are recorded in WORK/slurm/jobs.jsonl; the tasks' states and exit codes come from
    `squeue -t all` (no slurmdbd needed), polled every `poll` seconds, with the same progress display as
    local runs. mode: "run" (submit, wait, collect), "submit" (submit and return), "collect" (submit
    nothing: wait for the recorded tasks and collect). A task's stdout and stderr are
    WORK/slurm/JOBID_TASK.out and .err."""

    name = "slurm"

    def __init__(self, settings, mode="run"):
        self.settings, self.mode = dict(settings), mode
        self.poll = float(self.settings.get("poll", 2))
        self.submitted = []  # job ids submitted by this invocation

    def describe(self, jobs):
        what = ["slurm"]
        for key in ("partition", "time", "mem", "cpus_per_task", "account", "throttle", "jobs_per_task"):
            if self.settings.get(key) not in (None, ""):
                what.append("%s %s" % (key, self.settings[key]))
        return ", ".join(what)

    # -- talking to Slurm --
    @staticmethod
    def _call(cmd):
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True)
        except OSError as e:
            raise SlurmError("%s: %s (is Slurm installed? scripts/slurm-local.sh start brings up a local one)"
                             % (cmd[0], e))
        if proc.returncode != 0:
            raise SlurmError("%s failed (exit %d): %s" % (" ".join(shlex.quote(c) for c in cmd), proc.returncode,
                                                          proc.stderr.strip()))
        return proc.stdout

    def states(self, job_ids):
        """{(job id, task): (state, exit code text)} of the tasks Slurm still knows (within MinJobAge)."""
        if not job_ids:
            return {}
        for attempt in range(5):  # a busy controller may time out once in a while
            try:
                out = self._call(["squeue", "-h", "-r", "-t", "all", "-O", "JobArrayID:64,State:32,exit_code:16"])
                break
            except SlurmError:
                if attempt == 4:
                    raise
                time.sleep(2)
        wanted = set(job_ids)
        found = {}
        for line in out.splitlines():
            fields = line.split()
            if len(fields) < 2 or "_" not in fields[0]:
                continue
            job, task = fields[0].split("_", 1)
            if job not in wanted or not task.isdigit():
                continue
            status = int(fields[2]) if len(fields) > 2 and fields[2].isdigit() else 0
            code = "%d" % (status >> 8) if not status & 0x7f else "signal %d" % (status & 0x7f)
            found[(job, int(task))] = (fields[1], code)
        return found

    def submit(self, runner, specs):
        """One array job for `specs` (jobs_per_task of them a task); returns its id and the tasks' lists of
        specs (recorded in WORK/slurm/jobs.jsonl)."""
        per = max(1, int(self.settings.get("jobs_per_task") or 1))
        tasks = [specs[i:i + per] for i in range(0, len(specs), per)]
        folder = runner.exp.work / "slurm"
        folder.mkdir(parents=True, exist_ok=True)
        number = len(list(folder.glob("batch-*.json")))
        batch = folder / ("batch-%04d.json" % number)
        while batch.exists():
            number += 1
            batch = folder / ("batch-%04d.json" % number)
        batch.write_text(json.dumps({"tasks": tasks}, indent=1))
        script = batch.with_suffix(".sh")
        package = Path(__file__).resolve().parent.parent
        script.write_text("#!/bin/sh\n# One task of an experiment's job array: the jobs BATCH.json lists at "
                          "SLURM_ARRAY_TASK_ID.\nexport PYTHONPATH=%s${PYTHONPATH:+:$PYTHONPATH}\nexec %s -m vsexp.task %s\n"
                          % (shlex.quote(str(package)), shlex.quote(sys.executable), shlex.quote(str(batch))))
        array = "0-%d" % (len(tasks) - 1)
        if self.settings.get("throttle"):
            array += "%%%d" % int(self.settings["throttle"])
        cmd = ["sbatch", "--parsable", "--job-name=vsexp-" + runner.exp.name, "--array=" + array,
               "--output=%s/%%A_%%a.out" % folder, "--error=%s/%%A_%%a.err" % folder]
        settings = dict(self.settings)
        settings.setdefault("cpus_per_task", runner.exp.threads)
        for key, flag in SLURM_KEYS.items():
            if flag and settings.get(key) not in (None, ""):
                cmd.append("%s=%s" % (flag, settings[key]))
        cmd += list(settings.get("options") or [])
        cmd.append(str(script))
        job_id = self._call(cmd).strip().split(";")[0]
        if not job_id.isdigit():
            raise SlurmError("sbatch gave no job id: %r" % job_id)
        with open(folder / "jobs.jsonl", "a") as f:
            f.write(json.dumps({"job_id": job_id, "batch": str(batch), "tasks": [[s["done"] for s in t] for t in tasks],
                                "sbatch": cmd, "submitted": time.time()}) + "\n")
        self.submitted.append(job_id)
        return job_id, tasks

    @staticmethod
    def recorded(work):
        """Every recorded submission, oldest first."""
        path = work / "slurm" / "jobs.jsonl"
        if not path.is_file():
            return []
        return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]

    # -- the executor --
    def run(self, runner, jobs, progress):
        work = runner.exp.work
        specs = {}
        waiting = []
        for job in jobs:
            spec = runner.job_spec(*job)
            specs[spec["done"]] = (job, spec)
            info = finished_job(spec)
            if info:  # a task finished while nobody was collecting
                progress.started()
                runner.job_done(job, info)
            else:
                waiting.append(spec["done"])
        # The latest submission of each job, and whether it is still queued or running.
        latest = {}
        for record in self.recorded(work):
            for task, dones in enumerate(record["tasks"]):
                for done in dones if isinstance(dones, list) else [dones]:
                    latest[done] = (record["job_id"], task, record.get("submitted", 0))
        known = self.states({latest[d][0] for d in waiting if d in latest})
        live = {d for d in waiting if d in latest and known.get(latest[d][:2], ("",))[0] in ACTIVE}
        fresh = [d for d in waiting if d not in live]
        if self.mode == "collect":
            for done in fresh:
                job, spec = specs[done]
                progress.started()
                if done in latest:
                    runner.job_failed(job, self.failure(work, spec, latest[done][:2], known.get(latest[done][:2]),
                                                        collect=True))
                else:
                    runner.job_failed(job, "never submitted to Slurm: run without --collect to submit it")
            fresh = []
        if fresh:
            job_id, tasks = self.submit(runner, [specs[d][1] for d in fresh])
            now = time.time()
            for task, task_specs in enumerate(tasks):
                for spec in task_specs:
                    latest[spec["done"]] = (job_id, task, now)
            runner.say("submitted job array %s: %d tasks for %d jobs (%s); ids in %s" % (
                job_id, len(tasks), len(fresh), self.describe(runner.jobs), work / "slurm" / "jobs.jsonl"))
        if self.mode == "submit":
            return
        self.wait(runner, progress, {d: specs[d] for d in live | set(fresh)}, latest)

    def wait(self, runner, progress, tracked, latest):
        work = runner.exp.work
        started = set()
        while tracked:
            known = self.states({latest[d][0] for d in tracked})
            for done in list(tracked):
                job, spec = tracked[done]
                key = latest[done][:2]
                state = known.get(key)
                if state and state[0] in ACTIVE:
                    if state[0] != "PENDING" and done not in started:
                        started.add(done)
                        progress.started()
                    info = finished_job(spec) if state[0] != "PENDING" else None
                    if info:  # one of the jobs of a task that goes on
                        del tracked[done]
                        runner.job_done(job, info)
                    continue
                if state is None and time.time() - latest[done][2] < 30:
                    continue  # just submitted: not listed yet
                if done not in started:
                    started.add(done)
                    progress.started()
                del tracked[done]
                info = finished_job(spec)
                if info:  # written whole after the tool's summary was checked: this job succeeded
                    runner.job_done(job, info)
                else:
                    runner.job_failed(job, self.failure(work, spec, key, state))
            if tracked:
                time.sleep(self.poll)

    @staticmethod
    def failure(work, spec, key, state, collect=False):
        """What a failed task tells the user: Slurm's state and exit code, the end of its .err, the files,
        and how to run it again."""
        task = "%s_%d" % key
        err = work / "slurm" / (task + ".err")
        if state is None:
            what = "Slurm task %s ended without a result and Slurm no longer lists it" % task
        else:
            what = "Slurm task %s %s, exit code %s" % (task, state[0], state[1])
        lines = [what]
        try:  # the tool's own error lines from the job's log, else the end of the task's .err
            tail = [l for l in Path(spec["log"]).read_text(errors="replace").splitlines() if ": error:" in l][:6]
        except OSError:
            tail = []
        if not tail:
            try:
                tail = err.read_text(errors="replace").strip().splitlines()[-8:]
            except OSError:
                tail = []
        lines += ["  " + t for t in tail]
        lines.append("  .err: %s" % err)
        lines.append("  log: %s" % spec["log"])
        lines.append("  rerun by hand: %s" % rerun_command(spec))
        lines.append("  or run the experiment again%s: failed tasks are resubmitted, done ones kept"
                     % (" without --collect" if collect else ""))
        return "\n".join(lines)
