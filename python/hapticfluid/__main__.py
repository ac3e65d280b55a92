# SPDX-License-Identifier: GPL-3.0-or-later
"""``python3 -m hapticfluid ...``: the command line (see :mod:`hapticfluid.cli`)."""

import sys

from hapticfluid.bake import command as _bake_command
from hapticfluid.cli import main

if __name__ == "__main__":
    _bake_command.RUN_AS_PROGRAM = True  # a late Ctrl-C must not kill the bake by the signal
    sys.exit(main())
