"""python3 -m vsexp: the experiment runner's command line (cli.py)."""

import sys

from .cli import main

sys.exit(main())
