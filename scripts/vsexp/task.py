"""One Slurm array task: `python3 -m vsexp.task BATCH.json [INDEX]` runs the job at INDEX (default
SLURM_ARRAY_TASK_ID) of a batch file the slurm executor wrote, exactly as the local executor would, and
exits with the tool's exit code (1 when the tool wrote no usable summary), which Slurm records."""

import json
import os
import socket
import sys

from .executors import JobFailed, execute_job


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if not argv:
        print(__doc__, file=sys.stderr)
        return 2
    with open(argv[0]) as f:
        tasks = json.load(f)["tasks"]
    index = int(argv[1] if len(argv) > 1 else os.environ["SLURM_ARRAY_TASK_ID"])
    spec = tasks[index]
    print("task %d of %s on %s: %s" % (index, argv[0], socket.gethostname(), " ".join(spec["command"])), flush=True)
    try:
        info = execute_job(spec)
    except JobFailed as e:
        print(str(e), file=sys.stderr)
        return min(255, max(1, e.exit_code))
    print("done: %d frames, %.2f s" % (len(info["rows"]), info["wall"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
