"""``python -m simgrasp``: the command line."""

import sys

from simgrasp.cli import main

sys.exit(main())
