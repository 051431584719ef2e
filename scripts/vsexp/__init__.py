"""vsexp: the experiment runner of ViewSyn and MeshRender (python3 -m vsexp, or scripts/experiment.py).

It runs the tools over scenes, cameras and parameter sweeps, in parallel and resumably, writes one CSV
row per run and, with --report, a Markdown report with the comparison table against VSRS 4.2, a
work-precision plot and zoomed crops around depth edges:

    python3 scripts/experiment.py cfg/experiments/middlebury.json -j 2 --report doc/results.md

The experiment file format is described in doc/results.md's appendix and in cfg/experiments/README.md.
The package never parses the tools' stdout or their config files: it asks the tools
(`--print-config`, tools.py) and reads the JSON summary every run writes (`SummaryFile`).

Modules, one job each: experiment (the experiment file), tools (talking to the executables), runner
(runs, jobs, results.csv), executors (where jobs run: local processes or Slurm job arrays), task (one
Slurm array task), report (the Markdown report), plots (the work-precision plot), crops (the zoomed
crops), cli (the command line).
Only the Python standard library is needed to run experiments; the report's plots and crops need the
Debian packages python3-matplotlib and python3-numpy.
"""

from pathlib import Path

REPO = Path(__file__).resolve().parent.parent.parent
TOOLS = ("ViewSyn", "MeshRender")
STAGES = ("read_s", "depth_warp_s", "texture_warp_s", "blend_s", "hole_fill_s", "write_s")
RESULT_FIELDS = ("scene", "group", "camera", "tool", "settings", "config", "frames", "jobs", "split", "split_check",
                 "psnr_y", "psnr_u", "psnr_v", "psnr_yuv", "ivpsnr", "ssim_y", "seconds_per_frame") + STAGES + (
                 "wall_s_per_frame", "cpu_s_per_frame", "output", "finished")
# Metrics besides PSNR every run scores (QualityMetrics; doc/metrics.md) and the summary columns kept.
QUALITY_METRICS = "ivpsnr,ssim"
METRIC_COLUMNS = ("ivpsnr", "ssim_y")
# Keys the runner sets itself on every command line; an experiment may not set them.
RUNNER_KEYS = {"StartFrame", "OutputVirtualViewImageName", "ReferenceVirtualViewImageName", "ReportFile",
               "SummaryFile", "Threads", "QualityMetrics"}


class ExperimentError(Exception):
    """Bad experiment file or command line: every problem found, one a line."""
