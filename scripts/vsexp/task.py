"""One Slurm array task: `python3 -m vsexp.task BATCH.json [INDEX]` runs the jobs at INDEX (default
SLURM_ARRAY_TASK_ID) of a batch file the slurm executor wrote, one after the other, exactly as the local
executor would, and exits with the first failed tool's exit code (1 when a tool wrote no usable
summary), which Slurm records; 0 when every job succeeded."""

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
    code = 0
    for spec in tasks[index]:
        print("task %d of %s on %s: %s" % (index, argv[0], socket.gethostname(), " ".join(spec["command"])),
              flush=True)
        try:
            info = execute_job(spec)
        except JobFailed as e:  # the task's other jobs still run; its exit code is the first failure's
            print(str(e), file=sys.stderr, flush=True)
            code = code or min(255, max(1, e.exit_code))
            continue
        print("done: %d frames, %.2f s" % (len(info["rows"]), info["wall"]), flush=True)
    return code


if __name__ == "__main__":
    sys.exit(main())
