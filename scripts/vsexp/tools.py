"""Talking to the tools. The runner never parses a config file, a camera file or the tools' stdout: it
asks ViewSyn or MeshRender for the effective config and scene (`--print-config`, doc/report.md) and
reads the JSON summary each run writes (`SummaryFile`)."""

import json
import subprocess
import threading
from pathlib import Path

from . import ExperimentError

NOT_SET = "(not set)"  # --print-config's value of a key without a value


class ToolQuery:
    """`--print-config` of the executables in one folder, cached per (tool, config, overrides)."""

    def __init__(self, bin_dir):
        self.bin_dir = Path(bin_dir)
        self._cache = {}
        self._lock = threading.Lock()

    def print_config(self, tool, config, overrides=None):
        """The tool's JSON for `config` with `overrides` ({Key: text}, passed as Key=Value): "config"
        (every key's effective text) and "scene" (sizes, frames, resolved file names, cameras). File names
        come back resolved against the config's folder, so an absolute `config` gives absolute names.
        Raises ExperimentError with the tool's own message (unknown key with its nearest key, bad value,
        missing camera, ...) when it refuses them."""
        overrides = overrides or {}
        key = (tool, str(config), tuple(sorted(overrides.items())))
        with self._lock:
            if key in self._cache:
                return self._cache[key]
        cmd = [str(self.bin_dir / tool), "--print-config", str(config)]
        cmd += ["%s=%s" % kv for kv in sorted(overrides.items())]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True)
        except OSError as e:
            raise ExperimentError("%s: %s" % (cmd[0], e))
        if proc.returncode != 0:
            raise ExperimentError(proc.stderr.strip() or "%s exited with %d" % (" ".join(cmd), proc.returncode))
        try:
            answer = json.loads(proc.stdout)
        except ValueError as e:
            raise ExperimentError("%s: --print-config gave no JSON (%s); is %s current?" % (tool, e, cmd[0]))
        with self._lock:
            self._cache[key] = answer
        return answer

    def config_values(self, tool, config, overrides=None):
        """{Key: effective text} of the keys that have a value."""
        return {k: v for k, v in self.print_config(tool, config, overrides)["config"].items() if v != NOT_SET}

    def camera(self, tool, config, name, overrides=None):
        """K, R (world to camera) and centre of camera `name` of the config's camera file, as the tool reads
        them: asked as the virtual camera of the same config."""
        settings = dict(overrides or {})
        settings["VirtualCameraName"] = name
        return self.print_config(tool, config, settings)["scene"]["virtual_camera"]


def read_summary(path):
    """The JSON summary a run wrote (SummaryFile)."""
    with open(path) as f:
        return json.load(f)


def _text(value, digits):
    """A summary number as the tools' CSV writes it: fixed decimals, "inf", or empty for null."""
    if value is None:
        return ""
    if value == "inf":
        return "inf"
    return "%.*f" % (digits, value)


def frame_rows(summary):
    """The summary's frames as the per-frame rows of the tools' CSV (ReportFile): text with 4 decimals for
    PSNR and 6 for seconds, so that means over them are those of the CSV."""
    rows = []
    for frame in summary.get("frames", []):
        row = {"frame": str(frame["frame"])}
        for key, value in frame.items():
            if key != "frame":
                row[key] = _text(value, 4 if key.startswith("psnr_") else 6)
        rows.append(row)
    return rows


def text_value(value, digits):
    """A summary value as the CSV writes it ("" when absent)."""
    return _text(value, digits) if value is not None else ""


def mean_psnr(summary):
    """(Y, U, V, YUV) frame-mean PSNR texts as the run's last lines print them ("-" where none)."""
    mean = summary.get("mean") or {}
    return tuple(_text(mean.get("psnr_" + c), 4) or "-" for c in ("y", "u", "v", "yuv"))


def tool_version(summary):
    """"ViewSyn 0.1.0": the tool and version that wrote the summary."""
    return "%s %s" % (summary.get("tool", "?"), summary.get("version", "?"))
