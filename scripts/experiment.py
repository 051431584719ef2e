#!/usr/bin/env python3
"""Experiment runner: runs ViewSyn and MeshRender over scenes, cameras and parameter sweeps, in parallel
and resumably, writes one CSV row per run and, with --report, a Markdown report.

    python3 scripts/experiment.py cfg/experiments/middlebury.json -j 2 --report doc/results.md

The code is the package scripts/vsexp (also `cd scripts && python3 -m vsexp ...`); this file stays as
the entry point users know.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from vsexp.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
