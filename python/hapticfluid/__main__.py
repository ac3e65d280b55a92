"""``python3 -m hapticfluid ...``: the command line (see :mod:`hapticfluid.cli`)."""

import sys

from hapticfluid.cli import main

if __name__ == "__main__":
    sys.exit(main())
