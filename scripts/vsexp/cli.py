"""The command line: python3 -m vsexp FILE.json [-j N] [--report PATH.md] ... (or scripts/experiment.py)."""

import argparse
import datetime
import json
import os
import signal
import sys
import time
from pathlib import Path

from . import REPO, ExperimentError
from .experiment import Experiment
from .report import Report, _load
from .runner import Runner, check_settings, plan_runs, read_results
from .executors import LocalExecutor, SlurmExecutor



def make_executor(exp, args):
    """The executor the command line asks for, else the experiment file's (`executor`, `slurm`)."""
    name = args.executor or exp.executor
    slurm_only = [o for o, v in (("--submit-only", args.submit_only), ("--collect", args.collect)) if v]
    if name != "slurm":
        if slurm_only:
            raise ExperimentError("%s needs the slurm executor (--executor slurm)" % slurm_only[0])
        return LocalExecutor()
    settings = dict(exp.slurm)
    for key in ("partition", "time", "mem", "cpus_per_task", "account", "throttle", "poll", "jobs_per_task"):
        value = getattr(args, key)
        if value is not None:
            settings[key] = value
    if args.sbatch_option:
        settings["options"] = list(settings.get("options") or []) + args.sbatch_option
    for key in ("throttle", "jobs_per_task"):
        if settings.get(key) is not None and int(settings[key]) < 1:
            raise ExperimentError("%s must be at least 1" % key)
    return SlurmExecutor(settings, "submit" if args.submit_only else "collect" if args.collect else "run")


def main(argv=None):
    parser = argparse.ArgumentParser(description=sys.modules[__package__].__doc__.split("\n\n")[0],
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
    cluster = parser.add_argument_group("executors", "where the jobs run: here (local, the default) or as Slurm "
                                        "job arrays (slurm); the slurm options override the file's \"slurm\" "
                                        "object. The work folder must be shared with the nodes")
    cluster.add_argument("--executor", choices=("local", "slurm"), help="local (default) or slurm (default: the "
                         "file's \"executor\")")
    cluster.add_argument("--partition", help="sbatch --partition")
    cluster.add_argument("--time", help="sbatch --time per task (e.g. 0:10:00)")
    cluster.add_argument("--mem", help="sbatch --mem per task (e.g. 2G)")
    cluster.add_argument("--cpus-per-task", type=int, help="sbatch --cpus-per-task (default: the file's threads)")
    cluster.add_argument("--account", help="sbatch --account")
    cluster.add_argument("--throttle", type=int, help="tasks of the array at once (--array=0-N%%THROTTLE)")
    cluster.add_argument("--sbatch-option", action="append", default=[], metavar="OPTION",
                         help="one more sbatch option, e.g. --sbatch-option=--qos=long (repeatable)")
    cluster.add_argument("--jobs-per-task", type=int, help="jobs one array task runs one after the other "
                         "(default 1; Slurm starts about one task per CPU a second, so pack short jobs)")
    cluster.add_argument("--poll", type=float, help="seconds between squeue polls while waiting (default 2)")
    mode = cluster.add_mutually_exclusive_group()
    mode.add_argument("--submit-only", action="store_true", help="slurm: submit the jobs not done and return")
    mode.add_argument("--collect", action="store_true", help="slurm: submit nothing; wait for the submitted "
                      "tasks, collect their results, report the failed ones")
    args = parser.parse_args(argv)
    began = time.monotonic()

    load_start = _load()

    def terminate(signum, frame):
        raise KeyboardInterrupt()
    signal.signal(signal.SIGTERM, terminate)
    executor = None  # stop the tools and keep what finished, as for Ctrl-C
    try:
        if args.jobs < 1:
            raise ExperimentError("-j must be at least 1")
        exp = Experiment(args.experiment, args.data, args.work)
        executor = make_executor(exp, args)
        runner = Runner(exp, args.bin, args.jobs, args.quiet, executor)
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
        # Every setting goes to its tool once now, so that a misspelt key or a bad value stops the
        # experiment before anything runs (SceneGen included); settings of generated scenes only are
        # checked once SceneGen has written their configs (plan_runs).
        check_settings(exp, runner.query)
        if not args.no_run:
            runner.generate_scenes()  # also for --list: the runs of a generated scene come from its configs
        elif any(s.scenegen and not (s.folder / ".scenegen-done").is_file() for s in exp.scenes):
            raise ExperimentError("SceneGen scenes are not generated yet in %s: run without --no-run"
                                  % exp.work)
        runs = plan_runs(exp, runner.query)
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
            if getattr(executor, "mode", "run") == "submit":
                runner.say("submitted %s; collect with: %s --collect" % (
                    ", ".join(executor.submitted) or "nothing (every job is done or queued)",
                    " ".join(["python3", os.path.relpath(REPO / "scripts" / "experiment.py")] +
                             [a for a in (argv if argv is not None else sys.argv[1:]) if a != "--submit-only"])))
                return 0
            runner.say("ran %d runs, skipped %d already done, %.1f s" % (ran, skipped, elapsed))
            if ran:
                # The report's run time: every invocation that ran something, one JSON object a line.
                with open(exp.work / "invocations.jsonl", "a") as f:
                    f.write(json.dumps({
                        "seconds": round(elapsed, 1), "runs": ran, "skipped": skipped, "jobs": args.jobs,
                        "executor": executor.describe(args.jobs),
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
            report = Report(exp, runs, results, args.report, command, time.monotonic() - began, runner.query)
            report.vsrs_scores = runner.score_vsrs()
            report.write()
            runner.say("report: %s" % args.report)
        return 1 if runner.failures else 0
    except ExperimentError as e:
        print("error: %s" % e, file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        if executor is not None and executor.name == "slurm":
            print("\ninterrupted: finished runs are kept; the Slurm tasks keep running (ids in WORK/slurm/jobs.jsonl):"
                  " run the same command with --collect to wait for them and collect, or without it to also "
                  "resubmit failed ones", file=sys.stderr)
        else:
            print("\ninterrupted: finished runs are kept; run the same command again to resume", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
