import sys

from simgrasp.cli import main

sys.exit(main())
