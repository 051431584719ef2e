#!/usr/bin/env python3
"""End-to-end test of scripts/experiment.py on generated scenes (CTest: ExperimentRunner).

It renders SceneGen's `tiny` scene (3 frames, 64x48), runs a 2-setting ViewSyn sweep through the runner
twice (one scene group split into 1-frame jobs, one not) plus 1D runs, and checks that:
  - the CSV has exactly the expected rows;
  - each row's PSNR equals what a direct `Bin/ViewSyn` run of the same settings prints (exactly for
    unsplit runs; within 1e-4 dB for split runs, whose mean is taken over the 4-decimal per-frame values);
  - the joined output of a run split into frame ranges is byte-identical to a direct single run;
  - a 1D run with TemporalImprovementOption 1 is not split, and one with 0 is split and verified;
  - resuming runs nothing and leaves the CSV as it was; deleting one row re-runs exactly that run;
  - a misspelt sweep key or a bad value is refused by --list before anything runs;
  - the report, its plot and its crop are written, every figure it names exists, and the chart's points
    (written beside it as work_precision.json) equal the means of results.csv's rows.
Exits 77 (CTest SKIP_RETURN_CODE) when python3-matplotlib or python3-numpy is missing.
"""

import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
SKIP = 77

failures = []


def check(condition, message):
    if condition:
        print("ok:   " + message)
    else:
        print("FAIL: " + message)
        failures.append(message)


