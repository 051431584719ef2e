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
            report = Report(exp, runs, results, args.report, command, time.monotonic() - began, runner.query)
            report.vsrs_scores = runner.score_vsrs()
            report.write()
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