def run_runner(experiment, work, extra=()):
    cmd = [sys.executable, str(REPO / "scripts" / "experiment.py"), str(experiment), "-j", "2", "--work", str(work),
           "--bin", str(BIN)] + list(extra)
    # The experiment names its own generated data folder; VS_DATA_DIR, which points the other tests
    # at the real data sets, would take precedence over it (experiment.py: --data, then VS_DATA_DIR,
    # then the file's "data"), so the runner gets an environment without it.
    env = {k: v for k, v in os.environ.items() if k != "VS_DATA_DIR"}
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    print("$ " + " ".join(cmd))
    print(proc.stdout + proc.stderr)
    return proc


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def direct_run(folder, cfg, settings, output, start=None, count=None):
    """Bin/ViewSyn on the config with the settings; returns the mean PSNR (Y, U, V, YUV) of its JSON
    summary, with the 4 decimals the tool prints."""
    cmd = [str(BIN / "ViewSyn"), cfg] + ["%s=%s" % kv for kv in sorted(settings.items())]
    summary = Path(str(output) + ".summary.json")
    cmd += ["OutputVirtualViewImageName=%s" % output, "SummaryFile=%s" % summary, "Threads=1"]
    if start is not None:
        cmd += ["StartFrame=%d" % start, "TotalNumberOfFrames=%d" % count]
    proc = subprocess.run(cmd, cwd=str(folder), capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError("%s failed:\n%s" % (" ".join(cmd), proc.stdout[-2000:] + proc.stderr))
    mean = json.loads(summary.read_text())["mean"]
    return tuple("inf" if mean[k] == "inf" else "%.4f" % mean[k] for k in ("psnr_y", "psnr_u", "psnr_v", "psnr_yuv"))


def make_partly_static(src, dst, width, height, frames):
    """A 3-frame sequence whose lower half stays still while the upper half moves: frame 1 = frame 0's
    lower rows under frame 2's upper rows, frame 2 = frame 1. 1D TemporalImprovementOption keeps the
    hole fill of static rows from the previous frame, which is what makes a split 1D run differ."""
    import numpy as np
    dst.mkdir(parents=True, exist_ok=True)
    frame_bytes = width * height * 3 // 2
    rows, cw = height // 2, width // 2
    for name in ("texture_cam0", "texture_cam1", "texture_cam2", "depth_cam0", "depth_cam1", "depth_cam2"):
        d = np.fromfile(src / (name + ".yuv"), np.uint8).reshape(frames, frame_bytes)
        a, b = d[0].copy(), d[0].copy()
        b[:rows * width] = d[2][:rows * width]
        for off in (width * height, width * height + cw * (height // 2)):
            b[off:off + (rows // 2) * cw] = d[2][off:off + (rows // 2) * cw]
        np.concatenate([a, b, b]).tofile(dst / (name + ".yuv"))
    shutil.copy(src / "cameras.txt", dst / "cameras.txt")
    shutil.copy(src / "viewsyn_cam1.cfg", dst / "viewsyn_cam1.cfg")


def main():
    global BIN
    parser = argparse.ArgumentParser()
    parser.add_argument("--bin", default=str(REPO / "Bin"))
    parser.add_argument("--work", help="work folder (default: a new temporary folder, removed afterwards)")
    args = parser.parse_args()
    BIN = Path(args.bin).resolve()
    try:
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
    except ImportError as e:
        print("SKIP: %s; install the Debian packages python3-matplotlib python3-numpy "
              "(bash scripts/install_deps.sh)" % e)
        return SKIP
    for tool in ("ViewSyn", "SceneGen"):
        if not (BIN / tool).is_file():
            print("FAIL: %s not built in %s" % (tool, BIN))
            return 1
    temporary = args.work is None
    root = Path(args.work or tempfile.mkdtemp(prefix="vs_experiment_test_")).resolve()
    if root.exists() and not temporary:
        shutil.rmtree(root)
    root.mkdir(parents=True, exist_ok=True)
    try:
        return test(root)
    finally:
        if temporary and not failures:
            shutil.rmtree(root, ignore_errors=True)
        elif failures:
            print("files kept in %s" % root)


def test(root):
    # A data folder with the tiny scene and a partly static variant, as path-based scene groups.
    data = root / "data"
    tiny = data / "tiny_split"
    subprocess.run([str(BIN / "SceneGen"), "Scene=tiny", "OutputFolder=%s" % tiny, "Threads=2"], check=True,
                   stdout=subprocess.DEVNULL)
    shutil.copytree(tiny, data / "tiny_whole")
    make_partly_static(tiny, data / "static_half", 64, 48, 3)
    groups = [("split", "tiny_split", 1), ("whole", "tiny_whole", None), ("static", "static_half", 1)]
    sweep = {"Precision": [1, 4]}
    experiment = {
        "name": "test",
        "data": str(data),
        "scenes": [dict({"group": g, "path": p, "cameras": ["cam1"], "config": "viewsyn_{camera}.cfg",
                         "reference": "texture_{camera}.yuv"},
                        **({"frames_per_job": n, "verify_split": True} if n else {})) for g, p, n in groups],
        "methods": [
            {"name": "general", "label": "ViewSyn general", "tool": "ViewSyn", "settings": {"SynthesisMode": 0},
             "sweep": sweep, "groups": ["split", "whole"], "keep_output": True},
            {"name": "oned", "label": "ViewSyn 1D", "tool": "ViewSyn", "groups": ["static"], "keep_output": True,
             "settings": {"SynthesisMode": 1}, "sweep": {"TemporalImprovementOption": [0, 1]}},
        ],
        "tables": [{"title": "tiny", "groups": ["split", "whole"],
                    "rows": [{"label": "general", "method": "general"}]}],
        "plot": {"groups": ["whole"]},
        "crops": [{"scene": "tiny_whole", "camera": "cam1", "methods": ["single"], "size": [32, 24], "zoom": 2}],
    }
    # A single-setting method for the crop; its runs are those of the sweep's Precision=4 (same key).
    experiment["methods"].append({"name": "single", "tool": "ViewSyn", "groups": ["whole"],
                                  "settings": {"SynthesisMode": 0, "Precision": 4}})
    exp_path = root / "test.json"
    exp_path.write_text(json.dumps(experiment, indent=1))
    work = root / "work"
    report = root / "report" / "results.md"

    proc = run_runner(exp_path, work, ["--report", str(report)])
    check(proc.returncode == 0, "the runner succeeds")
    if proc.returncode != 0:
        return 1
    results = work / "results.csv"
    rows = read_csv(results)
    keys = sorted((r["scene"], r["camera"], r["tool"], r["settings"]) for r in rows)
    expected = sorted(
        [(s, "cam1", "ViewSyn", "Precision=%d SynthesisMode=0" % p) for s in ("tiny_split", "tiny_whole")
         for p in (1, 4)] +
        [("static_half", "cam1", "ViewSyn", "SynthesisMode=1 TemporalImprovementOption=%d" % t) for t in (0, 1)])
    check(keys == expected, "the CSV holds the expected %d rows: %s" % (len(expected), keys))

    # Compare every row with a direct single run of ViewSyn.
    for r in rows:
        settings = dict(item.split("=", 1) for item in r["settings"].split())
        scene_folder = data / r["scene"]
        direct = root / ("direct_%s_%s.yuv" % (r["scene"], r["settings"].replace(" ", "_").replace("=", "")))
        printed = direct_run(scene_folder, "viewsyn_cam1.cfg", settings, direct)
        got = (r["psnr_y"], r["psnr_u"], r["psnr_v"], r["psnr_yuv"])
        if int(r["jobs"]) == 1:
            check(got == printed, "%s %s: CSV PSNR %s equals ViewSyn's printed %s" % (r["scene"], r["settings"],
                                                                                   got, printed))
        else:
            close = all(abs(float(a) - float(b)) <= 1.01e-4 for a, b in zip(got, printed))
            check(close, "%s %s (split in %s jobs): CSV PSNR %s within 1e-4 dB of ViewSyn's printed %s"
                  % (r["scene"], r["settings"], r["jobs"], got, printed))
        output = work / r["output"]
        check(output.is_file() and output.read_bytes() == direct.read_bytes(),
              "%s %s: the runner's output (%s job(s)) is byte-identical to one direct run"
              % (r["scene"], r["settings"], r["jobs"]))
    by_key = {(r["scene"], r["settings"]): r for r in rows}
    for p in (1, 4):
        r = by_key[("tiny_split", "Precision=%d SynthesisMode=0" % p)]
        check(r["jobs"] == "3" and r["split_check"].startswith("identical"),
              "tiny_split Precision=%d: split into 3 jobs and verified identical (%s)" % (p, r["split_check"]))
        r = by_key[("tiny_whole", "Precision=%d SynthesisMode=0" % p)]
        check(r["jobs"] == "1" and not r["split"], "tiny_whole Precision=%d: one job" % p)
    r1 = by_key[("static_half", "SynthesisMode=1 TemporalImprovementOption=1")]
    r0 = by_key[("static_half", "SynthesisMode=1 TemporalImprovementOption=0")]
    check(r1["jobs"] == "1" and "TemporalImprovementOption" in r1["split"],
          "1D with TemporalImprovementOption 1 is not split: %s" % r1["split"])
    check(r0["jobs"] == "3" and r0["split_check"].startswith("identical"),
          "1D with TemporalImprovementOption 0 is split and verified identical (%s)" % r0["split_check"])
    # Why the refusal: split such a run by hand and compare (informative; ViewSyn may change).
    static = data / "static_half"
    whole = root / "tio1_whole.yuv"
    direct_run(static, "viewsyn_cam1.cfg", {"SynthesisMode": 1}, whole)
    parts = b""
    for start in range(3):
        part = root / ("tio1_part%d.yuv" % start)
        direct_run(static, "viewsyn_cam1.cfg", {"SynthesisMode": 1}, part, start, 1)
        parts += part.read_bytes()
    print("note: a 1D TemporalImprovementOption 1 run split by hand into 1-frame ranges %s one run on the "
          "partly static sequence" % ("DIFFERS from" if parts != whole.read_bytes() else "equals"))

    check(report.is_file() and (report.parent / "results" / "work_precision.png").is_file()
          and (report.parent / "results" / "crop_tiny_whole_cam1.png").is_file(),
          "the report, its plot and its crop are written")
    text = report.read_text() if report.is_file() else ""
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    check(len(images) >= 2 and all((report.parent / i).is_file() for i in images),
          "every figure the report names exists: %s" % images)
    # The chart's points are the CSV's means: the plot writes what it plotted beside the image.
    plotted = report.parent / "results" / "work_precision.json"
    values = json.loads(plotted.read_text()) if plotted.is_file() else {"pairs": [], "points": []}
    pairs = {tuple(p) for p in values["pairs"]}
    whole_rows = [r for r in rows if r["group"] == "whole"]
    check(pairs == {(r["scene"], r["camera"]) for r in whole_rows},
          "the chart's points are over the plot group's runs: %s" % sorted(pairs))
    settings = sorted({r["settings"] for r in whole_rows})
    check(sorted(p["settings"] for p in values["points"]) == settings,
          "the chart has one point per setting: %s" % settings)
    for point in values["points"]:
        runs = [r for r in whole_rows if r["settings"] == point["settings"] and (r["scene"], r["camera"]) in pairs]
        for key, column in (("psnr_y", "psnr_y"), ("ivpsnr", "ivpsnr"), ("seconds", "cpu_s_per_frame")):
            want = sum(float(r[column]) for r in runs) / len(runs) if runs else None
            check(want is not None and point[key] is not None and abs(point[key] - want) <= 1e-9,
                  "chart point %s: %s %s equals the mean of results.csv's %s (%s)"
                  % (point["settings"], key, point[key], column, want))
    check("| general (Precision=4 SynthesisMode=0) |" in text or "| general (Precision=1 SynthesisMode=0) |" in text,
          "the report's table names the best setting")

    # Resume: nothing runs, the CSV stays as it was.
    before = results.read_bytes()
    proc = run_runner(exp_path, work)
    check(proc.returncode == 0 and "0 to run as 0 jobs" in proc.stdout, "resuming runs nothing")
    check(results.read_bytes() == before, "resuming leaves the CSV unchanged")
    # Delete one row: exactly that run runs again, with the same figures.
    lines = before.decode().splitlines(keepends=True)
    dropped = [l for l in lines[1:] if "static_half" in l and "TemporalImprovementOption=0" in l]
    results.write_text("".join(l for l in lines if l not in dropped))
    proc = run_runner(exp_path, work)
    check(proc.returncode == 0 and "1 to run as 4 jobs" in proc.stdout,
          "a deleted row runs again (1 run: 3 jobs and the whole-range check)")
    again = {(r["scene"], r["settings"]): r for r in read_csv(results)}
    r = again[("static_half", "SynthesisMode=1 TemporalImprovementOption=0")]
    check((r["psnr_y"], r["psnr_u"], r["psnr_v"]) == (r0["psnr_y"], r0["psnr_u"], r0["psnr_v"]),
          "the re-run gives the same PSNR")

    # A misspelt sweep key (and a bad value) stops --list before anything runs, with the tool's hint.
    bad = dict(experiment, methods=[dict(experiment["methods"][0], sweep={"Precison": [1, 4]}),
                                    dict(experiment["methods"][1], settings={"SynthesisMode": 7})]
               + experiment["methods"][2:])
    bad_path = root / "bad.json"
    bad_path.write_text(json.dumps(bad, indent=1))
    bad_work = root / "bad_work"
    proc = run_runner(bad_path, bad_work, ["--list"])
    check(proc.returncode == 1 and "unknown key 'Precison' (did you mean 'Precision'?)" in proc.stderr
          and "SynthesisMode" in proc.stderr and "7" in proc.stderr,
          "--list refuses a misspelt sweep key and a bad value, naming both")
    check(not (bad_work / "runs").exists() and not (bad_work / "results.csv").exists(),
          "nothing ran for the refused experiment")

    print("%d check(s) failed" % len(failures) if failures else "all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
